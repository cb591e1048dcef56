// The exact path (solve_direct): boxed LCPs whose solution is known by construction, the
// optimality conditions of the equivalent QP, singular and inconsistent systems, islands, its
// tolerance, and agreement with PGS, CHOLMOD and boxed Lemke on what is unique (6.2).
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <random>
#include <vector>

#include "cbps/base/error.hpp"
#include "cbps/io/siconos.hpp"
#include "cbps/scene/builtin.hpp"
#include "cbps/solvers/exact/active_set.hpp"
#include "cbps/solvers/exact/direct.hpp"
#include "cbps/solvers/exact/lemke.hpp"
#include "cbps/solvers/paper/pgs.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/step/simulation.hpp"
#include "cbps/system/boxed_problem.hpp"
#include "cbps/system/system.hpp"
#include "fixture.hpp"

using namespace cbps;
using test::construct;
using test::Constructed;
using test::scale_of;
using test::solve_exact;
namespace fs = std::filesystem;

namespace {

double objective(const SpMat& A, const VecX& b, const VecX& x) {
  return 0.5 * x.dot(A * x) - b.dot(x);  // ½ λᵀ A λ − bᵀ λ (6.2)
}

}  // namespace

TEST_CASE("the direct path equals CHOLMOD on an equality system with one factorization",
          "[direct][eq6.2.9]") {
  Simulation sim(make_builtin_scene("chain", {{"n", "40"}, {"mass_ratio", "10"}}));
  for (int s = 0; s < 20; ++s) sim.step();
  const System sys = sim.build_system();
  VecX cholesky;
  solve_cholesky(sys.A, sys.b, cholesky);
  VecX lambda;
  const SolverSummary s = solve_direct(sys.problem(), lambda);
  INFO(s.message);
  CHECK(s.termination == Termination::Direct);
  CHECK(s.factorizations == 1);
  CHECK_FALSE(s.singular);
  CHECK((lambda - cholesky).lpNorm<Eigen::Infinity>() <=
        1e-12 * cholesky.lpNorm<Eigen::Infinity>());
}

TEST_CASE("positive definite boxed problems: the constructed lambda is found (6.2)",
          "[direct][eq6.2.9]") {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 200; ++trial) {
    const int k = 1 + trial % 25;
    const Constructed p = construct(k, k + 3, rng);
    SolverSummary s;
    const VecX lambda = solve_exact(p, &s);
    CAPTURE(trial, k, s.message);
    REQUIRE(s.termination == Termination::Direct);
    const double scale = scale_of(p.A, p.b);
    CHECK(natural_map_residual(BoxedProblem{p.A, p.b, p.lo, p.hi}, lambda) <= 1e-12 * scale);
    // A is positive definite: lambda is unique.
    CHECK((lambda - p.lambda_star).lpNorm<Eigen::Infinity>() <= 1e-8 * scale);
  }
}

TEST_CASE("semidefinite boxed problems: w and Jᵀ lambda are the constructed ones (6.2)",
          "[direct][eq6.2.9]") {
  const Method method = GENERATE(Method::Direct, Method::ActiveSet);
  CAPTURE(to_string(method));
  std::mt19937 rng(12);
  int singular = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const int d = 2 + trial % 10;
    const int k = d + 1 + trial % 13;  // more rows than degrees of freedom: A singular
    const Constructed p = construct(k, d, rng);
    SolverSummary s;
    const VecX lambda = solve_exact(p, &s, method);
    CAPTURE(trial, k, d, s.message);
    REQUIRE(s.termination == Termination::Direct);
    singular += s.singular ? 1 : 0;
    const double scale = scale_of(p.A, p.b);
    CHECK(natural_map_residual(BoxedProblem{p.A, p.b, p.lo, p.hi}, lambda) <= 1e-9 * scale);
    // lambda is not unique, but w = A lambda − b and the force Jᵀ lambda are (6.2).
    const VecX w = p.A * lambda - p.b;
    CHECK((w - p.w_star).lpNorm<Eigen::Infinity>() <= 1e-7 * scale);
    const VecX force = p.J.transpose() * lambda;
    const VecX force_star = p.J.transpose() * p.lambda_star;
    CHECK((force - force_star).lpNorm<Eigen::Infinity>() <= 1e-7 * scale);
  }
  // Most of these needed the active-set path's proximal (regularised) loop; the interior-point
  // path regularises every Newton system and does not tell.
  if (method == Method::ActiveSet) CHECK(singular > 100);
}

TEST_CASE("the direct solution minimises ½ λᵀAλ − bᵀλ over the box (6.2)", "[direct][eq6.2.9]") {
  std::mt19937 rng(13);
  std::normal_distribution<double> n01;
  for (int trial = 0; trial < 60; ++trial) {
    const int d = 3 + trial % 6;
    const int k = trial % 2 == 0 ? d + 4 : d;  // semidefinite and definite
    const Constructed p = construct(k, d, rng);
    const VecX lambda = solve_exact(p);
    const double f = objective(p.A, p.b, lambda);
    const double slack = 1e-9 * std::max(1.0, std::abs(f));
    CAPTURE(trial, k, d, f);
    // Any feasible point, near or far, is no better (the QP is convex: local = global).
    for (const double step : {1e-4, 1e-2, 1.0, 10.0}) {
      for (int sample = 0; sample < 50; ++sample) {
        VecX mu(k);
        for (int i = 0; i < k; ++i) mu(i) = clamp(lambda(i) + step * n01(rng), p.lo(i), p.hi(i));
        CHECK(objective(p.A, p.b, mu) >= f - slack);
      }
    }
  }
}

TEST_CASE("many islands solved apart give what one block gives, and boxed Lemke agrees",
          "[direct][lcp]") {
  // Ten constructed problems placed on the diagonal in a shuffled row order.
  std::mt19937 rng(14);
  std::vector<Constructed> parts;
  int n = 0;
  for (int i = 0; i < 10; ++i) {
    parts.push_back(construct(6 + i, 4 + i % 5, rng));
    n += static_cast<int>(parts.back().b.size());
  }
  std::vector<int> order(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) order[std::size_t(i)] = i;
  std::shuffle(order.begin(), order.end(), rng);
  std::vector<Triplet> t;
  VecX b(n), lo(n), hi(n), w_star(n);
  int offset = 0;
  for (const Constructed& p : parts) {
    const auto k = static_cast<int>(p.b.size());
    for (int i = 0; i < k; ++i) {
      const int gi = order[std::size_t(offset + i)];
      b(gi) = p.b(i);
      lo(gi) = p.lo(i);
      hi(gi) = p.hi(i);
      w_star(gi) = p.w_star(i);
      for (SpMat::InnerIterator it(p.A, i); it; ++it)
        t.emplace_back(order[std::size_t(offset + it.row())], gi, it.value());
    }
    offset += k;
  }
  SpMat A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  const double scale = scale_of(A, b);

  // The active-set path splits the islands; the interior-point path takes them together.
  VecX apart;
  const SolverSummary s = solve_active_set(BoxedProblem{A, b, lo, hi}, apart);
  INFO(s.message);
  CHECK(s.islands == 10);
  CHECK(s.termination == Termination::Direct);
  CHECK((A * apart - b - w_star).lpNorm<Eigen::Infinity>() <= 1e-7 * scale);

  SolverOptions whole;
  whole.direct.split_islands = false;
  VecX together;
  const SolverSummary s1 = solve_active_set(BoxedProblem{A, b, lo, hi}, together, whole);
  INFO(s1.message);
  CHECK(s1.islands == 1);
  CHECK(s1.termination == Termination::Direct);
  CHECK((A * together - A * apart).lpNorm<Eigen::Infinity>() <= 1e-7 * scale);

  VecX interior;
  const SolverSummary s2 = solve_direct(BoxedProblem{A, b, lo, hi}, interior);
  INFO(s2.message);
  CHECK(s2.termination == Termination::Direct);
  CHECK((A * interior - A * apart).lpNorm<Eigen::Infinity>() <= 1e-7 * scale);

  // An independent dense method: Lemke on the boxed problem (M = A, q = −b).
  const LcpResult lemke = solve_boxed_lemke(MatX(A), -b, lo, hi);
  INFO(lemke.message);
  REQUIRE(lemke.solved());
  CHECK((A * lemke.z - A * apart).lpNorm<Eigen::Infinity>() <= 1e-7 * scale);
}

TEST_CASE("a row given twice: Cholesky refuses, the direct path solves it, v2 is unchanged",
          "[direct][eq6.2.9][eq12.3.1]") {
  Simulation plain(make_builtin_scene("chain", {{"n", "8"}}));
  for (int s = 0; s < 25; ++s) plain.step();
  Scene scene = plain.scene();                    // the same state, bodies moving
  scene.distances.push_back(scene.distances[3]);  // the same constraint twice: A singular
  const Simulation doubled(scene);
  const System sys = plain.build_system();
  const System sys2 = doubled.build_system();
  VecX lambda;
  solve_cholesky(sys.A, sys.b, lambda);
  const VecX v2 = compute_v2(sys.v1, sys.Minv, sys.J, lambda, sys.fext, sys.dt);

  VecX dummy;
  CHECK_THROWS_AS(solve_cholesky(sys2.A, sys2.b, dummy), ComputationError);
  VecX lambda2;
  const SolverSummary s = solve_direct(sys2.problem(), lambda2);
  INFO(s.message);
  CHECK(s.termination == Termination::Direct);
  CHECK(s.singular);
  const VecX v2_doubled = compute_v2(sys2.v1, sys2.Minv, sys2.J, lambda2, sys2.fext, sys2.dt);
  CHECK((v2_doubled - v2).lpNorm<Eigen::Infinity>() <= 1e-10);
  // The two copies share the one constraint force between them.
  CHECK(lambda2(3) + lambda2(8) == Approx(lambda(3)).epsilon(1e-9));

  SECTION("and PGS converges to the same v2 and w although lambda is not unique") {
    VecX pgs = VecX::Zero(sys2.rows());
    SolverOptions options;
    options.max_iterations = 100000;
    options.tolerance = 1e-11;
    const SolverSummary sp = solve_pgs(sys2.problem(), pgs, options);
    INFO(sp.message);
    CHECK(sp.termination == Termination::ResidualTolerance);
    const VecX v2_pgs = compute_v2(sys2.v1, sys2.Minv, sys2.J, pgs, sys2.fext, sys2.dt);
    CHECK((v2_pgs - v2_doubled).lpNorm<Eigen::Infinity>() <= 1e-8);
    CHECK((sys2.A * pgs - sys2.A * lambda2).lpNorm<Eigen::Infinity>() <= 1e-9);
  }
}

TEST_CASE("inconsistent equality rows are reported as not converged, never as solved", "[direct]") {
  // Rows 0 and 1 are the same constraint asking for different things: no lambda solves both.
  MatX Ad(3, 3);
  Ad << 1, 1, 0, 1, 1, 0, 0, 0, 2;
  const SpMat A = Ad.sparseView();
  const VecX b = (VecX(3) << 1.0, 2.0, 4.0).finished();
  const VecX lo = VecX::Constant(3, -kInf), hi = VecX::Constant(3, kInf);
  VecX lambda;
  const SolverSummary s = solve_direct(BoxedProblem{A, b, lo, hi}, lambda);
  INFO(s.message);
  CHECK(s.termination == Termination::NotConverged);
  CHECK(s.residual >= 0.49);  // w = (s − 1, s − 2, ·) can be no smaller than ±0.5
  CHECK(s.message.find("stopped short") != std::string::npos);
  CHECK(lambda(2) == Approx(2.0));  // the consistent island is still solved
}

TEST_CASE("non-finite data ends the direct solve with NonFinite", "[direct]") {
  const SpMat A = MatX::Identity(2, 2).sparseView();
  const VecX b = (VecX(2) << 1.0, std::nan("")).finished();
  const VecX lo = VecX::Zero(2), hi = VecX::Constant(2, kInf);
  VecX lambda;
  CHECK(solve_direct(BoxedProblem{A, b, lo, hi}, lambda).termination == Termination::NonFinite);
}

TEST_CASE("a guess is taken at the rounding floor of its own rows, not of the largest row's",
          "[direct][tolerance]") {
  // Two rows of compliances 1e6 and 1e-8 kg⁻¹ (a milligram and a hundred-tonne body), each
  // pushed to λ_k = b_k / A_kk (1/3 N and 1 N). The guess has row 1 half a newton off: its w_1
  // is 5e-9 m/s, under the rounding floor of the first row (64 u · 1e6 · 1/3 · 2, 4.7e-9 m/s,
  // which the shared floor gave every row) and 1e14 times that of its own (64 u · 2e-8). Taken
  // as it was, direct returned λ_1 = 1.5 N and called it solved.
  const SpMat A = (VecX(2) << 1e6, 1e-8).finished().asDiagonal().toDenseMatrix().sparseView();
  const VecX b = (VecX(2) << 1e6 / 3.0, 1e-8).finished();
  const VecX lo = VecX::Zero(2), hi = VecX::Constant(2, kInf);
  const BoxedProblem problem{A, b, lo, hi};
  VecX lambda = (VecX(2) << 1.0 / 3.0, 1.5).finished();
  SolverOptions o;
  o.tolerance = 1e-10;
  const SolverSummary s = solve_direct(problem, lambda, o);
  INFO(s.message);
  CHECK(s.termination == Termination::Direct);
  CHECK(s.route != "guess");
  CHECK(lambda(0) == Approx(1.0 / 3.0).epsilon(1e-14));
  CHECK(lambda(1) == Approx(1.0).epsilon(1e-12));
  // The guess of the right answer is still taken as it is.
  VecX exact = (VecX(2) << 1.0 / 3.0, 1.0).finished();
  CHECK(within_rounding(problem, exact, VecX::Ones(2), 0.0));
  const SolverSummary again = solve_direct(problem, exact, o);
  CHECK(again.route == "guess");
  CHECK(exact(1) == 1.0);
}

TEST_CASE("every symmetric Siconos relay problem: direct and boxed Lemke agree on w",
          "[direct][siconos]") {
  const fs::path dir = fs::path(CBPS_DATA_DIR) / "siconos" / "relay";
  int compared = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() != ".dat") continue;
    const StoredLcp p = read_siconos(entry.path().string(), true);
    if ((p.M - p.M.transpose()).lpNorm<Eigen::Infinity>() > 0) continue;
    CAPTURE(entry.path().filename().string());
    const SpMat A = p.M.sparseView();
    const VecX b = -p.q;
    VecX lambda;
    const SolverSummary s = solve_direct(BoxedProblem{A, b, p.lb, p.ub}, lambda);
    INFO(s.message);
    const LcpResult lemke = solve_boxed_lemke(p.M, p.q, p.lb, p.ub);
    REQUIRE(lemke.solved());
    const double scale = lcp_scale(p.M, p.q);
    CHECK(s.termination == Termination::Direct);
    CHECK(s.residual <= kLcpSolvedTolerance * scale);
    CHECK((p.M * lambda - p.M * lemke.z).lpNorm<Eigen::Infinity>() <= 1e-9 * scale);
    ++compared;
  }
  CHECK(compared >= 5);
}

TEST_CASE("the solver tolerance reaches the direct path", "[exports][direct][tolerance]") {
  // A pyramid's one island is singular: the direct path's proximal loop takes many steps to
  // the rounding floor and stops early at a loose tolerance, which it must then meet.
  Scene scene = make_builtin_scene("pyramid", {{"base", "6"}});
  Simulation sim(scene);
  for (int k = 0; k < 30; ++k) sim.step();
  const System& sys = sim.assemble();
  SolverSettings tight = scene.solver;
  tight.method = Method::Direct;
  tight.tolerance = 0.0;
  SolverSettings loose = tight;
  loose.tolerance = 1e-3;
  VecX lambda_tight = VecX::Zero(sys.rows()), lambda_loose = VecX::Zero(sys.rows());
  const SolverSummary t = sim.solve_system(sys, sys.b, lambda_tight, tight);
  const SolverSummary l = sim.solve_system(sys, sys.b, lambda_loose, loose);
  CHECK(t.residual < 1e-9);
  CHECK(l.residual <= 1e-3);
  CHECK(l.residual > 10 * t.residual);
  CHECK(l.iterations < t.iterations);
  CHECK(l.termination == Termination::Direct);
}
