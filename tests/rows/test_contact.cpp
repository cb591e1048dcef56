// Contact rows (5.3) and restitution (8.2.1) on the built-in contact scenes. Every expected value
// is worked out in the comment beside it from a force balance or from kinematics, or comes from
// another solver; none is a number printed by the code under test.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "cbps/rows/contact.hpp"
#include "cbps/rows/row.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/step/simulation.hpp"
#include "cbps/system/system.hpp"
#include "fixture.hpp"

using namespace cbps;
using test::contact_scene;
using test::kG;

namespace {

/// The solver settings of the scene with another method (e.g. the direct path, 6.2).
SolverSettings with_method(const Scene& scene, const std::string& method) {
  SolverSettings s = scene.solver;
  s.method = method_of(method);
  return s;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// 12.2: the sphere in the V. Normals a = (sin φ_l, cos φ_l, 0) and b = (−sin φ_r, cos φ_r, 0)
// point from each static plane (body a of the manifold) to the ball (body b). At rest
// a λ₁ + b λ₂ = m g ŷ: the x row gives λ₁ sin φ_l = λ₂ sin φ_r, the y row
// λ₁ cos φ_l + λ₂ cos φ_r = m g, so λ₁ = m g sin φ_r / sin(φ_l + φ_r), λ₂ = m g sin φ_l /
// sin(φ_l + φ_r); for φ_l = φ_r = 45° both are m g / (2 cos 45°). A = J M⁻¹ Jᵀ is 2×2 and
// positive definite (a and b are independent), so λ is unique and any exact solver must give it.

TEST_CASE(
    "v-corner: the contact forces balance the weight, lambda = m g sin(phi)/sin(phi_l + "
    "phi_r) (12.2, 5.3)",
    "[contact][eq12.2][eq12.2.1][eq12.2.2][eq5.3]") {
  const auto [left_deg, right_deg] =
      GENERATE(std::pair{45.0, 30.0}, std::pair{45.0, 45.0}, std::pair{30.0, 60.0});
  CAPTURE(left_deg, right_deg);
  const double m = 1.0;  // the scene's default ball mass, kg
  const double phi_l = left_deg * kPi / 180.0;
  const double phi_r = right_deg * kPi / 180.0;
  const Vec3 a(std::sin(phi_l), std::cos(phi_l), 0.0);
  const Vec3 b(-std::sin(phi_r), std::cos(phi_r), 0.0);
  const double lambda1 = m * kG * std::sin(phi_r) / std::sin(phi_l + phi_r);
  const double lambda2 = m * kG * std::sin(phi_l) / std::sin(phi_l + phi_r);
  if (left_deg == right_deg) {
    CHECK(lambda1 == Approx(m * kG / (2.0 * std::cos(kPi / 4.0))).epsilon(1e-14));
  }
  const std::map<std::string, std::string> values = {
      {"angle_left_deg", std::to_string(left_deg)}, {"angle_right_deg", std::to_string(right_deg)}};

  SECTION("J's rows are [n^T, (r x n)^T] in the ball's columns only (12.2.1, 5.3)") {
    Simulation sim(contact_scene("v-corner", values, "direct"));
    const System sys = sim.build_system();
    REQUIRE(sys.rows() == 2);
    CHECK(sys.blocks() == 1);  // the two planes are static: no columns (5.3)
    CHECK(sys.J.cols() == 6);
    const MatX J = MatX(sys.J);
    // The contact point lies on the line through the centre along n, so r_b ∥ n and
    // r_b × n = 0: the sphere's rows have no angular part (12.2: "no rotation").
    Eigen::Matrix<double, 2, 6> expected;
    expected << a.transpose(), 0, 0, 0, b.transpose(), 0, 0, 0;
    INFO("J =\n" << J);
    CHECK((J - expected).lpNorm<Eigen::Infinity>() < 1e-15);  // a few roundings of unit values
    // (12.2.2): Jᵀ λ = a λ₁ + b λ₂, and at the force balance it is the weight m g ŷ.
    const VecX lambda = Eigen::Vector2d(lambda1, lambda2);
    const VecX f = sys.J.transpose() * lambda;
    CHECK((f.head<3>() - m * kG * Vec3::UnitY()).norm() < 1e-13 * m * kG);
  }

  SECTION("the direct path at step 0 and after 60 steps, PGS to its tolerance (6.2, 7.1.1)") {
    // The ball starts touching both planes (depth 0) at rest, so the first system already has
    // the static answer. Direct: exact up to rounding, 1e-9 relative leaves ~10⁶ u of room.
    Simulation sim(contact_scene("v-corner", values, "direct"));
    const System sys = sim.build_system();
    REQUIRE(sys.rows() == 2);
    VecX lambda = VecX::Zero(2);
    const SolverSummary direct = sim.solve_system(sys, lambda);
    INFO(direct.message);
    CHECK(direct.termination == Termination::Direct);
    CHECK(lambda(0) == Approx(lambda1).epsilon(1e-9));
    CHECK(lambda(1) == Approx(lambda2).epsilon(1e-9));
    // PGS stops at natural-map residual 1e-10 (the scene's tolerance); with A⁻¹'s norm at most
    // m / (1 − |cos(φ_l + φ_r)|) ≤ 1.4 kg here, λ is within ~1e-10 N: 1e-8 relative is loose.
    VecX lambda_pgs = VecX::Zero(2);
    const SolverSummary pgs =
        sim.solve_system(sys, sys.b, lambda_pgs, with_method(sim.scene(), "pgs"));
    INFO(pgs.message);
    CHECK(pgs.termination == Termination::ResidualTolerance);
    CHECK(lambda_pgs(0) == Approx(lambda1).epsilon(1e-8));
    CHECK(lambda_pgs(1) == Approx(lambda2).epsilon(1e-8));

    // 60 steps of 1/60 s (1 s): the ball must stay where it is, with the same forces. Both
    // runs get a 1 mm contact margin (the scene's default, made explicit): PGS's 1e-10 N error
    // separates the ball by ~1e-14 m, which at margin 0 loses a contact for a step (measured:
    // the ball then sinks 1.45 mm and λ₂ jumps to 13.96 N).
    for (const std::string method : {"direct", "pgs"}) {
      CAPTURE(method);
      std::map<std::string, std::string> run_values = values;
      run_values["margin"] = "0.001";
      Simulation run(contact_scene("v-corner", run_values, method));
      const Vec3 x0 = run.bodies()[2].x;
      VecX last;
      int rows = 0;
      run.set_observer([&](const System& s, const VecX& l, const VecX&) {
        rows = s.rows();
        last = l;
      });
      double max_penetration = 0.0;
      for (int s = 0; s < 60; ++s)
        max_penetration = std::max(max_penetration, run.step().max_penetration);
      REQUIRE(rows == 2);
      const double rel = method == "direct" ? 1e-9 : 1e-8;
      CHECK(last(0) == Approx(lambda1).epsilon(rel));
      CHECK(last(1) == Approx(lambda2).epsilon(rel));
      CHECK(max_penetration < 1e-9);
      CHECK((run.bodies()[2].x - x0).norm() < 1e-9);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// 8.2: restitution.

TEST_CASE("restitution: upsilon = -eps j_c v1 above the threshold, none below (8.2.1, 5.3)",
          "[contact][eq8.2.1][eq5.3]") {
  const double beta = 0.2;
  const double dt = 1.0 / 60.0;
  const double eps = 0.5;
  const double threshold = 0.1;
  // The bias of a system with the push (5.3; the position system of 8.1) or without it (the
  // velocity system of 8.1).
  const auto bias = [&](double depth, double approach, bool push) {
    const double upsilon = contact_bias(depth, approach, dt, eps, threshold);
    return push ? with_push(upsilon, contact_push(depth, beta, dt)) : upsilon;
  };
  // Approaching at 2 m/s (j_c v1 = −2): the row asks to separate at ε · 2 = +1 m/s.
  CHECK(bias(0.0, -2.0, false) == 1.0);
  CHECK(bias(0.0, -2.0, true) == 1.0);  // d = 0: no push
  // With a depth of 1 cm the push β d / dt = 0.2 · 0.01 · 60 = 0.12 m/s adds to it (5.3)...
  CHECK(bias(0.01, -2.0, true) == Approx(1.12).epsilon(1e-14));
  // ...but not in the velocity system of the improved push (8.1).
  CHECK(bias(0.01, -2.0, false) == 1.0);
  // Below the threshold (a resting contact) and for separating bodies: no bounce.
  CHECK(bias(0.0, -0.05, false) == 0.0);
  CHECK(bias(0.0, 2.0, false) == 0.0);
  CHECK(bias(0.01, -0.05, true) == Approx(0.12).epsilon(1e-14));
  // A gap of 1 mm (a margin point, d = −0.001): closing at 2 m/s covers 3.3 cm in the step, so
  // the impact is now and the target is the rebound alone, ε · 2 = 1 m/s (adding d / dt =
  // −0.06 m/s would take 6 % off it). At 0.05 m/s the gap stays open: d / dt, a bound on the
  // approach, and no rebound.
  CHECK(bias(-0.001, -2.0, true) == 1.0);
  CHECK(bias(-0.001, -2.0, false) == 1.0);
  CHECK(bias(-0.001, -0.05, true) == Approx(-0.06).epsilon(1e-14));
  // Fast (0.5 m/s, above the threshold) but not fast enough to close 1 cm in 1/60 s (0.6 m/s).
  CHECK(bias(-0.01, -0.5, true) == Approx(-0.6).epsilon(1e-14));
}

TEST_CASE("bounce: each rebound apex is eps^2 times the one before (8.2.1, 8.1)",
          "[contact][eq8.2.1][eq8.1]") {
  // A ball dropped from h0 = 1 m with ε = 0.8 (the scene's defaults, dt 1/240, improved push)
  // leaves the ground at ε times its impact speed, so apex heights go as ε² = 0.64.
  // Tolerance 5 %: the impact is seen up to one step late, so the speed read is off by up to
  // g dt = 0.04 m/s of ≥ 2.8 m/s (h ≥ 0.41 m) and the ball is up to v dt ≈ 1.2 cm deep; the
  // height (∝ v²) is then off by up to 2 g dt / v + v dt / h ≈ 3 % + 3 % per bounce.
  const double eps = 0.8;
  const double h0 = 1.0;
  const double r = 0.1;
  Simulation sim(contact_scene("bounce", {}));
  REQUIRE(sim.scene().world.restitution == eps);
  std::vector<double> apex;  // heights of the ball's lowest point at each local maximum of y
  double y_prev2 = sim.bodies()[1].x.y();
  double y_prev = y_prev2;
  for (int s = 0; s < 500 && apex.size() < 3; ++s) {  // apexes near 0.8, 1.47, 1.99 s
    sim.step();
    const double y = sim.bodies()[1].x.y();
    if (y_prev > y_prev2 && y_prev >= y) apex.push_back(y_prev - r);
    y_prev2 = y_prev;
    y_prev = y;
  }
  INFO("apex heights " << (apex.size() > 0 ? apex[0] : 0) << ", " << (apex.size() > 1 ? apex[1] : 0)
                       << ", " << (apex.size() > 2 ? apex[2] : 0) << " m");
  REQUIRE(apex.size() == 3);
  CHECK(apex[0] / h0 == Approx(eps * eps).epsilon(0.05));
  CHECK(apex[1] / apex[0] == Approx(eps * eps).epsilon(0.05));
  CHECK(apex[2] / apex[1] == Approx(eps * eps).epsilon(0.05));
}
