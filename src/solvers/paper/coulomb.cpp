// Coulomb friction bounds ±mu lambda_n (5.4) around any method: a fixed point of boxed problems.
#include "cbps/solvers/paper/coulomb.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "cbps/base/error.hpp"
#include "cbps/solvers/exact/direct.hpp"

namespace cbps {

namespace {

/// Moves each Coulomb row's bounds to cmin = −mu lambda_n, cmax = mu lambda_n (5.4); the other
/// rows keep theirs. Returns the largest change of a bound, N.
double move_bounds(const CoulombRows& coulomb, const VecX& lambda, VecX& cmin, VecX& cmax) {
  double change = 0.0;
  for (Eigen::Index k = 0; k < cmin.size(); ++k) {
    const int n = coulomb.normal_row[static_cast<std::size_t>(k)];
    if (n < 0) continue;
    const double bound = coulomb.mu(k) * std::max(0.0, lambda(n));
    change = std::max(change, std::abs(bound - cmax(k)));
    cmin(k) = -bound;
    cmax(k) = bound;
  }
  return change;
}

/// The fixed point for the direct path: solve the boxed problem, move the bounds, again, until
/// lambda solves the box its own normal rows give (5.4): its natural-map residual under the
/// bounds moved to it at most the rounding floor, 1e-12 max(1, ‖b‖∞), or the residual of a solve
/// that reached its floor (or the bounds stop moving). A sticking
/// contact's friction rows lie inside their box, so a move of the bounds that keeps them inside
/// changes nothing: a 1 kg cube resting on a 20° incline (four points, their normal forces not
/// unique) is a fixed point after one solve, where waiting for the bounds to stop moving took
/// 100 rounds and 1,792 factorizations and failed. `bounded` refers to cmin and cmax, which start
/// as the caller's bounds and move.
SolverSummary direct_fixed_point(const BoxedProblem& bounded,
                                 const CoulombRows& coulomb,
                                 VecX& cmin,
                                 VecX& cmax,
                                 VecX& lambda,
                                 const SolverOptions& options) {
  const VecX& b = bounded.b;
  const double scale = std::max(1.0, b.size() > 0 ? b.lpNorm<Eigen::Infinity>() : 0.0);
  SolverSummary total;
  int rounds = 0;
  double change = kInf;
  bool fixed = false;
  double solved_to = 0.0;  // the last solve's own residual where it reached its floor, N
  const auto floor_of = [&](const VecX& l) { return residual_floor(bounded, l); };
  while (rounds < 100) {
    change = move_bounds(coulomb, lambda, cmin, cmax);
    // λ solves the box of its own bounds as well as a solve that reached its floor solved its
    // box (a solve that stopped short is no such measure: then the rounds go on).
    if (rounds > 0 &&
        (change <= 1e-12 * scale || natural_map_residual(bounded, lambda) <=
                                        std::max({solved_to, 1e-12 * scale, floor_of(lambda)}))) {
      fixed = true;
      break;
    }
    const SolverSummary s = solve(bounded, lambda, options);
    ++rounds;
    solved_to = s.termination == Termination::Direct ? s.residual : 0.0;
    total.iterations += s.iterations;
    total.factorizations += s.factorizations;
    total.pivots += s.pivots;
    total.islands = s.islands;
    total.space = s.space;
    if (total.route.empty()) total.route = s.route;  // later rounds start from the round before
    total.singular = total.singular || s.singular;
    total.termination = s.termination;
    if (!s.ok() || s.termination == Termination::TimeLimit || past_deadline(options)) break;
  }
  if (!fixed && total.termination == Termination::Direct)
    total.termination = Termination::NotConverged;
  total.residual = natural_map_residual(bounded, lambda);  // A + eps E when cfm > 0
  // At the fixed point λ's own residual is the verdict: within the tolerance, or the rounding
  // floor, the solve reached it, whatever its last round's solve said of its own box.
  if (fixed && total.termination == Termination::NotConverged &&
      total.residual <= std::max(options.tolerance, residual_floor(bounded, lambda)))
    total.termination = Termination::Direct;
  std::ostringstream msg;
  msg << "direct with Coulomb bounds: " << (fixed ? "fixed point" : "no fixed point") << " in "
      << rounds << " rounds (last bound change " << change << " N), " << total.factorizations
      << " factorizations, residual under its own bounds " << total.residual << " N";
  total.message = msg.str();
  return total;
}

/// The methods whose sweep depends on nothing but lambda and the problem (the Gauss-Seidel and
/// Jacobi sweeps of 7.1.1 and their block and matrix-free forms): bounds moved between two sweeps
/// of one solve are what a new solve from that lambda would see. The others carry state from
/// sweep to sweep (momentum, a dual, a peer's own loop) and restart for every move.
bool sweeps_alone(Method method) {
  return method == Method::Pgs || method == Method::Sgs || method == Method::Jacobi ||
         method == Method::BlockPgs || method == Method::MatrixFree;
}

/// The iterative methods: the bounds follow lambda before every sweep (bounded, cmin, cmax as
/// for direct_fixed_point).
SolverSummary sweep_with_moving_bounds(const BoxedProblem& bounded,
                                       const CoulombRows& coulomb,
                                       VecX& cmin,
                                       VecX& cmax,
                                       VecX& lambda,
                                       const SolverOptions& options) {
  if (sweeps_alone(options.method)) {
    // One solve, the bounds moved after every sweep (after_sweep) through the references
    // `bounded` holds: a sweep under the Coulomb box then costs what a sweep under the paper's
    // box costs (one solve() a sweep, each with its two residuals, cost 1.4 times as much; with
    // the symmetry test as well, 3.7 times).
    SolverOptions moving = options;
    moving.split_islands = false;
    moving.after_sweep = [&coulomb, &cmin, &cmax, observer = options.after_sweep](
                             int sweeps, const VecX& l, double seconds) {
      move_bounds(coulomb, l, cmin, cmax);
      return !observer || observer(sweeps, l, seconds);
    };
    move_bounds(coulomb, lambda, cmin, cmax);
    SolverSummary s = solve(bounded, lambda, moving);
    std::ostringstream msg;
    msg << to_string(s.termination) << " after " << count_text(s.iterations, "sweep")
        << " with Coulomb bounds, residual " << s.residual << " N";
    s.message = msg.str();
    return s;
  }
  SolverOptions one = options;
  one.max_iterations = 1;
  one.split_islands = false;
  SolverSummary total;
  total.termination = Termination::MaxIterations;
  while (total.iterations < options.max_iterations) {
    move_bounds(coulomb, lambda, cmin, cmax);
    one.seed = options.seed * 1000003u + static_cast<std::uint64_t>(total.iterations);
    const SolverSummary s = solve(bounded, lambda, one);
    total.iterations += s.iterations;
    total.residual = s.residual;
    total.delta = s.delta;
    if (s.termination != Termination::MaxIterations) {
      total.termination = s.termination;
      break;
    }
  }
  std::ostringstream msg;
  msg << to_string(total.termination) << " after " << count_text(total.iterations, "sweep")
      << " with Coulomb bounds, residual " << total.residual << " N";
  total.message = msg.str();
  return total;
}

}  // namespace

void coulomb_bounds(const BoxedProblem& problem,
                    const CoulombRows& coulomb,
                    const VecX& lambda,
                    VecX& cmin,
                    VecX& cmax) {
  cmin = problem.cmin;
  cmax = problem.cmax;
  move_bounds(coulomb, lambda, cmin, cmax);
}

namespace {

/// f(the problem with the Coulomb bounds taken at lambda): A (+ cfm E, formed or through J and
/// Minv), b and the cones as they are.
template <class F>
auto at_own_bounds(const BoxedProblem& problem,
                   const CoulombRows& coulomb,
                   const VecX& lambda,
                   F&& f) {
  VecX cmin, cmax;
  coulomb_bounds(problem, coulomb, lambda, cmin, cmax);
  BoxedProblem bounded{problem.A, problem.b, cmin, cmax, problem.J, problem.Minv};
  bounded.cfm = problem.cfm;
  bounded.cones = problem.cones;
  return f(bounded);
}

}  // namespace

double coulomb_residual(const BoxedProblem& problem,
                        const CoulombRows& coulomb,
                        const VecX& lambda,
                        double cfm) {
  return at_own_bounds(problem, coulomb, lambda, [&](const BoxedProblem& p) {
    return natural_map_residual(p, lambda, cfm);
  });
}

UnitFreeResidual coulomb_unit_free(const BoxedProblem& problem,
                                   const CoulombRows& coulomb,
                                   const VecX& lambda,
                                   double cfm) {
  return at_own_bounds(problem, coulomb, lambda, [&](const BoxedProblem& p) {
    return unit_free_residual(p, lambda, cfm);
  });
}

SolverSummary solve_coulomb(const BoxedProblem& problem,
                            const CoulombRows& coulomb,
                            VecX& lambda,
                            const SolverOptions& options) {
  if (!coulomb.any()) return solve(problem, lambda, options);
  if (lambda.size() != problem.rows()) lambda = VecX::Zero(problem.rows());
  // Constraint-force mixing: A + eps E formed once here, not by solve() in every round.
  return with_cfm_applied(problem, options, [&](const BoxedProblem& p, const SolverOptions& o) {
    SolverSummary s;
    // The bounds move; the rest of the problem is the caller's.
    VecX cmin = p.cmin, cmax = p.cmax;
    BoxedProblem bounded{p.A, p.b, cmin, cmax};
    bounded.J = p.J;
    bounded.Minv = p.Minv;
    bounded.blocks = p.blocks;
    bounded.kinds = p.kinds;
    bounded.cfm = p.cfm;  // already in A (or in J Minv Jᵀ + cfm E when A was left out)
    // A's symmetry tested once here, not by solve() in every round or sweep (a sweep of the
    // Coulomb box cost 3.7 of the paper box's when every sweep tested it again).
    bounded.symmetric = p.symmetric;
    bounded.A_rows = p.A_rows;
    SpMat A_rows;
    if (!p.symmetric && p.A_formed()) {
      const double asymmetry = max_asymmetry(p.A);
      if (asymmetry <= kSymmetryTolerance || asymmetry <= symmetry_tolerance(p.A)) {
        bounded.symmetric = true;
      } else if (p.A_rows == nullptr) {
        A_rows = p.A.transpose();  // column k = row k of A, as solve() would form it
        bounded.A_rows = &A_rows;
      }
    }
    if (!is_iterative(o.method)) {
      s = direct_fixed_point(bounded, coulomb, cmin, cmax, lambda, o);
    } else {
      s = sweep_with_moving_bounds(bounded, coulomb, cmin, cmax, lambda, o);
    }
    return s;
  });
}

}  // namespace cbps
