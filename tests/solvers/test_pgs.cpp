// Projected Gauss-Seidel and Jacobi (7.1.1) against exact answers.
#include <catch2/catch.hpp>
#include <random>

#include "cbps/cbps.hpp"
#include "cbps/scene/builtin.hpp"
#include "cbps/step/simulation.hpp"

using namespace cbps;

namespace {
/// A random SPD matrix B Bᵀ + n I, dense entries, fixed seed.
SpMat random_spd(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01;
  MatX B(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) B(i, j) = n01(rng);
  const MatX A = B * B.transpose() + n * MatX::Identity(n, n);
  return A.sparseView();
}
}  // namespace

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

TEST_CASE("the natural-map residual is zero at a solution and positive elsewhere", "[solver]") {
  const SpMat A = random_spd(5, 9);
  const VecX b = VecX::LinSpaced(5, -1.0, 1.0);
  const VecX lo = VecX::Constant(5, -kInf);
  const VecX hi = VecX::Constant(5, kInf);
  const VecX x = MatX(A).ldlt().solve(b);
  CHECK(natural_map_residual(BoxedProblem{A, b, lo, hi}, x) < 1e-14);
  CHECK(natural_map_residual(BoxedProblem{A, b, lo, hi}, VecX::Zero(5)) == Approx(1.0));  // |b|∞
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

TEST_CASE("warm starting from last step's lambda by row id saves sweeps on a hanging chain",
          "[solver][simulation]") {
  Scene scene = make_builtin_scene("chain", {{"n", "20"}});
  // Hang it straight down and let it settle so consecutive steps have nearly equal lambda.
  for (std::size_t k = 0; k < scene.bodies.size(); ++k) {
    scene.bodies[k].x = Vec3(0.0, -0.1 * static_cast<double>(k + 1), 0.0);
  }
  scene.solver.tolerance = 1e-8;
  scene.solver.iterations = 100000;
  Scene cold_scene = scene;
  cold_scene.solver.warm_start = false;
  Simulation warm(scene);
  Simulation cold(cold_scene);
  long warm_sweeps = 0;
  long cold_sweeps = 0;
  for (int s = 0; s < 20; ++s) {
    warm_sweeps += warm.step().solver.iterations;
    cold_sweeps += cold.step().solver.iterations;
  }
  INFO("sweeps over 20 steps: warm " << warm_sweeps << ", cold " << cold_sweeps);
  CHECK(warm_sweeps * 2 < cold_sweeps);
}
