// The exact path (solve_direct): boxed LCPs whose solution is known by construction, the
// optimality conditions of the equivalent QP, singular and inconsistent systems, islands, and
// agreement with PGS, CHOLMOD and boxed Lemke on what is unique (6.2).
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <random>
#include <vector>

#include "cbps/cbps.hpp"
#include "cbps/error.hpp"
#include "cbps/io/siconos.hpp"
#include "cbps/scene/builtin.hpp"
#include "cbps/solvers/lemke.hpp"
#include "cbps/step/simulation.hpp"

using namespace cbps;
namespace fs = std::filesystem;

namespace {

/// A boxed problem with a solution chosen first: lambda_star, and w_star = A lambda_star − b with
/// the sign each row's place demands (6.2).
struct Constructed {
  SpMat A;
  MatX J;  ///< A = J Jᵀ: rows of J are the constraints, columns the degrees of freedom
  VecX b, lo, hi, lambda_star, w_star;
};

/// k rows over d degrees of freedom, A = J Jᵀ: positive definite if d ≥ k (almost surely),
/// semidefinite with rank d if d < k, as a box on four contacts (12 rows, 6 DOF). Rows are a
/// mix of the paper's kinds: bilateral (free), contact [0, ∞) at rest or pushing, friction
/// [−c, c] sticking or sliding, fixed (cmin = cmax).
Constructed construct(int k, int d, std::mt19937& rng) {
  std::normal_distribution<double> n01;
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Constructed p;
  p.J = MatX(k, d);
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < d; ++j) p.J(i, j) = u(rng) < 0.5 ? n01(rng) : 0.0;
  for (int i = 0; i < k; ++i) p.J(i, i % d) += 1.0;  // no empty row
  const MatX A = p.J * p.J.transpose();
  p.A = A.sparseView();
  p.lo.resize(k);
  p.hi.resize(k);
  p.lambda_star.resize(k);
  p.w_star = VecX::Zero(k);
  for (int i = 0; i < k; ++i) {
    const double c = 0.5 + u(rng);
    switch (static_cast<int>(6 * u(rng))) {
      case 0:  // bilateral row (distance): free, w = 0
        p.lo(i) = -kInf;
        p.hi(i) = kInf;
        p.lambda_star(i) = 2 * u(rng) - 1;
        break;
      case 1:  // contact, separating: lambda = 0, w > 0
        p.lo(i) = 0;
        p.hi(i) = kInf;
        p.lambda_star(i) = 0;
        p.w_star(i) = 0.1 + u(rng);
        break;
      case 2:  // contact, pushing: lambda > 0, w = 0
        p.lo(i) = 0;
        p.hi(i) = kInf;
        p.lambda_star(i) = 0.1 + u(rng);
        break;
      case 3:  // friction at its bound, sliding
        p.lo(i) = -c;
        p.hi(i) = c;
        p.lambda_star(i) = u(rng) < 0.5 ? -c : c;
        p.w_star(i) = p.lambda_star(i) < 0 ? 0.1 + u(rng) : -0.1 - u(rng);
        break;
      case 4:  // fixed row: lambda = cmin = cmax, w anything
        p.lo(i) = p.hi(i) = c;
        p.lambda_star(i) = c;
        p.w_star(i) = 2 * u(rng) - 1;
        break;
      default:  // friction sticking: strictly inside
        p.lo(i) = -c;
        p.hi(i) = c;
        p.lambda_star(i) = c * (1.6 * u(rng) - 0.8);
    }
  }
  // A semidefinite: a nonzero w on a free row must be orthogonal to nothing, but b = A λ* − w*
  // is any vector, so every constructed problem has λ* as a solution.
  p.b = A * p.lambda_star - p.w_star;
  return p;
}

double objective(const SpMat& A, const VecX& b, const VecX& x) {
  return 0.5 * x.dot(A * x) - b.dot(x);  // ½ λᵀ A λ − bᵀ λ (6.2)
}

/// max(1, ‖b‖∞, max |A_ij|), the scale residuals are measured against (lcp.hpp).
double scale_of(const SpMat& A, const VecX& b) { return lcp_scale(MatX(A), -b); }

VecX solve_exact(const Constructed& p, SolverSummary* summary = nullptr) {
  VecX lambda = VecX::Zero(p.b.size());
  const SolverSummary s = solve_direct(BoxedProblem{p.A, p.b, p.lo, p.hi}, lambda);
  if (summary != nullptr) *summary = s;
  return lambda;
}

}  // namespace

TEST_CASE("islands are the connected blocks of A, found in order of their first row", "[direct]") {
  // Rows {0, 3, 5}, {1, 4} and {2}: a permuted block diagonal.
  std::vector<Triplet> t;
  for (const auto& [i, j] : std::vector<std::pair<int, int>>{{0, 3}, {3, 5}, {1, 4}}) {
    t.emplace_back(i, j, 1.0);
    t.emplace_back(j, i, 1.0);
  }
  for (int i = 0; i < 6; ++i) t.emplace_back(i, i, 4.0);
  SpMat A(6, 6);
  A.setFromTriplets(t.begin(), t.end());
  const auto islands = find_islands(A);
  REQUIRE(islands.size() == 3);
  CHECK(islands[0] == std::vector<int>{0, 3, 5});
  CHECK(islands[1] == std::vector<int>{1, 4});
  CHECK(islands[2] == std::vector<int>{2});
}

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
  std::mt19937 rng(12);
  int singular = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const int d = 2 + trial % 10;
    const int k = d + 1 + trial % 13;  // more rows than degrees of freedom: A singular
    const Constructed p = construct(k, d, rng);
    SolverSummary s;
    const VecX lambda = solve_exact(p, &s);
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
  CHECK(singular > 100);  // most of these needed the proximal (regularised) path
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

  VecX apart;
  const SolverSummary s = solve_direct(BoxedProblem{A, b, lo, hi}, apart);
  INFO(s.message);
  CHECK(s.islands == 10);
  CHECK(s.termination == Termination::Direct);
  CHECK((A * apart - b - w_star).lpNorm<Eigen::Infinity>() <= 1e-7 * scale);

  SolverOptions whole;
  whole.direct.split_islands = false;
  VecX together;
  const SolverSummary s1 = solve_direct(BoxedProblem{A, b, lo, hi}, together, whole);
  INFO(s1.message);
  CHECK(s1.islands == 1);
  CHECK(s1.termination == Termination::Direct);
  CHECK((A * together - A * apart).lpNorm<Eigen::Infinity>() <= 1e-7 * scale);

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

TEST_CASE("PGS converges to the direct lambda on positive definite boxed problems",
          "[direct][solver][eq7.1.1]") {
  std::mt19937 rng(15);
  for (int trial = 0; trial < 30; ++trial) {
    const Constructed p = construct(10, 13, rng);
    const VecX exact = solve_exact(p);
    VecX pgs = VecX::Zero(10);
    SolverOptions options;
    options.max_iterations = 200000;
    options.tolerance = 1e-12;
    const SolverSummary s = solve_pgs(BoxedProblem{p.A, p.b, p.lo, p.hi}, pgs, options);
    CAPTURE(trial, s.message);
    REQUIRE(s.termination == Termination::ResidualTolerance);
    CHECK((pgs - exact).lpNorm<Eigen::Infinity>() <= 1e-8 * scale_of(p.A, p.b));
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

// ---------------------------------------------------------------------------------------------
// Block PGS (block_pgs_sweep): 7.1.1 over blocks of rows, each solved by boxed Lemke.

TEST_CASE("block PGS with blocks of one row is PGS (7.1.1), iterate for iterate", "[direct][pgs]") {
  std::mt19937 rng(11);
  const Constructed p = construct(30, 40, rng);
  const std::vector<int> singles(30, -1);
  VecX a = VecX::Zero(30), b = VecX::Zero(30);
  for (int sweep = 0; sweep < 25; ++sweep) {
    pgs_sweep(BoxedProblem{p.A, p.b, p.lo, p.hi}, a);
    block_pgs_sweep(BoxedProblem{p.A, p.b, p.lo, p.hi, nullptr, nullptr, &singles}, b);
    REQUIRE((a - b).lpNorm<Eigen::Infinity>() == 0.0);  // the same arithmetic, in the same order
  }
}

TEST_CASE("block PGS finds the constructed solution; one block of every row is Lemke's answer",
          "[direct][pgs]") {
  std::mt19937 rng(12);
  for (int trial = 0; trial < 50; ++trial) {
    CAPTURE(trial);
    const Constructed p = construct(24, 30, rng);  // positive definite: lambda* is unique
    const double scale = scale_of(p.A, p.b);
    std::vector<int> blocks(24);
    for (int i = 0; i < 24; ++i) blocks[static_cast<std::size_t>(i)] = i / 4;  // 6 blocks of 4
    SolverOptions options;
    options.method = Method::BlockPgs;
    options.max_iterations = 2000;
    options.tolerance = 1e-10 * scale;
    options.block_regularization = 0.0;
    VecX lambda = VecX::Zero(24);
    const SolverSummary s =
        solve(BoxedProblem{p.A, p.b, p.lo, p.hi, nullptr, nullptr, &blocks}, lambda, options);
    CAPTURE(s.message);
    CHECK(s.termination == Termination::ResidualTolerance);
    CHECK((lambda - p.lambda_star).lpNorm<Eigen::Infinity>() <= 1e-6);
    CHECK(s.message.find("row by row") == std::string::npos);  // Lemke solved every block

    const std::vector<int> one(24, 0);
    VecX whole = VecX::Zero(24);
    block_pgs_sweep(BoxedProblem{p.A, p.b, p.lo, p.hi, nullptr, nullptr, &one}, whole, 1.0, 0.0);
    CHECK(natural_map_residual(BoxedProblem{p.A, p.b, p.lo, p.hi}, whole) <= 1e-9 * scale);
  }
}

TEST_CASE("block PGS on a resting stack reaches the direct path's v2 (7.1.1, 6.2)",
          "[direct][pgs][contact]") {
  // 5 boxes: 5 manifolds of 4 points, 12 rows each, every block of rank 6. From lambda = 0,
  // 400 block sweeps against row-by-row PGS with as many sweeps; the direct path is the
  // reference for the unique v2 (6.2).
  Scene scene = make_builtin_scene("stack", {{"n", "5"}});
  const Simulation sim(scene);
  const System sys = sim.build_system();
  REQUIRE(sys.rows() == 60);
  VecX exact = VecX::Zero(sys.rows());
  REQUIRE(solve_direct(sys.problem(), exact).termination == Termination::Direct);
  const VecX v2 = compute_v2(sys.v1, sys.Minv, sys.J, exact, sys.fext, sys.dt);
  const auto error_after = [&](Method method) {
    SolverOptions options;
    options.method = method;
    options.max_iterations = 400;
    VecX lambda = VecX::Zero(sys.rows());
    solve(sys.problem(), lambda, options);  // the problem's blocks: one per contact manifold
    return (compute_v2(sys, lambda) - v2).lpNorm<Eigen::Infinity>();
  };
  const double block = error_after(Method::BlockPgs);
  const double rows = error_after(Method::Pgs);
  INFO("max |v2 - v2_direct| after 400 sweeps: block PGS " << block << " m/s, PGS " << rows
                                                           << " m/s");
  CHECK(block < 1e-6);
  CHECK(block < 0.01 * rows);
}
