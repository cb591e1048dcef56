// A peer in `cbps profile` (studies/profile.hpp, issue 50 item 15): it reports only its final
// point, so an iterative peer runs once per tolerance, told that tolerance, and its cost at a
// loose tolerance is that run's. Before, one run to the finest tolerance counted its whole
// budget at every tolerance (the same sweeps at 1e-4 as at 1e-10).
#include <catch2/catch.hpp>
#include <random>

#include "cbps/solvers/peers/peers.hpp"
#include "cbps/studies/profile.hpp"
#include "cbps/studies/solver_spec.hpp"

using namespace cbps;

TEST_CASE("an iterative peer's sweeps in a profile are its own at each tolerance",
          "[profile][peers]") {
  if (!peer_available(Method::SiconosPgs)) {
    WARN("this build has no Siconos numerics: not tested");
    return;
  }
  // An LCP (every row [0, inf)) of 80 rows, A = B B^T + I / 4: definite, PGS converges linearly,
  // so 1e-10 takes several times the sweeps of 1e-4.
  const int c = 80;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  MatX B(c, c);
  for (int i = 0; i < c; ++i)
    for (int j = 0; j < c; ++j) B(i, j) = u(rng) / std::sqrt(static_cast<double>(c));
  ProfileProblem p;
  p.stored.A = (B * B.transpose() + 0.25 * MatX::Identity(c, c)).sparseView();
  p.stored.b.resize(c);
  for (int k = 0; k < c; ++k) p.stored.b(k) = u(rng);
  p.stored.cmin = VecX::Zero(c);
  p.stored.cmax = VecX::Constant(c, kInf);
  p.scale = scale_of(p.problem());
  p.exact = VecX::Zero(c);
  const ProfileLimits limits{100000, 30.0};
  const ProfileMeasurement m = profile_peer(p, parse_solver_spec("siconos:pgs"), limits);
  INFO(m.status << ", residual " << m.residual << ", sweeps " << m.reached[0].iterations << " / "
                << m.reached[1].iterations << " / " << m.reached[2].iterations);
  CHECK(m.final_point_only);
  // Siconos' PGS stops by its own error measure, so told 1e-10 it may stop just short of cbps's
  // unit-free 1e-10; 1e-4 and 1e-8 it reaches, each in its own run.
  REQUIRE(m.reached[0].iterations >= 1);
  REQUIRE(m.reached[1].iterations >= 1);
  CHECK(m.reached[0].iterations < m.reached[1].iterations);
  if (m.reached[2].iterations >= 0) CHECK(m.reached[1].iterations < m.reached[2].iterations);
  // A pivoting peer runs once: one cost at every tolerance its answer meets.
  const ProfileMeasurement lemke = profile_peer(p, parse_solver_spec("siconos:lemke"), limits);
  INFO(lemke.status);
  REQUIRE(lemke.status == "solved");
  for (const ProfileReached& r : lemke.reached) CHECK(r.iterations == 1);
  CHECK(lemke.reached[0].time_s == lemke.reached[2].time_s);
}
