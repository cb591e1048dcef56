// Accelerated projected gradient descent (apgd.hpp; Mazhar, Heyn, Negrut, Tasora, ACM TOG 2015):
// it reaches the direct path's w and v2 on real problems, it keeps the sweep loop's contract, its
// first step is the projected gradient step with L = ‖A‖∞, it restarts and counts the restarts,
// and it returns the best iterate it saw.
#include <algorithm>
#include <catch2/catch.hpp>
#include <limits>
#include <vector>

#include "cbps/solvers/compared/apgd.hpp"
#include "cbps/solvers/paper/pgs.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/system/boxed_problem.hpp"
#include "cbps/system/system.hpp"
#include "fixture.hpp"
#include "methods_fixture.hpp"

using namespace cbps;
using test::Problem;

TEST_CASE("APGD reaches the direct path's w and v2 (6.2, 12.3.1)",
          "[apgd][direct][eq6.2][eq12.3.1]") {
  const Problem p = GENERATE(values<Problem>({test::kChain, test::kStack, test::kPyramid}));
  const System sys = test::system_of(p.name, p.values, p.steps);
  const BoxedProblem problem = sys.problem();
  SolverOptions options;
  options.max_iterations = 40000;  // measured need: 422 (chain), 3688 (stack), 85 (pyramid)
  options.tolerance = test::kSweepTolerance * test::kEps * scale_of(problem);
  const VecX reference = test::direct_solution(sys, options.tolerance);
  VecX lambda = VecX::Zero(sys.rows());
  const SolverSummary s = solve_apgd(problem, lambda, options);
  INFO(p.name << ", " << sys.rows() << " rows: " << s.message);
  REQUIRE(s.termination == Termination::ResidualTolerance);
  CHECK(natural_map_residual(problem, lambda) <= options.tolerance);
  // w = A λ − b is unique even where λ is not (A singular, 6.2). Measured |w − w_direct|∞ /
  // tolerance: 0.96 (chain), 31.7 (stack), 1.04 (pyramid); at bound rows the residual is the
  // distance to the bound, not |w|, hence the stack's larger ratio. kW = 2^9 leaves ten times the
  // most. v2 (bound from test_every_solver_agrees.cpp): measured at most 42.5 Δt tolerances, on the
  // stack.
  const double kW = 512.0;
  const test::Difference d = test::difference(sys, lambda, reference);
  const double w_error = d.w;
  const double v2_error = d.v2;
  INFO("|w - w_direct| " << w_error << " m/s^2 (" << w_error / options.tolerance
                         << " tolerances), |v2 - v2_direct| " << v2_error << " m/s ("
                         << v2_error / (sys.dt * options.tolerance) << " dt tolerances)");
  CHECK(w_error <= kW * options.tolerance);
  CHECK(v2_error <= test::kVelocityPerResidual * sys.dt * options.tolerance);
}

TEST_CASE("APGD's first step is the projected gradient step with L = the largest row sum of A",
          "[apgd][eq6.2]") {
  // From λ_0 = y_0: λ_1 = clamp(λ_0 − (A λ_0 − b) / L, cmin, cmax), L = ‖A‖∞ ≥ the largest
  // eigenvalue of A (Gershgorin), so the backtracking test ½ dᵀAd ≤ ½ L dᵀd holds at once.
  const System sys = test::system_of("stack", {{"n", "3"}, {"mu", "0.5"}}, 10);
  const BoxedProblem problem = sys.problem();
  double L = 0.0;
  for (Eigen::Index k = 0; k < sys.A.outerSize(); ++k)
    L = std::max(L, VecX(MatX(sys.A).col(k)).lpNorm<1>());
  VecX lambda0 = VecX::Constant(sys.rows(), 1.0).cwiseMax(sys.cmin).cwiseMin(sys.cmax);
  const VecX w0 = sys.A * lambda0 - sys.b;
  VecX expected(sys.rows());
  for (Eigen::Index k = 0; k < sys.rows(); ++k)
    expected(k) = clamp(lambda0(k) - w0(k) / L, sys.cmin(k), sys.cmax(k));
  SolverOptions options;
  options.max_iterations = 1;
  VecX lambda = lambda0;
  std::vector<VecX> iterates;
  options.after_sweep = [&](int, const VecX& l, double) {
    iterates.push_back(l);
    return true;
  };
  solve_apgd(problem, lambda, options);
  REQUIRE(iterates.size() == 1);
  CHECK((iterates[0] - expected).lpNorm<Eigen::Infinity>() <=
        4 * test::kEps * expected.lpNorm<Eigen::Infinity>());  // L summed in another order
}

TEST_CASE("APGD restarts and counts it, and returns the iterate of smallest residual it saw",
          "[apgd][eq6.2]") {
  // Measured on the 10-box stack to a relative residual 1e-10: 3788 iterations, 4363 products
  // with A, 8 restarts. Stopped early at 300 iterations the last iterate need not be the best:
  // the returned lambda must be the best of all iterates the hook saw (and the start).
  const System sys = test::system_of(test::kStack.name, test::kStack.values, test::kStack.steps);
  const BoxedProblem problem = sys.problem();
  SolverOptions options;
  options.max_iterations = 300;
  double smallest = natural_map_residual(problem, VecX::Zero(sys.rows()));
  double last = 0.0;
  options.after_sweep = [&](int, const VecX& l, double) {
    last = natural_map_residual(problem, l);
    smallest = std::min(smallest, last);
    return true;
  };
  VecX lambda = VecX::Zero(sys.rows());
  const SolverSummary s = solve_apgd(problem, lambda, options);
  INFO(s.message << "\nlast iterate's residual " << last << " N, smallest " << smallest << " N");
  CHECK(s.restarts > 0);
  CHECK(s.message.find(std::to_string(s.restarts) + " restarts") != std::string::npos);
  CHECK(natural_map_residual(problem, lambda) == smallest);
  CHECK(s.residual == smallest);

  ApgdSettings never;
  never.restart = false;
  options.after_sweep = nullptr;
  lambda.setZero();
  CHECK(solve_apgd(problem, lambda, options, never).restarts == 0);
}
