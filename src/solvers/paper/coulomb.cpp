// Coulomb friction bounds ±mu lambda_n (5.4) around any method: a fixed point of boxed problems.
#include "cbps/solvers/paper/coulomb.hpp"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "cbps/base/error.hpp"
#include "cbps/solvers/exact/direct.hpp"
#include "cbps/solvers/methods.hpp"

namespace cbps {

namespace {

/// Moves each Coulomb row's bounds to cmin = −mu lambda_n, cmax = mu lambda_n (5.4); the other
/// rows keep theirs. Returns the largest change of a bound, N.
double move_bounds(const CoulombRows& coulomb, const VecX& lambda, VecX& cmin, VecX& cmax) {
  double change = 0.0;
  if (!coulomb.any()) return change;
  const FrictionContacts& contacts = *coulomb.contacts;
  for (long i = 0; i < contacts.contacts(); ++i) {
    const int n = contacts.normal[static_cast<std::size_t>(i)];
    const double bound = coulomb_bound(contacts.mu(i), lambda(n));
    for (const int k : {n + 1, n + 2}) {  // its friction rows t1, t2
      change = std::max(change, std::abs(bound - cmax(k)));
      cmin(k) = -bound;
      cmax(k) = bound;
    }
  }
  return change;
}

/// Row k's contact row under Coulomb's box, −1 for the other rows; and its coefficient.
void coulomb_rows(const CoulombRows& coulomb,
                  Eigen::Index rows,
                  std::vector<int>& normal,
                  VecX& mu) {
  normal.assign(static_cast<std::size_t>(rows), -1);
  mu = VecX::Zero(rows);
  if (!coulomb.any()) return;
  for (long i = 0; i < coulomb.contacts->contacts(); ++i) {
    const int n = coulomb.contacts->normal[static_cast<std::size_t>(i)];
    for (const int k : {n + 1, n + 2}) {
      normal[static_cast<std::size_t>(k)] = n;
      mu(k) = coulomb.contacts->mu(i);
    }
  }
}

/// Newton's steps on the Coulomb box's own natural map, its bounds taken at λ (5.4):
///   F_k(λ) = λ_k − clamp(λ_k − ρ_k w_k, l_k(λ), u_k(λ)),  w = A λ − b,  ρ_k = 1/A_kk (kg),
/// with l_k = −u_k = −mu_k max(0, λ_n) for a Coulomb row k of contact row n and the caller's
/// bounds for every other row. F is piecewise linear, so semismooth (Qi & Sun, Math. Program. 58,
/// 1993); an element of its generalized Jacobian takes per row ρ_k (row k of A) where the clamp is
/// inside its box, e_k where a fixed bound holds it, and e_k ∓ mu_k e_n where a Coulomb bound
/// ±mu_k λ_n does (the friction force follows its normal force). Each step: Newton's where G is
/// regular and the step lowers ‖F‖² by Armijo's fraction along t = 1, 1/2, ...; else
/// Levenberg–Marquardt's, (GᵀG + ‖F‖ I) d = −Gᵀ F (Fan & Yuan, Computing 74, 2005: fast near
/// answers that are not isolated, as on a singular A). This finishes where moving the bounds and
/// solving the box again cycles (pgs's card-house states: bounds moving by 1 N after 100 rounds).
/// Ends at `target` (N, the natural map of 6.2 under the bounds at λ), after kBoxNewtonSteps
/// steps, or where neither step descends; λ becomes the point of least residual, returned.
constexpr int kBoxNewtonSteps = 50;
/// Newton's steps reach the rounding floor of the box's exact solve (residual_floor) only to
/// within a few times it: their last steps solve with an LU of the generalized Jacobian, not the
/// box's Cholesky, and end where no step lowers ‖F‖ (slide on an incline: 1e-11 N against a
/// floor of 4e-12 N). Their answer stands at this many times that floor.
constexpr double kNewtonFloor = 10.0;
/// The fixed point's rounds at most, and the rounds in a row that do not halve λ's residual
/// under its own bounds after which Newton's steps take over.
constexpr int kMaxRounds = 100;
constexpr int kStalledRounds = 5;
constexpr double kBoxArmijo = 1e-4;

double coulomb_box_newton(const BoxedProblem& bounded,
                          const CoulombRows& coulomb,
                          VecX& cmin,
                          VecX& cmax,
                          double target,
                          VecX& lambda) {
  const SpMat A = formed_A(bounded);
  const Eigen::Index c = bounded.rows();
  std::vector<int> normal_of;  // row k's contact row, −1 for a row with fixed bounds
  VecX mu_of;
  coulomb_rows(coulomb, c, normal_of, mu_of);
  VecX rho(c);
  for (Eigen::Index k = 0; k < c; ++k) {
    const double a = A.coeff(k, k);
    rho(k) = a > 0.0 ? 1.0 / a : 1.0;
  }
  // F at x, and where G is wanted the rows' cases: 0 inside, 1 at a fixed bound, ±2 at the
  // Coulomb bound ±mu λ_n.
  std::vector<int> kind(static_cast<std::size_t>(c));
  const auto map = [&](const VecX& x, bool record) {
    VecX lo = cmin, hi = cmax;
    move_bounds(coulomb, x, lo, hi);
    const VecX w = A * x - bounded.b;
    VecX F(c);
    for (Eigen::Index k = 0; k < c; ++k) {
      const double z = x(k) - rho(k) * w(k);
      const double y = clamp(z, lo(k), hi(k));
      F(k) = x(k) - y;
      if (!record) continue;
      const bool moving = normal_of[static_cast<std::size_t>(k)] >= 0;
      int& at = kind[static_cast<std::size_t>(k)];
      at = z > lo(k) && z < hi(k) ? 0 : !moving ? 1 : z >= hi(k) ? 2 : -2;
    }
    return F;
  };
  const auto residual_at = [&](const VecX& x) {
    move_bounds(coulomb, x, cmin, cmax);
    return natural_map_residual(bounded, x);
  };
  VecX best = lambda;
  double best_r = residual_at(lambda);
  Eigen::SparseLU<SpMat, Eigen::COLAMDOrdering<int>> lu;
  Eigen::SimplicialLDLT<SpMat> normal;
  for (int step = 0; step < kBoxNewtonSteps && best_r > target; ++step) {
    const VecX F = map(lambda, true);
    const double f = F.squaredNorm();
    if (!(f > 0.0)) break;
    std::vector<Triplet> t;
    t.reserve(static_cast<std::size_t>(A.nonZeros() + 2 * c));
    for (int j = 0; j < A.outerSize(); ++j)
      for (SpMat::InnerIterator it(A, j); it; ++it)
        if (kind[static_cast<std::size_t>(it.row())] == 0)
          t.emplace_back(int(it.row()), j, rho(it.row()) * it.value());
    for (Eigen::Index k = 0; k < c; ++k) {
      const int at = kind[static_cast<std::size_t>(k)];
      if (at == 0) continue;
      t.emplace_back(int(k), int(k), 1.0);
      const int n = normal_of[static_cast<std::size_t>(k)];
      if (n >= 0 && lambda(n) > 0.0) t.emplace_back(int(k), n, at > 0 ? -mu_of(k) : mu_of(k));
    }
    SpMat G(c, c);
    G.setFromTriplets(t.begin(), t.end());
    const auto descend = [&](const VecX& d, double smallest) {
      if (!d.allFinite()) return false;
      for (double s = 1.0; s >= smallest; s *= 0.5) {
        const VecX trial = lambda + s * d;
        if (map(trial, false).squaredNorm() <= (1.0 - kBoxArmijo * s) * f) {
          lambda = trial;
          return true;
        }
      }
      return false;
    };
    lu.compute(G);
    bool moved = lu.info() == Eigen::Success && descend(lu.solve(-F), 1.0 / 1024);
    if (!moved) {
      const SpMat Gt = G.transpose();
      SpMat H = Gt * G;
      for (Eigen::Index k = 0; k < c; ++k) H.coeffRef(k, k) += std::sqrt(f);
      normal.compute(H);
      moved = normal.info() == Eigen::Success && descend(normal.solve(-(Gt * F)), 1e-10);
    }
    if (!moved) break;
    const double r = residual_at(lambda);
    if (r < best_r) {
      best_r = r;
      best = lambda;
    }
  }
  lambda = best;
  move_bounds(coulomb, lambda, cmin, cmax);
  return best_r;
}

/// direct_fixed_point's message: how it ended, after how many rounds, what Newton's steps did
/// (newton_r < 0: they did not run), and the residual under the bounds λ was judged by.
std::string fixed_point_message(bool fixed,
                                int rounds,
                                bool by_newton,
                                double newton_r,
                                double change,
                                const SolverSummary& total) {
  std::ostringstream msg;
  msg << "direct with Coulomb bounds: " << (fixed ? "fixed point" : "no fixed point") << " in "
      << rounds << " rounds";
  if (by_newton)
    msg << " and Newton's steps on the Coulomb box's own natural map";
  else if (newton_r >= 0.0)
    msg << " (Newton's steps on the Coulomb box's own natural map stalled at residual " << newton_r
        << " N)";
  msg << " (last change " << change << " N), " << total.factorizations
      << " factorizations, residual under "
      << (fixed ? "its own bounds " : "the last round's bounds ") << total.residual << " N";
  return msg.str();
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
  VecX best = lambda;  // the round whose λ best solves the box of its own bounds
  double best_r = kInf;
  int stalled = 0;  // rounds in a row that did not halve that residual
  VecX newton;      // where Newton's steps ended, once they ran
  double newton_r = kInf;
  // Newton's steps from the rounds' best λ; true (λ their answer) where they reach the target,
  // else λ and the bounds left as they were.
  const auto finish_by_newton = [&] {
    const VecX cmin_before = cmin, cmax_before = cmax;
    newton = best_r < kInf ? best : lambda;
    const double target = std::max(unit_free_target(bounded).both(options.tolerance, newton),
                                   kNewtonFloor * floor_of(newton));
    newton_r = coulomb_box_newton(bounded, coulomb, cmin, cmax, target, newton);
    if (newton_r <= target) {
      change = (newton - lambda).lpNorm<Eigen::Infinity>();
      lambda = newton;
      fixed = true;
      return true;
    }
    // Short of it the rounds go on from their own λ and bounds.
    cmin = cmin_before;
    cmax = cmax_before;
    return false;
  };
  while (rounds < kMaxRounds) {
    change = move_bounds(coulomb, lambda, cmin, cmax);
    if (rounds > 0) {
      // λ solves the box of its own bounds as well as a solve that reached its floor solved its
      // box (a solve that stopped short is no such measure: then the rounds go on).
      const double r = natural_map_residual(bounded, lambda);
      if (change <= 1e-12 * scale || r <= std::max({solved_to, 1e-12 * scale, floor_of(lambda)})) {
        fixed = true;
        break;
      }
      stalled = r < 0.5 * best_r ? 0 : stalled + 1;
      if (r < best_r) {
        best_r = r;
        best = lambda;
      }
      if (stalled == kStalledRounds && finish_by_newton()) break;  // the rounds cycle
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
  // Newton's steps also where the rounds end without stalling (a round's solve stopped short);
  // short of the target λ stays the last round's, its residual under the bounds it solved.
  if (!fixed && newton.size() == 0 && rounds > 0 && total.termination != Termination::TimeLimit &&
      total.termination != Termination::NonFinite && !past_deadline(options)) {
    const VecX cmin_solved = cmin, cmax_solved = cmax;
    move_bounds(coulomb, lambda, cmin, cmax);
    const double r = natural_map_residual(bounded, lambda);
    if (r < best_r) {
      best_r = r;
      best = lambda;
    }
    if (!finish_by_newton()) {
      cmin = cmin_solved;
      cmax = cmax_solved;
    }
  }
  if (!fixed && total.termination == Termination::Direct)
    total.termination = Termination::NotConverged;
  total.residual = natural_map_residual(bounded, lambda);  // A + eps E when cfm > 0
  // At the fixed point λ's own residual is the verdict: within the tolerance, or the rounding
  // floor, the solve reached it, whatever its last round's solve said of its own box.
  const bool by_newton = fixed && newton.size() > 0 && lambda == newton;
  if (fixed && total.termination == Termination::NotConverged &&
      total.residual <=
          std::max(options.tolerance,
                   (by_newton ? kNewtonFloor : 1.0) * residual_floor(bounded, lambda)))
    total.termination = Termination::Direct;
  total.message = fixed_point_message(
      fixed, rounds, by_newton, newton.size() > 0 ? newton_r : -1.0, change, total);
  return total;
}

/// The methods whose sweep depends on nothing but lambda and the problem (their entry's
/// sweeps_alone, methods.hpp: the Gauss-Seidel and Jacobi sweeps of 7.1.1, their block and
/// matrix-free forms, and 7.1.1 in the coloured (rbgs) and levelled (shock) orders): bounds moved
/// between two sweeps of one solve are what a new solve from that lambda would see. The others
/// carry state from sweep to sweep (momentum, a dual, a peer's own loop) that was built for the
/// box before the move, and restart for every move: one solve() of one iteration per box.
bool sweeps_alone(Method method) { return method_entry(method).sweeps_alone; }

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
