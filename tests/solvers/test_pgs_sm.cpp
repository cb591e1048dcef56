// PGS with subspace minimization (Silcowitz, Niebe and Erleben, GRAPP 2010) against the direct
// path on real problems, its options contract, and what it is for: far fewer iterations than PGS
// once the active set is found.
#include <catch2/catch.hpp>
#include <cstdio>
#include <limits>
#include <map>
#include <random>
#include <stdexcept>
#include <string>

#include "cbps/solvers/compared/nncg.hpp"
#include "cbps/solvers/compared/pgs_sm.hpp"
#include "cbps/solvers/paper/pgs.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/system/boxed_problem.hpp"
#include "cbps/system/system.hpp"
#include "fixture.hpp"
#include "methods_fixture.hpp"

using namespace cbps;
using test::in_box;
using test::inf_norm;
using test::iterations_to;
using test::system_of;

namespace {

/// PGS-SM is asked for a natural-map residual of kRelative · scale_of on every problem here: it
/// gets there (measured: 25 iterations on the chain, 5,694 on the 10-box stack, 5,654 on the
/// base-4 pyramid), where PGS and NNCG stall above it on the contact problems. The scenes are
/// stepped with contact persistence off, the states these were measured on (methods_fixture.hpp).
constexpr double kRelative = 1e-10;

/// |w − w_direct|∞ and |v2 − v2_direct|∞ against that tolerance (6.2, 12.3.1): measured at most
/// 4.8 tolerances for w and 7.3 Δt tolerances for v2 (the chain, solved by CG to round-off,
/// 1e-5 of both); 2^8 as in test_every_solver_agrees.cpp.
constexpr double kWPerResidual = 256.0;
constexpr double kVelocityPerResidual = 256.0;

}  // namespace

TEST_CASE("PGS-SM reaches the direct path's w and v2 on a chain, a stack and a pyramid (6.2)",
          "[pgs-sm][solver][direct][eq6.2][eq12.3.1]") {
  const test::Problem c = GENERATE(values<test::Problem>({
      {"chain", {{"n", "20"}, {"mass_ratio", "10"}}, 10},
      {"stack", {{"n", "10"}, {"persistence", "0"}}, 30},
      {"pyramid", {{"base", "4"}, {"persistence", "0"}}, 30},
  }));
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
  options.tolerance = kRelative * scale;
  VecX lambda = VecX::Zero(sys.rows());
  const SolverSummary s = solve_pgs_sm(problem, lambda, options);
  INFO("pgs-sm: " << s.message);
  CHECK(s.termination == Termination::ResidualTolerance);
  CHECK(in_box(problem, lambda));
  const auto [dw, dv] = test::difference(sys, lambda, reference);
  INFO("|w - w_direct| " << dw << " m/s^2 (" << dw / options.tolerance << " tolerances), |v2 - "
                         << "v2_direct| " << dv << " m/s (" << dv / (sys.dt * options.tolerance)
                         << " dt tolerances)");
  CHECK(dw <= kWPerResidual * options.tolerance);
  CHECK(dv <= kVelocityPerResidual * sys.dt * options.tolerance);
}

TEST_CASE("PGS-SM: on a chain CG solves the free rows in far fewer iterations than PGS (6.2.9)",
          "[pgs-sm][solver][eq6.2.9]") {
  // The chain's rows are all free (unbounded links) and A is definite: after the 5 PGS sweeps
  // of the first phase, CG on A(F,F) = A (20 rows) converges in at most 20 steps in exact
  // arithmetic. Measured to 1e-10 · scale: PGS-SM 25 iterations (5 sweeps and 20 CG steps) with
  // 1 CG start, PGS 5,071 sweeps.
  const System sys = system_of("chain", {{"n", "20"}, {"mass_ratio", "10"}}, 10);
  const BoxedProblem problem = sys.problem();
  SolverOptions options;
  options.max_iterations = 100000;
  options.tolerance = kRelative * scale_of(problem);
  VecX sm = VecX::Zero(sys.rows()), pgs = sm;
  const SolverSummary s = solve_pgs_sm(problem, sm, options);
  const SolverSummary p = solve_pgs(problem, pgs, options);
  INFO("pgs-sm: " << s.message << "; pgs: " << p.message);
  REQUIRE(s.termination == Termination::ResidualTolerance);
  REQUIRE(p.termination == Termination::ResidualTolerance);
  CHECK(s.iterations <= PgsSmSettings{}.pgs_sweeps + sys.rows());
  CHECK(s.restarts == 1);
  CHECK(10 * s.iterations <= p.iterations);
}

TEST_CASE("PGS-SM finds a constructed active set: rows at cmin, at cmax and free (6.2)",
          "[pgs-sm][solver][eq6.2]") {
  // Positive definite problems with a known solution mixing every kind of row (fixture
  // construct): lambda is unique, so it is compared itself, against lambda_star.
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    const test::Constructed p = test::construct(12, 16, rng);
    const BoxedProblem problem{p.A, p.b, p.lo, p.hi};
    SolverOptions options;
    options.max_iterations = 100000;
    options.tolerance = 1e-12 * test::scale_of(p.A, p.b);
    VecX lambda = VecX::Zero(12);
    const SolverSummary s = solve_pgs_sm(problem, lambda, options);
    CAPTURE(trial, s.message);
    REQUIRE(s.termination == Termination::ResidualTolerance);
    // A = J Jᵀ with 16 > 12 columns is definite (almost surely): lambda is unique, and 1e-8 ·
    // scale leaves its conditioning room above the 1e-12 residual.
    CHECK(inf_norm(lambda - p.lambda_star) <= 1e-8 * test::scale_of(p.A, p.b));
  }
}

TEST_CASE("measure: iterations to 1e-6 and 1e-10 relative for PGS, NNCG and PGS-SM",
          "[.pgs-sm-measure]") {
  const int limit = 200000;
  for (const test::Problem& c :
       {test::Problem{"chain", {{"n", "20"}, {"mass_ratio", "10"}}, 10},
        test::Problem{"stack", {{"n", "10"}, {"persistence", "0"}}, 30},
        test::Problem{"pyramid", {{"base", "6"}, {"persistence", "0"}}, 30},
        test::Problem{"pyramid", {{"base", "4"}, {"persistence", "0"}}, 30}}) {
    const System sys = system_of(c.name, c.values, c.steps);
    const BoxedProblem problem = sys.problem();
    for (const double relative : {1e-6, 1e-10}) {
      const int pgs = iterations_to(problem, relative, limit, solve_pgs);
      const int nncg = iterations_to(
          problem, relative, limit, [](const BoxedProblem& p, VecX& l, const SolverOptions& o) {
            return solve_nncg(p, l, o);
          });
      const int sm = iterations_to(
          problem, relative, limit, [](const BoxedProblem& p, VecX& l, const SolverOptions& o) {
            return solve_pgs_sm(p, l, o);
          });
      std::printf("%-8s rows %4ld  %.0e: pgs %7d  nncg %7d  pgs-sm %7d\n",
                  c.name.c_str(),
                  static_cast<long>(sys.rows()),
                  relative,
                  pgs,
                  nncg,
                  sm);
    }
  }
}
