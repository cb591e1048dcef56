// Coulomb friction (5.4 with bounds ±mu lambda_n): the rows point to their contact row, and the
// fixed point of boxed problems keeps the cone and slows a sliding box by mu g.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "cbps/solvers/solver.hpp"
#include "cbps/step/simulation.hpp"
#include "cbps/system/system.hpp"
#include "fixture.hpp"

using namespace cbps;
using test::contact_scene;
using test::kG;

TEST_CASE(
    "Coulomb friction rows point to their contact row, the direct solve keeps |lambda_t| "
    "<= mu lambda_n and slows a sliding box by mu g (5.4)",
    "[contact][eq5.4][eq6.2]") {
  // The slide scene at step 0: a 1 kg box at v0 = 2 m/s along x on the ground, mu = 0.3.
  const double mu = 0.3;
  const double v0 = 2.0;
  Simulation sim(contact_scene("slide", {{"friction", "coulomb"}}, "direct"));
  const System sys = sim.build_system();
  REQUIRE(sys.rows() == 12);
  for (int k = 0; k < sys.rows(); ++k) {
    CAPTURE(k, sys.labels[std::size_t(k)]);
    const int n = sys.normal_row[std::size_t(k)];
    if (k % 3 == 0) {
      CHECK(n == -1);  // a contact row
      continue;
    }
    REQUIRE(n == k - k % 3);  // the contact row of the same point, just before its tangents
    CHECK(sys.labels[std::size_t(n)].rfind("contact ", 0) == 0);
    // "friction ground-box #f t1" belongs to "contact ground-box #f".
    const std::string& label = sys.labels[std::size_t(k)];
    CHECK(label.substr(9, label.size() - 12) == sys.labels[std::size_t(n)].substr(8));
    CHECK(sys.mu(k) == mu);
  }
  VecX lambda = VecX::Zero(sys.rows());
  const SolverSummary s = sim.solve_system(sys, lambda);
  INFO(s.message);
  CHECK(s.termination == Termination::Direct);
  // The bounds ±mu lambda_n are iterated to a fixed point, so the cone holds up to the last
  // bound change: 1e-9 N, 1e-10 of the weight, allows for it.
  const double cone_slack = 1e-9;
  double normal_total = 0.0;
  for (int k = 0; k < sys.rows(); k += 3) {
    normal_total += lambda(k);
    for (int t = k + 1; t <= k + 2; ++t) {
      CAPTURE(t);
      CHECK(std::abs(lambda(t)) <= mu * lambda(k) + cone_slack);
    }
  }
  // The box neither rises nor sinks: the normal forces carry the weight, Σλ_n = m g (v2_y = 0).
  CHECK(normal_total == Approx(1.0 * kG).epsilon(1e-9));
  // It slides: kinetic friction μ Σλ_n = μ m g decelerates it, v2_x = v0 − μ g dt, and it does
  // not tip (μ = 0.3 < half width / half height = 1), so ω2 = 0.
  const VecX v2 = compute_v2(sys.v1, sys.Minv, sys.J, lambda, sys.fext, sys.dt);
  CHECK(v2(0) == Approx(v0 - mu * kG * sys.dt).epsilon(1e-9));
  CHECK(std::abs(v2(1)) < 1e-9);
  CHECK(v2.tail<3>().norm() < 1e-9);
}
