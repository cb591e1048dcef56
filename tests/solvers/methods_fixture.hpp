// What the tests of the methods PGS is compared with (pgs-nesterov, apgd, nncg, pgs-sm, admm,
// rbgs) and of the solve contract share: the fixture's problems, the direct path's answer on
// them, the bounds a solve to a tolerance is held to, the count of iterations to a relative
// residual, and whether a λ lies in the box.
#pragma once

#include <catch2/catch.hpp>
#include <limits>
#include <map>
#include <string>

#include "cbps/solvers/solver.hpp"
#include "cbps/system/boxed_problem.hpp"
#include "cbps/system/system.hpp"
#include "fixture.hpp"

namespace cbps::test {

/// A built-in scene's system after some steps.
struct Problem {
  std::string name;
  std::map<std::string, std::string> values;
  int steps;
};

/// The 20-link chain with end-mass ratio 10, falling (A definite, 20 rows), as in
/// test_every_solver_agrees.cpp.
inline const Problem kChain{"chain", {{"n", "20"}, {"mass_ratio", "10"}}, 10};
/// The stepped scenes below are stepped with contact persistence off (persistence=0: rows are
/// matched from step to step by feature id), the states the methods' numbers were measured on.
/// Persistence changes the warm starts and so the state reached: at step 20 the stack's problem
/// is then a harder one at 1e-10 (measured: apgd 1.3e-7 N and pgs-nesterov 6.1e-8 N after 40,000
/// sweeps, against 3,633 sweeps to 1e-10 N for apgd here).
///
/// A column of 10 boxes with the paper's friction, mu = 0.5, settled at step 20 (four contacts a
/// face: A singular, only w and v2 unique).
inline const Problem kStack{"stack", {{"n", "10"}, {"mu", "0.5"}, {"persistence", "0"}}, 20};
/// The small pyramid, base 3 (6 boxes), at step 20 (A singular).
inline const Problem kPyramid{"pyramid", {{"base", "3"}, {"persistence", "0"}}, 20};

inline constexpr double kEps = std::numeric_limits<double>::epsilon();

/// The tolerance the methods are asked to stop at, as a multiple of ε · scale_of(problem):
/// 2^20 ε ≈ 2.3e-10 of the problem's scale, the sweep tolerance of test_every_solver_agrees.cpp.
inline constexpr double kSweepTolerance = 1048576.0;  // 2^20

/// v2 against the residual (test_every_solver_agrees.cpp derives it): J (v2 − v2_direct) =
/// Δt (w − w_direct), so a residual r moves v2 by about Δt r; measured there at most 23.5 Δt r,
/// 2^8 leaves ten times that.
inline constexpr double kVelocityPerResidual = 256.0;

/// The direct path's solution of a system at tolerance 0 (down to its rounding floor): the
/// reference. On the settled stack and pyramid its active-set path ends NotConverged at a residual
/// near 1e-10 N (measured 1.2e-10 and 1.0e-10 at step 20; 5.5e-11 N on the base-3 pyramid at
/// step 30): the reference is held to 1/fraction of the tolerance the methods under test are
/// asked for, not to its own floor.
inline VecX direct_solution(const System& sys, double tolerance, double fraction = 8.0) {
  SolverOptions direct;
  direct.method = Method::Direct;
  VecX lambda = VecX::Zero(sys.rows());
  const SolverSummary s = solve(sys.problem(), lambda, direct);
  INFO("reference: " << s.message);
  INFO("reference residual " << natural_map_residual(sys.problem(), lambda) << " N, tolerance "
                             << tolerance << " N");
  REQUIRE(natural_map_residual(sys.problem(), lambda) <= tolerance / fraction);
  return lambda;
}

/// How far λ is from the reference in what is unique even where λ is not (A singular, 6.2):
/// w = A λ − b (m/s²) and v2 (m/s, 12.3.1), as ∞-norms.
struct Difference {
  double w = 0.0;
  double v2 = 0.0;
};
inline Difference difference(const System& sys, const VecX& lambda, const VecX& reference) {
  return {(sys.A * (lambda - reference)).lpNorm<Eigen::Infinity>(),
          (compute_v2(sys, lambda) - compute_v2(sys, reference)).lpNorm<Eigen::Infinity>()};
}

/// ‖v‖∞.
inline double inf_norm(const VecX& v) { return v.lpNorm<Eigen::Infinity>(); }

/// Whether λ lies in [cmin, cmax] (every iterate of a projected method must).
inline bool in_box(const BoxedProblem& p, const VecX& lambda) {
  for (Eigen::Index k = 0; k < p.rows(); ++k)
    if (!(p.cmin(k) <= lambda(k) && lambda(k) <= p.cmax(k))) return false;
  return true;
}

/// Iterations a method takes from lambda = 0 to a relative natural-map residual
/// (residual / scale_of(problem) ≤ relative), or −1 when it does not get there within `limit`.
template <class Solve>
int iterations_to(const BoxedProblem& problem, double relative, int limit, Solve run) {
  SolverOptions options;
  options.max_iterations = limit;
  options.tolerance = relative * scale_of(problem);
  VecX lambda = VecX::Zero(problem.rows());
  const SolverSummary s = run(problem, lambda, options);
  return s.termination == Termination::ResidualTolerance ? s.iterations : -1;
}

}  // namespace cbps::test
