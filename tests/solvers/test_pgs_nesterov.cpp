// PGS with Nesterov momentum and adaptive restart (pgs_nesterov.hpp; O'Donoghue & Candès 2015):
// it reaches the direct path's w and v2 on real problems, it keeps the sweep loop's contract, its
// first two iterations are the formula's, it restarts and counts the restarts, and it needs far
// fewer sweeps than plain PGS (7.1.1).
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "cbps/solvers/compared/apgd.hpp"
#include "cbps/solvers/compared/pgs_nesterov.hpp"
#include "cbps/solvers/paper/pgs.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/system/boxed_problem.hpp"
#include "cbps/system/system.hpp"
#include "fixture.hpp"
#include "methods_fixture.hpp"

using namespace cbps;
using test::Problem;

namespace {

SolverSummary nesterov(const BoxedProblem& problem, VecX& lambda, const SolverOptions& options) {
  return solve_pgs_nesterov(problem, lambda, options);
}

SolverSummary apgd(const BoxedProblem& problem, VecX& lambda, const SolverOptions& options) {
  return solve_apgd(problem, lambda, options);
}

}  // namespace

TEST_CASE("PGS with Nesterov momentum reaches the direct path's w and v2 (7.1.1, 6.2, 12.3.1)",
          "[pgs-nesterov][direct][eq6.2][eq12.3.1]") {
  const Problem p = GENERATE(values<Problem>({test::kChain, test::kStack, test::kPyramid}));
  const System sys = test::system_of(p.name, p.values, p.steps);
  const BoxedProblem problem = sys.problem();
  SolverOptions options;
  options.max_iterations = 20000;  // measured need: 244 (chain), 1339 (stack), 82 (pyramid)
  options.tolerance = test::kSweepTolerance * test::kEps * scale_of(problem);
  const VecX reference = test::direct_solution(sys, options.tolerance);
  VecX lambda = VecX::Zero(sys.rows());
  const SolverSummary s = solve_pgs_nesterov(problem, lambda, options);
  INFO(p.name << ", " << sys.rows() << " rows: " << s.message);
  REQUIRE(s.termination == Termination::ResidualTolerance);
  CHECK(natural_map_residual(problem, lambda) <= options.tolerance);
  // w = A λ − b is unique even where λ is not (A singular, 6.2). Measured |w − w_direct|∞ /
  // tolerance: 0.94 (chain), 20.3 (stack), 0.75 (pyramid); at bound rows the residual is the
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

TEST_CASE("the first two iterations: a plain sweep, then a sweep from the extrapolated point",
          "[pgs-nesterov][eq7.1.1]") {
  // t_1 = 1 gives β_1 = 0: iteration 1 is one PGS sweep. Iteration 1 never restarts (y = λ_0,
  // so (y − λ_1)ᵀ(λ_1 − λ_0) = −‖λ_1 − λ_0‖² ≤ 0), so iteration 2 extrapolates with
  // β_2 = (t_2 − 1) / t_3, t_2 = (1 + √5)/2, t_3 = (1 + √(1 + 4 t_2²))/2 (≈ 0.2818).
  const System sys = test::system_of("stack", {{"n", "3"}, {"mu", "0.5"}}, 10);
  const BoxedProblem problem = sys.problem();
  const VecX lambda0 = VecX::Zero(sys.rows());
  VecX lambda1 = lambda0;
  pgs_sweep(problem, lambda1);
  const double t2 = 0.5 * (1.0 + std::sqrt(5.0));
  const double t3 = 0.5 * (1.0 + std::sqrt(1.0 + 4.0 * t2 * t2));
  const double beta2 = (t2 - 1.0) / t3;
  VecX lambda2 = (lambda1 + beta2 * (lambda1 - lambda0)).cwiseMax(sys.cmin).cwiseMin(sys.cmax);
  pgs_sweep(problem, lambda2);

  SolverOptions options;
  options.max_iterations = 1;
  VecX lambda = lambda0;
  solve_pgs_nesterov(problem, lambda, options);
  CHECK((lambda - lambda1).lpNorm<Eigen::Infinity>() == 0.0);
  options.max_iterations = 2;
  lambda = lambda0;
  solve_pgs_nesterov(problem, lambda, options);
  INFO("iteration 2 differs from the plain sweep's by "
       << (lambda2 - lambda1).lpNorm<Eigen::Infinity>() << " N");
  CHECK((lambda - lambda2).lpNorm<Eigen::Infinity>() == 0.0);  // the same operations
}

TEST_CASE("the restart fires and is counted, and momentum needs far fewer sweeps than PGS",
          "[pgs-nesterov][eq7.1.1]") {
  // Measured on the 20-link chain (mass ratio 10) to a relative residual 1e-10: plain PGS 5071
  // sweeps, with momentum and restart 254 sweeps and 4 restarts. O'Donoghue & Candès: momentum
  // turns the O(κ) iterations of a gradient method into O(√κ); the assertion asks for 5 times
  // fewer sweeps, a quarter of the measured 20.
  const System sys = test::system_of(test::kChain.name, test::kChain.values, test::kChain.steps);
  const BoxedProblem problem = sys.problem();
  SolverOptions options;
  options.max_iterations = 100000;
  options.tolerance = 1e-10 * scale_of(problem);
  VecX plain = VecX::Zero(sys.rows());
  const SolverSummary p = solve_pgs(problem, plain, options);
  VecX accelerated = VecX::Zero(sys.rows());
  const SolverSummary a = solve_pgs_nesterov(problem, accelerated, options);
  INFO("pgs: " << p.message << "\n" << a.message);
  REQUIRE(p.termination == Termination::ResidualTolerance);
  REQUIRE(a.termination == Termination::ResidualTolerance);
  CHECK(5 * a.iterations < p.iterations);
  CHECK(a.restarts > 0);
  CHECK(a.message.find(std::to_string(a.restarts) + " restarts") != std::string::npos);

  // Without the restart, none is counted.
  PgsNesterovSettings never;
  never.restart = false;
  VecX unrestarted = VecX::Zero(sys.rows());
  options.max_iterations = 50;
  CHECK(solve_pgs_nesterov(problem, unrestarted, options, never).restarts == 0);
}

TEST_CASE("accelerated PGS and APGD against plain PGS: iterations to 1e-6 and 1e-10 (7.1.1)",
          "[.][accel-table]") {
  // The table of the report: build/release/tests/cbps_tests "[accel-table]". −1: not reached.
  for (const Problem& p : {test::kChain, test::kStack, test::kPyramid}) {
    const System sys = test::system_of(p.name, p.values, p.steps);
    for (const double relative : {1e-6, 1e-10}) {
      const int limit = 1000000;
      std::printf("%-8s %3ld rows  relative %.0e: pgs %6d  pgs-nesterov %5d  apgd %5d\n",
                  p.name.c_str(),
                  long(sys.rows()),
                  relative,
                  test::iterations_to(sys.problem(), relative, limit, solve_pgs),
                  test::iterations_to(sys.problem(), relative, limit, nesterov),
                  test::iterations_to(sys.problem(), relative, limit, apgd));
    }
  }
}
