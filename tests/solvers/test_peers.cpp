// The peers (solvers/peers/peers.hpp): Siconos numerics and Bullet on cbps's boxed problem, the
// first checks of cbps against code it did not write. Each peer's answer is judged by cbps's
// natural-map residual; where a peer solves, cbps's direct path agrees with it to a bound that
// follows from both residuals (check_agreement below); on the vendored Siconos problems, read by
// cbps's reader, Siconos' Lemke and cbps's Lemke reach the same verdicts.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "cbps/base/error.hpp"
#include "cbps/io/stored_problem.hpp"
#include "cbps/solvers/exact/lemke.hpp"
#include "cbps/solvers/peers/peers.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/system/boxed_problem.hpp"
#include "cbps/system/system.hpp"
#include "cbps/system/unit_free.hpp"
#include "fixture.hpp"

using namespace cbps;
using test::system_of;

namespace {

/// Skips a test (returns true) when this build lacks the peer's library; CI builds with both.
bool missing(Method method) {
  if (peer_available(method)) return false;
  WARN(std::string(to_string(method)) + ": not in this build (scripts/setup.sh installs it)");
  return true;
}

/// Two approximate answers x1, x2 of the box-constrained problem with F(x) = A x − b, A
/// symmetric positive semidefinite. With r_i their natural-map residual vectors, y_i = x_i − r_i
/// is the projection of x_i − F(x_i) on the box, so <F(x_i) − r_i, y − y_i> ≥ 0 for every y in
/// the box. Taking y = y_2 in the first and y = y_1 in the second and adding, with d = x1 − x2,
/// e = r1 − r2: <A d, d − e> ≤ <e, d − e>, hence
///     dᵀ A d ≤ <A d + d, e> ≤ |A d + d|₂ |e|₂ ≤ |A d + d|₂ √c (ρ1 + ρ2),
/// ρ_i = |r_i|∞ the residual each solve reported. dᵀ A d = |Minv^½ Jᵀ d|² when A = J Minv Jᵀ:
/// the bound holds Jᵀλ (and w = A λ − b, |A d|² ≤ λ_max(A) dᵀ A d) together where λ itself is not
/// unique. The first inequality holds for any two points (the projection is firmly
/// nonexpansive); the last ties the agreement to the residuals the solves reported, so a peer's
/// answer that is not what its reported residual says, or a residual cbps measures wrongly, fails.
void check_agreement(
    const BoxedProblem& p, const VecX& x1, double reported1, const VecX& x2, double reported2) {
  const VecX d = x1 - x2;
  const VecX Ad = p.A * d;
  const double dAd = d.dot(Ad);
  const double c = static_cast<double>(p.rows());
  const double bound = (Ad + d).norm() * std::sqrt(c) * (reported1 + reported2);
  // The rounding of forming A d and the residuals: 64 ε |A| |d|² and 64 ε scale √c |A d + d|.
  const double rounding = 64.0 * 2.2e-16 *
                          (MatX(p.A).cwiseAbs().maxCoeff() * d.squaredNorm() +
                           scale_of(p) * std::sqrt(c) * (Ad + d).norm());
  INFO("d^T A d = " << dAd << ", bound from the reported residuals " << bound << ", rounding "
                    << rounding);
  CHECK(dAd <= bound + rounding);
  const double lambda_max = Eigen::SelfAdjointEigenSolver<MatX>(MatX(p.A)).eigenvalues().maxCoeff();
  CHECK(Ad.squaredNorm() <= lambda_max * (bound + rounding) * (1.0 + 1e-12));
}

SolverOptions peer_options(Method method, int iterations = 20000) {
  SolverOptions o;
  o.method = method;
  o.max_iterations = iterations;
  o.tolerance = 0.0;  // every sweep; a pivoting peer keeps its own default tolerance
  return o;
}

/// A boxed problem with every kind of row: free, [0, ∞), (−∞, 0], [−1, 2] and [0, 3]; A
/// symmetric definite (random_spd), so its answer is unique. (A StoredProblem holds what a
/// BoxedProblem refers to.)
StoredProblem mixed_problem(unsigned seed) {
  StoredProblem p;
  p.A = test::random_spd(5, seed);
  p.b = VecX(5);
  p.b << 7.0, -3.0, 4.0, 9.0, 12.0;
  p.cmin = VecX(5);
  p.cmax = VecX(5);
  p.cmin << -kInf, 0.0, -kInf, -1.0, 0.0;
  p.cmax << kInf, kInf, 0.0, 2.0, 3.0;
  return p;
}

}  // namespace

TEST_CASE("a problem's class for the peers: LCP, relay or MLCP", "[peers]") {
  StoredProblem p = mixed_problem(1);
  CHECK(peer_class(p.problem()) == PeerClass::Mlcp);
  p.cmin.setZero();
  p.cmax.setConstant(kInf);
  CHECK(peer_class(p.problem()) == PeerClass::Lcp);
  p.cmin.setConstant(-1.0);
  p.cmax.setConstant(2.0);
  CHECK(peer_class(p.problem()) == PeerClass::Relay);
  p.cmax[2] = kInf;  // one half-bounded row among finite ones: neither
  CHECK(peer_class(p.problem()) == PeerClass::Mlcp);
}

TEST_CASE("the peers solve a problem with every kind of row to the unique answer", "[peers]") {
  // The answer is unique (A definite), so the direct path's lambda is the one every peer that
  // solves must find. siconos:enum meets the MLCP (a free row) by enumeration, exactly; the
  // mapping of the boxed rows (two complementarity pairs each) is what it checks.
  const StoredProblem stored = mixed_problem(GENERATE(1u, 2u, 3u));
  const BoxedProblem p = stored.problem();
  VecX direct = VecX::Zero(5);
  SolverOptions d;
  d.method = Method::Direct;
  const SolverSummary ds = solve(p, direct, d);
  REQUIRE(ds.residual <= 1e-12 * scale_of(p));
  for (const Method m : {Method::SiconosEnum,
                         Method::SiconosPgs,
                         Method::BulletDantzig,
                         Method::BulletLemke,
                         Method::BulletPgs}) {
    if (missing(m)) continue;
    INFO(to_string(m));
    VecX lambda = VecX::Zero(5);
    const SolverSummary s = solve(p, lambda, peer_options(m));
    INFO(s.message);
    CHECK_FALSE(s.peer_status.empty());
    CHECK(s.residual == Approx(natural_map_residual(p, lambda)).margin(1e-15));
    if (m == Method::SiconosEnum || m == Method::BulletDantzig || m == Method::BulletPgs) {
      // Enumeration and Dantzig's pivoting are exact on a definite A; PGS converges on it.
      CHECK(s.termination != Termination::PeerUnsolved);
      CHECK((lambda - direct).lpNorm<Eigen::Infinity>() <= 1e-8 * (1.0 + direct.norm()));
    }
    if (s.termination != Termination::PeerUnsolved)
      check_agreement(p, lambda, s.residual, direct, ds.residual);
  }
}

TEST_CASE("where a peer solves a contact step, the direct path agrees in w and J^T lambda",
          "[peers][direct]") {
  // Singular A (four contacts a face): lambda is not unique, J^T lambda and w are; the bound
  // of check_agreement holds them. The ball in a V with friction boxes (split in two pairs), a
  // sliding box, a stack of three.
  struct Case {
    const char* name;
    std::map<std::string, std::string> values;
    int steps;
  };
  const Case c = GENERATE(values<Case>(
      {{"v-corner", {{"mu", "0.3"}}, 10}, {"slide", {}, 10}, {"stack", {{"n", "3"}}, 10}}));
  INFO(c.name);
  const System sys = system_of(c.name, c.values, c.steps);
  const BoxedProblem p = sys.problem();
  VecX direct = VecX::Zero(sys.rows());
  SolverOptions d;
  d.method = Method::Direct;
  const double direct_residual = solve(p, direct, d).residual;
  REQUIRE(direct_residual <= 1e-10 * scale_of(p));
  int solved = 0;
  for (const Method m : {Method::SiconosLemke,
                         Method::SiconosEnum,
                         Method::SiconosAvi,
                         Method::BulletDantzig,
                         Method::BulletPgs}) {
    if (missing(m) || !peer_refusal(m, p).empty()) continue;
    INFO(to_string(m));
    VecX lambda = VecX::Zero(sys.rows());
    const SolverSummary s = solve(p, lambda, peer_options(m, 100000));
    INFO(s.message);
    if (s.termination == Termination::PeerUnsolved) continue;
    ++solved;
    check_agreement(p, lambda, s.residual, direct, direct_residual);
  }
  // Measured: siconos:enum on the V and the slide, bullet:pgs on all three.
  CHECK(solved >= 1);
}

TEST_CASE("on the vendored Siconos problems, Siconos' Lemke and cbps's reach the same verdict",
          "[peers][siconos]") {
  if (missing(Method::SiconosLemke)) return;
  int compared = 0;
  for (const char* kind : {"lcp", "relay"}) {
    for (const auto& file : test::dat_files(test::kSiconosDir / kind)) {
      StoredProblem stored;
      try {
        stored = read_problem(file.string());
      } catch (const InputError&) {
        continue;  // the block (SBM) files cbps does not read (io/siconos.hpp)
      }
      INFO(file.filename().string());
      const BoxedProblem p = stored.problem();
      VecX ours = VecX::Zero(p.rows()), theirs = VecX::Zero(p.rows());
      SolverOptions lemke;
      lemke.method = Method::Lemke;
      const SolverSummary c = solve(p, ours, lemke);
      const SolverSummary s = solve(p, theirs, peer_options(Method::SiconosLemke));
      INFO("cbps lemke: " << c.message << "\nsiconos:lemke: " << s.message);
      // The same verdict (unit_free.hpp) on both: both solved, or neither (lcp_CPS_3 and the
      // perturbed Pang problem have no solution; both pivotings end in a ray).
      const bool c_solved = is_solved(unit_free_residual(p, ours), ours);
      const bool s_solved = is_solved(unit_free_residual(p, theirs), theirs);
      CHECK(c_solved == s_solved);
      ++compared;
      // Siconos' own word (its Lemke's end and its own check of the answer) agrees with cbps's
      // verdict on that answer.
      CHECK(s.peer_said_ok == s_solved);
      // Where both solved and A is symmetric semidefinite, w agrees to the residuals' bound.
      const MatX A = MatX(p.A);
      if (c_solved && s_solved && (A - A.transpose()).cwiseAbs().maxCoeff() == 0.0 &&
          Eigen::SelfAdjointEigenSolver<MatX>(A).eigenvalues().minCoeff() >= 0.0)
        check_agreement(p, ours, c.residual, theirs, s.residual);
    }
  }
  CHECK(compared >= 20);  // 24 files cbps reads (3 block files it does not)
}

TEST_CASE("a peer that cannot take a problem says why, before it runs", "[peers]") {
  StoredProblem big;
  big.A = test::random_spd(21, 4);
  big.b = VecX::Ones(21);
  big.cmin = VecX::Zero(21);
  big.cmax = VecX::Constant(21, kInf);
  const StoredProblem free_row = mixed_problem(1);
  StoredProblem positive_bound = mixed_problem(1);
  positive_bound.cmin[4] = 0.5;  // [0.5, 3]: Dantzig's method starts at 0
  VecX lambda;
  const auto refused = [&](Method m, const StoredProblem& p, const std::string& why) {
    INFO(to_string(m) << ": " << why);
    if (missing(m)) return;
    CHECK_THAT(peer_refusal(m, p.problem()), Catch::Contains(why));
    CHECK_THROWS_AS(solve(p.problem(), lambda, peer_options(m)), InputError);
  };
  refused(Method::SiconosEnum, big, "at most 20");
  refused(Method::SiconosAvi, free_row, "row 0 is free");
  refused(Method::BulletDantzig, positive_bound, "cmin <= 0 <= cmax");
  if (!missing(Method::SiconosEnum))
    CHECK(peer_refusal(Method::SiconosEnum, free_row.problem()).empty());
}

TEST_CASE("Siconos ending its process ends only its child: cbps reports it and goes on",
          "[peers][siconos]") {
  // Siconos' MLCP Lemke asserts (NM_gemm: A->matrix0) on a chain's free rows: measured with
  // `cbps lcp` on a chain folder. The child dies of SIGABRT; the parent's lambda stays the guess.
  if (missing(Method::SiconosLemke)) return;
  const System sys = system_of("chain", {{"n", "10"}}, 5);
  const BoxedProblem p = sys.problem();
  REQUIRE(peer_class(p) == PeerClass::Mlcp);
  VecX lambda = VecX::Zero(sys.rows());
  const SolverSummary s = solve(p, lambda, peer_options(Method::SiconosLemke));
  CHECK_THAT(s.peer_status, Catch::Contains("ended the process"));
  CHECK_FALSE(s.peer_said_ok);
  CHECK(s.termination == Termination::PeerUnsolved);
  CHECK(lambda.isZero(0.0));
  // And this process goes on: the same problem by enumeration afterwards.
  const SolverSummary e = solve(p, lambda, peer_options(Method::SiconosEnum));
  CHECK(e.termination == Termination::Direct);
}

TEST_CASE("the peers get cbps's iteration limit", "[peers]") {
  // The ball in a V (an LCP of two rows) takes PGS 9 sweeps to 1e-10 of its scale; asked for 3,
  // Siconos' PGS and Bullet's stop at 3.
  const System sys = system_of("v-corner", {}, 10);
  const BoxedProblem p = sys.problem();
  REQUIRE(peer_class(p) == PeerClass::Lcp);
  for (const Method m : {Method::SiconosPgs, Method::BulletPgs}) {
    if (missing(m)) continue;
    INFO(to_string(m));
    VecX lambda = VecX::Zero(sys.rows());
    SolverOptions o = peer_options(m, 3);
    const SolverSummary s = solve(p, lambda, o);
    CHECK(s.peer_iterations == 3);
    // Three sweeps of Gauss-Seidel from 0: cbps's own PGS gives the same iterate.
    VecX pgs = VecX::Zero(sys.rows());
    SolverOptions own;
    own.method = Method::Pgs;
    own.max_iterations = 3;
    solve(p, pgs, own);
    CHECK((lambda - pgs).lpNorm<Eigen::Infinity>() <= 1e-12 * (1.0 + pgs.norm()));
  }
}

TEST_CASE("Siconos' fc3d solvers on a sliding box: Coulomb's law, judged by cbps",
          "[peers][siconos][cones]") {
  // The slide scene: a box moving at 2 m/s along x on a plane, four contacts sliding the same
  // way. Coulomb's law per contact (cone_problem.hpp): u_n = 0, friction −mu r_n u_t / ‖u_t‖,
  // properties of the law checked on sums no solver forms. NSN-AC and ADMM are run too: they
  // must return, and whatever they return is judged by the same residual.
  const double mu = 0.3;
  const System sys = system_of("slide", {{"mu", "0.3"}}, 2);
  const FrictionContacts cones = test::cones_of(sys, mu, FrictionLaw::CoulombCone);
  REQUIRE(cones.contacts() * 3 == sys.rows());  // every row a contact's
  BoxedProblem problem = sys.problem();
  problem.cones = &cones;
  REQUIRE(peer_class(problem) == PeerClass::FrictionContact);
  for (const Method m : {Method::SiconosFc3dNsgs,
                         Method::SiconosFc3dProx,
                         Method::SiconosFc3dNsnAc,
                         Method::SiconosFc3dAdmm}) {
    if (missing(m)) continue;
    SolverOptions o = peer_options(m, 2000);
    o.tolerance = 1e-12;
    VecX lambda = VecX::Zero(sys.rows());
    const SolverSummary s = solve(problem, lambda, o);
    INFO(to_string(m) << ": " << s.message);
    REQUIRE(lambda.allFinite());
    const double residual = natural_map_residual(problem, lambda);
    CHECK(s.residual == residual);  // cbps's verdict is cbps's residual, never the peer's word
    const bool solved = is_solved(unit_free_residual(problem, lambda), lambda);
    CHECK((s.termination != Termination::PeerUnsolved) == solved);
    if (m == Method::SiconosFc3dNsgs || m == Method::SiconosFc3dProx) {
      // The two that solve the slide: Coulomb's law on the sums.
      REQUIRE(solved);
      const VecX w = sys.A * lambda - sys.b;
      double normal = 0.0;
      Eigen::Vector2d friction = Eigen::Vector2d::Zero();
      for (const int n : cones.normal) {
        normal += lambda(n);
        CHECK(std::abs(w(n)) <= 1e-8);
        const double u_t = std::hypot(w(n + 1), w(n + 2));
        REQUIRE(u_t > 1e-3);
        // Against the sliding, as strong as the cone allows: r_t · u_t = −mu r_n ‖u_t‖.
        CHECK(lambda(n + 1) * w(n + 1) + lambda(n + 2) * w(n + 2) ==
              Approx(-mu * lambda(n) * u_t).epsilon(1e-8));
        friction += Eigen::Vector2d(lambda(n + 1), lambda(n + 2));
      }
      CHECK(normal > 0.0);
      CHECK(friction.norm() == Approx(mu * normal).epsilon(1e-8));
    }
  }
}

TEST_CASE("Siconos' fc3d solvers take only Coulomb's cones, every row a contact's",
          "[peers][siconos][cones]") {
  const System sys = system_of("slide", {{"mu", "0.3"}}, 2);
  FrictionContacts cones = test::cones_of(sys, 0.3, FrictionLaw::Relaxation);
  BoxedProblem problem = sys.problem();
  VecX lambda;
  const auto refused = [&](Method m, const BoxedProblem& p, const std::string& why) {
    INFO(to_string(m) << ": " << why);
    if (missing(m)) return;
    CHECK_THAT(peer_refusal(m, p), Catch::Contains(why));
    CHECK_THROWS_AS(solve(p, lambda, peer_options(m)), InputError);
  };
  refused(Method::SiconosFc3dProx, problem, "this one is the boxed problem");
  problem.cones = &cones;
  refused(Method::SiconosFc3dNsgs, problem, "convex relaxation (ccp)");
  // The same contacts beside a row no contact owns (a free row of its own).
  cones.law = FrictionLaw::CoulombCone;
  const long c = sys.rows();
  SpMat A(c + 1, c + 1);
  std::vector<Triplet> t;
  for (int j = 0; j < sys.A.outerSize(); ++j)
    for (SpMat::InnerIterator it(sys.A, j); it; ++it) t.emplace_back(int(it.row()), j, it.value());
  t.emplace_back(int(c), int(c), 1.0);
  A.setFromTriplets(t.begin(), t.end());
  const VecX b = (VecX(c + 1) << sys.b, 1.0).finished();
  const VecX cmin = (VecX(c + 1) << sys.cmin, -kInf).finished();
  const VecX cmax = (VecX(c + 1) << sys.cmax, kInf).finished();
  BoxedProblem extra{A, b, cmin, cmax};
  extra.cones = &cones;
  refused(Method::SiconosFc3dAdmm, extra, "row " + std::to_string(c) + " is in no contact");
  // And the boxed peers refuse the cones (solve(): they solve 6.2's boxed problem).
  if (!missing(Method::SiconosLemke))
    CHECK_THROWS_WITH(solve(problem, lambda, peer_options(Method::SiconosLemke)),
                      Catch::Contains("siconos:fc3d-*"));
}
