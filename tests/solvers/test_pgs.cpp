// Projected Gauss-Seidel and Jacobi (7.1.1) against exact answers, and the forms of the sweep:
// symmetric, in a random row order, damped.
#include <Eigen/Cholesky>
#include <catch2/catch.hpp>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "cbps/scene/builtin.hpp"
#include "cbps/solvers/exact/direct.hpp"
#include "cbps/solvers/paper/pgs.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/step/simulation.hpp"
#include "cbps/system/boxed_problem.hpp"
#include "cbps/system/system.hpp"
#include "fixture.hpp"

using namespace cbps;
using test::construct;
using test::Constructed;
using test::random_spd;
using test::scale_of;
using test::solve_exact;
using test::system_of;

TEST_CASE("PGS with infinite bounds converges to the Cholesky solution (7.1.1, 6.2.9)",
          "[solver][eq7.1.1]") {
  Simulation sim(make_builtin_scene("chain", {{"n", "30"}, {"mass_ratio", "5"}}));
  for (int s = 0; s < 30; ++s) sim.step();  // falling: gravity now loads every link
  const System sys = sim.build_system();
  VecX direct;
  solve_cholesky(sys.A, sys.b, direct);
  VecX lambda = VecX::Zero(sys.rows());
  SolverOptions options;
  options.max_iterations = 200000;
  options.tolerance = 1e-11;
  const SolverSummary s = solve_pgs(sys.problem(), lambda, options);
  INFO(s.message);
  CHECK(s.termination == Termination::ResidualTolerance);
  // A is positive definite here, so lambda is unique: compare it relative to its size.
  CHECK((lambda - direct).lpNorm<Eigen::Infinity>() < 1e-6 * direct.lpNorm<Eigen::Infinity>());
}

TEST_CASE("one PGS sweep uses each new lambda_j at once, Jacobi the old ones (7.1.1)",
          "[solver][eq7.1.1]") {
  // clang-format off
  MatX Ad(2, 2); Ad << 2, 1,
                       1, 2;
  // clang-format on
  const SpMat A = Ad.sparseView();
  const VecX b = VecX::Constant(2, 3.0);
  const VecX lo = VecX::Constant(2, -kInf);
  const VecX hi = VecX::Constant(2, kInf);
  VecX gs = VecX::Zero(2);
  pgs_sweep(BoxedProblem{A, b, lo, hi}, gs);
  CHECK(gs(0) == 1.5);   // (3 − 1·0) / 2
  CHECK(gs(1) == 0.75);  // (3 − 1·1.5) / 2
  VecX jac = VecX::Zero(2);
  VecX scratch;
  jacobi_sweep(BoxedProblem{A, b, lo, hi}, jac, 1.0, scratch);
  CHECK(jac(0) == 1.5);
  CHECK(jac(1) == 1.5);
}

TEST_CASE("PGS clamps each lambda_j to [cmin_j, cmax_j] and solves the boxed LCP (6.2)",
          "[solver][eq6.2]") {
  const int n = 12;
  const SpMat A = random_spd(n, 42);
  std::mt19937 rng(1);
  std::normal_distribution<double> n01;
  // Build a solution by construction: rows 0..3 at cmin, 4..7 at cmax, the rest free.
  VecX cmin = VecX::Constant(n, -1.0);
  VecX cmax = VecX::Constant(n, 1.0);
  VecX star(n);
  VecX w(n);  // w = A λ* − b: ≥ 0 at cmin, ≤ 0 at cmax, 0 where free
  for (int k = 0; k < n; ++k) {
    if (k < 4) {
      star(k) = cmin(k);
      w(k) = std::abs(n01(rng)) + 0.1;
    } else if (k < 8) {
      star(k) = cmax(k);
      w(k) = -std::abs(n01(rng)) - 0.1;
    } else {
      star(k) = 0.5 * std::tanh(n01(rng));
      w(k) = 0.0;
    }
  }
  const VecX b = A * star - w;
  VecX lambda = VecX::Zero(n);
  SolverOptions options;
  options.max_iterations = 10000;
  options.tolerance = 1e-13;
  const SolverSummary s = solve_pgs(BoxedProblem{A, b, cmin, cmax}, lambda, options);
  INFO(s.message);
  CHECK((lambda - star).lpNorm<Eigen::Infinity>() < 1e-11);
  CHECK(natural_map_residual(BoxedProblem{A, b, cmin, cmax}, star) < 1e-13);
  for (int k = 0; k < n; ++k) {
    CHECK(lambda(k) >= cmin(k));
    CHECK(lambda(k) <= cmax(k));
  }
}

TEST_CASE("Jacobi converges on a diagonally dominant system and reports its sweeps", "[solver]") {
  // clang-format off
  MatX Ad(3, 3); Ad << 4, 1, 0,
                       1, 4, 1,
                       0, 1, 4;
  // clang-format on
  const SpMat A = Ad.sparseView();
  const VecX b(Eigen::Vector3d(1.0, 2.0, 3.0));
  const VecX exact = Ad.ldlt().solve(b);
  VecX lambda = VecX::Zero(3);
  SolverOptions options;
  options.max_iterations = 500;
  options.tolerance = 1e-14;
  const VecX cmin = VecX::Constant(3, -kInf), cmax = VecX::Constant(3, kInf);
  const SolverSummary s = solve_jacobi(BoxedProblem{A, b, cmin, cmax}, lambda, options);
  INFO(s.message);
  CHECK(s.termination == Termination::ResidualTolerance);
  CHECK(s.iterations > 1);
  CHECK((lambda - exact).lpNorm<Eigen::Infinity>() < 1e-13);
}

TEST_CASE("the iteration limit, the change tolerance and non-finite values end a solve",
          "[solver]") {
  const SpMat A = random_spd(6, 3);
  const VecX b = VecX::Ones(6);
  const VecX lo = VecX::Constant(6, -kInf);
  const VecX hi = VecX::Constant(6, kInf);
  VecX lambda = VecX::Zero(6);
  SolverOptions options;
  options.max_iterations = 3;
  CHECK(solve_pgs(BoxedProblem{A, b, lo, hi}, lambda, options).iterations == 3);
  options.max_iterations = 1000;
  options.delta_tolerance = 1e-9;
  lambda.setZero();
  const SolverSummary s = solve_pgs(BoxedProblem{A, b, lo, hi}, lambda, options);
  CHECK(s.termination == Termination::DeltaTolerance);
  CHECK(s.delta <= 1e-9);
  VecX bad_b = b;
  bad_b(2) = std::numeric_limits<double>::quiet_NaN();
  lambda.setZero();
  CHECK(solve_pgs(BoxedProblem{A, bad_b, lo, hi}, lambda, options).termination ==
        Termination::NonFinite);
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

TEST_CASE("symmetric Gauss-Seidel is a forward sweep then a backward sweep", "[solver][variants]") {
  const System sys = system_of("pyramid", {{"base", "3"}}, 2);
  std::vector<int> backward(static_cast<std::size_t>(sys.rows()));
  for (int k = 0; k < sys.rows(); ++k) backward[std::size_t(k)] = sys.rows() - 1 - k;
  VecX by_hand = VecX::Zero(sys.rows()), sgs = by_hand;
  SolverOptions options;
  options.max_iterations = 5;
  options.relaxation = 1.2;
  solve_sgs(sys.problem(), sgs, options);
  for (int k = 0; k < 5; ++k) {
    pgs_sweep(sys.problem(), by_hand, 1.2);
    pgs_sweep(sys.problem(), by_hand, 1.2, backward);
  }
  CHECK((sgs - by_hand).lpNorm<Eigen::Infinity>() == 0.0);  // the same operations
}

TEST_CASE("random row order: the seed fixes the iterates, another seed changes them",
          "[solver][variants]") {
  const System sys = system_of("stack", {{"n", "3"}}, 3);
  const auto run = [&](std::uint64_t seed) {
    SolverOptions options;
    options.order = RowOrder::Random;
    options.seed = seed;
    options.max_iterations = 7;
    VecX lambda = VecX::Zero(sys.rows());
    solve_pgs(sys.problem(), lambda, options);
    return lambda;
  };
  CHECK((run(1) - run(1)).lpNorm<Eigen::Infinity>() == 0.0);
  CHECK((run(1) - run(2)).lpNorm<Eigen::Infinity>() > 1e-6);
}

TEST_CASE("damping makes projected Jacobi converge where plain Jacobi diverges",
          "[solver][variants]") {
  // A = (1 − a) I + a 11ᵀ with a = 0.9 (3×3, definite): Jacobi's iteration matrix −a (11ᵀ − I)
  // has the eigenvalue −2a = −1.8, so plain Jacobi diverges; damped by omega its eigenvalues
  // are 1 − omega (1 + 2a) and 1 − omega (1 − a): omega = 0.3 gives 0.16 and 0.97, < 1.
  MatX dense = MatX::Constant(3, 3, 0.9);
  dense.diagonal().setOnes();
  const SpMat A = dense.sparseView();
  const VecX b = VecX::Ones(3);
  const VecX lo = VecX::Constant(3, -kInf), hi = VecX::Constant(3, kInf);
  SolverOptions options;
  options.max_iterations = 2000;
  options.tolerance = 1e-12;
  VecX plain = VecX::Zero(3), damped = VecX::Zero(3);
  options.relaxation = 1.0;
  const SolverSummary p = solve_jacobi(BoxedProblem{A, b, lo, hi}, plain, options);
  options.relaxation = 0.3;
  const SolverSummary d = solve_jacobi(BoxedProblem{A, b, lo, hi}, damped, options);
  CHECK(p.termination != Termination::ResidualTolerance);
  CHECK(d.termination == Termination::ResidualTolerance);
  const VecX exact = dense.ldlt().solve(b);  // 1 / (1 + 2a) each
  CHECK((damped - exact).lpNorm<Eigen::Infinity>() < 1e-11);
}
