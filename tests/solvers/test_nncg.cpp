// The nonsmooth nonlinear conjugate gradient method (Silcowitz-Hansen, Niebe and Erleben, The
// Visual Computer 2010) against the direct path on real problems, its options contract, and what
// defines it: PGS sweeps with a Fletcher–Reeves momentum that restarts when beta > 1.
#include <algorithm>
#include <catch2/catch.hpp>
#include <limits>
#include <map>
#include <string>

#include "cbps/solvers/compared/nncg.hpp"
#include "cbps/solvers/paper/pgs.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/system/boxed_problem.hpp"
#include "cbps/system/system.hpp"
#include "fixture.hpp"
#include "methods_fixture.hpp"

using namespace cbps;
using test::in_box;
using test::inf_norm;
using test::system_of;

namespace {

/// w = A lambda − b is unique where lambda is not (6.2); its distance from the direct path's is
/// held to kWPerResidual times the residual NNCG stopped at. Measured ratio |Δw|∞ / tolerance:
/// 0.98 on the chain, 2.1 on the stack, 1.0 on the pyramid; 2^8 leaves room above the largest.
constexpr double kWPerResidual = 256.0;

/// v2 against the residual, as in test_every_solver_agrees.cpp: |Δv2| ≈ Δt |Δw| through the
/// M-weighted right inverse of J. Measured |Δv2|∞ / (Δt · tolerance): 21, 6.7, 6.2; 2^8 as there.
constexpr double kVelocityPerResidual = 256.0;

/// The three fixture problems and the residual, relative to scale_of, NNCG is asked for on each.
/// NNCG reaches 1e-10 on the chain (352 iterations) but not on the singular contact problems
/// within 200,000 iterations (neither does PGS); 1e-6 it reaches on the stack in 37,424
/// iterations (PGS 59,543) and on the base-4 pyramid in 86 (PGS 358). The scenes are stepped with
/// contact persistence off, the states these were measured on (methods_fixture.hpp).
struct Case {
  test::Problem scene;
  double relative;
};

}  // namespace

TEST_CASE("NNCG reaches the direct path's w and v2 on a chain, a stack and a pyramid (6.2)",
          "[nncg][solver][direct][eq6.2][eq12.3.1]") {
  const Case the = GENERATE(values<Case>({
      {{"chain", {{"n", "20"}, {"mass_ratio", "10"}}, 10}, 1e-10},
      {{"stack", {{"n", "10"}, {"persistence", "0"}}, 30}, 1e-6},
      {{"pyramid", {{"base", "4"}, {"persistence", "0"}}, 30}, 1e-6},
  }));
  const test::Problem& c = the.scene;
  const System sys = system_of(c.name, c.values, c.steps);
  const BoxedProblem problem = sys.problem();
  const double scale = scale_of(problem);
  INFO(c.name << " after " << c.steps << " steps: " << sys.rows() << " rows, scale " << scale);

  SolverOptions direct;
  direct.method = Method::Direct;
  VecX reference = VecX::Zero(sys.rows());
  const SolverSummary sd = solve(problem, reference, direct);
  INFO("direct: " << sd.message);
  REQUIRE(sd.termination == Termination::Direct);

  SolverOptions options;
  options.max_iterations = 100000;
  options.tolerance = the.relative * scale;
  VecX lambda = VecX::Zero(sys.rows());
  const SolverSummary s = solve_nncg(problem, lambda, options);
  INFO("nncg: " << s.message);
  CHECK(s.termination == Termination::ResidualTolerance);
  const auto [dw, dv] = test::difference(sys, lambda, reference);
  INFO("|w - w_direct| " << dw << " m/s^2 (" << dw / options.tolerance << " tolerances), |v2 - "
                         << "v2_direct| " << dv << " m/s (" << dv / (sys.dt * options.tolerance)
                         << " dt tolerances)");
  CHECK(in_box(problem, lambda));
  CHECK(dw <= kWPerResidual * options.tolerance);
  CHECK(dv <= kVelocityPerResidual * sys.dt * options.tolerance);
}

TEST_CASE("NNCG restarts when beta > 1, counts it, and without momentum it is PGS (7.1.1)",
          "[nncg][solver][eq7.1.1]") {
  const System sys = system_of("chain", {{"n", "20"}, {"mass_ratio", "10"}}, 10);
  const BoxedProblem problem = sys.problem();
  SolverOptions options;
  options.max_iterations = 100000;
  options.tolerance = 1e-10 * scale_of(problem);
  VecX lambda = VecX::Zero(sys.rows());
  const SolverSummary nncg = solve_nncg(problem, lambda, options);
  VecX pgs_lambda = VecX::Zero(sys.rows());
  const SolverSummary pgs = solve_pgs(problem, pgs_lambda, options);
  INFO("nncg: " << nncg.message << "; pgs: " << pgs.message);
  REQUIRE(nncg.termination == Termination::ResidualTolerance);
  REQUIRE(pgs.termination == Termination::ResidualTolerance);
  // The paper's claim, NNCG converges in fewer iterations than PGS; measured 352 against
  // 5,071 (8 restarts). Asked: at most a quarter.
  CHECK(4 * nncg.iterations <= pgs.iterations);
  CHECK(nncg.restarts > 0);
  CHECK(nncg.restarts < nncg.iterations);

  // restart_beta = 0 restarts at every iteration: beta = 0, p_k = r_k, lambda_{k+1} =
  // clamp(lambda_k + (PGS(lambda_k) − lambda_k)) = PGS(lambda_k) up to the rounding of that sum.
  NncgSettings always;
  always.restart_beta = 0.0;
  SolverOptions few;
  few.max_iterations = 50;
  VecX a = VecX::Zero(sys.rows()), b = a;
  const SolverSummary s = solve_nncg(problem, a, few, always);
  solve_pgs(problem, b, few);
  CHECK(s.restarts == 49);  // every iteration after the first
  // 50 sweeps, each adding a few ulps of max |lambda|.
  CHECK(inf_norm(a - b) <= 1e-12 * std::max(1.0, inf_norm(b)));
  // A restart threshold never met: no restart counted.
  NncgSettings never;
  never.restart_beta = std::numeric_limits<double>::infinity();
  VecX c = VecX::Zero(sys.rows());
  CHECK(solve_nncg(problem, c, few, never).restarts == 0);
}
