// The exact path for the boxed problem of 6.2: a primal-dual interior-point method (Mehrotra's
// predictor-corrector) with its Newton systems factored in body space, then a crossover to the
// exact active set. The method, its parameters and its sources are described at solve_direct()
// in direct.hpp.
#include "cbps/solvers/exact/direct.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "cbps/base/friction_law.hpp"
#include "cbps/solvers/cone/cone_direct.hpp"
#include "cbps/solvers/exact/active_set.hpp"
#include "cbps/solvers/exact/interior_point.hpp"
#include "cbps/solvers/islands.hpp"
#include "cbps/solvers/methods.hpp"
#include "cbps/system/unit_free.hpp"
#include "newton_system.hpp"

namespace cbps {

namespace {

/// The crossover's first proximal ε, a fraction of max A_kk: small, because the interior point's
/// partition is close (its proximal steps contract the error by about ε/(σ + ε)).
constexpr double kCrossoverEpsilon = 1e-6;
/// Islands up to this many rows finish apart on CHOLMOD factors of A's free block (row space);
/// larger ones in body space, where one factor is updated from step to step but each step
/// costs a solve of the whole problem (the base-10 pyramid, one island of 1,200 rows: 13 ms in
/// body space against 60 ms on A(F, F); the 100-column stack's 120-row islands the other way).
constexpr Eigen::Index kRowSpaceFinish = 500;
/// A warm start's crossover (warm_finish) takes at most this many proximal steps before the
/// interior point runs from scratch (the cold crossover from the interior point's partition
/// takes 19 to 24 on the 10-box stack and the base-6 pyramid stepped by PGS);
constexpr int kWarmSteps = 30;
/// … and at most this many pivoting rounds in all (each one solve with the free block, about
/// 0.4 ms on the base-20 pyramid's 4,800 rows, where the cold interior point takes about 20 ms).
/// The last step's answer in a scene stepped by the direct path needs 1 to a few
/// (tests/solvers/test_direct_interior.cpp); on states stepped by PGS, settling with its errors,
/// even the last step's exact answer needed 200 to 400 (0.9 λ* likewise), and PGS's λ under
/// `--check` on the base-20 pyramid 233 on one step and 49,473 (9 s, unfinished) on the next:
/// there the interior point is the cheaper way.
constexpr long kWarmRounds = 100;
/// What a message adds when the warm crossover ran out of those.
constexpr const char* kWarmUnfinished =
    "; before it, the warm start's crossover did not finish in 30 proximal steps and 100 "
    "pivoting rounds";
static_assert(kWarmSteps == 30 && kWarmRounds == 100, "kWarmUnfinished names them");

/// The whole solve: the interior iterations, then the crossover.
class InteriorSolver {
 public:
  InteriorSolver(const BoxedProblem& problem, const SolverOptions& options, SolverSummary& stats)
      : p_(problem),
        options_(options),
        stats_(stats),
        diagonal_(diagonal_of_A(problem)),
        rows_{problem.b,
              problem.cmin,
              problem.cmax,
              diagonal_,
              scale_of(problem),
              max_abs_row_sum(problem)} {
    newton_ = make_newton_system(problem, options.direct.memory.get());
    stats_.space = newton_->space();
  }

  /// The interior iterations, then the crossover; true when lambda reaches the tolerance.
  bool solve(VecX& lambda) {
    const InteriorOutcome interior =
        run_interior_point(rows_, *newton_, RowReduction(), options_, lambda);
    stats_.iterations = interior.iterations;
    stats_.factor_nnz = std::max(stats_.factor_nnz, interior.factor_nnz);
    const bool small = p_.rows() <= kRowSpaceFinish;
    if (interior.solved && !small) {
      stats_.factorizations += newton_->factorizations();
      return true;
    }
    // The crossover starts from the interior point's partition: bound rows at their bounds.
    for (Eigen::Index k = 0; k < lambda.size(); ++k) {
      const Place place = interior.place[std::size_t(k)];
      if (place == Place::Lower || place == Place::Fixed) lambda(k) = p_.cmin(k);
      if (place == Place::Upper) lambda(k) = p_.cmax(k);
    }
    // Islands of up to kRowSpaceFinish rows finish apart on A(F, F) itself, from ε = 0: where
    // the free block is definite that is exact to round-off, and each factor is the island's
    // own. Larger islands then finish together in body space.
    const std::vector<std::vector<int>> islands =
        small ? std::vector<std::vector<int>>{} : find_islands(p_);
    bool large = false;
    bool all_solved = true;
    if (small) {
      crossover_in_rows_ = true;
      all_solved = finish(p_, lambda, nullptr);
    } else {
      for_each_island(islands, p_, lambda, [&](const BoxedProblem& island, VecX& lambda_I) {
        if (island.rows() > kRowSpaceFinish) {
          large = true;
          return;
        }
        crossover_in_rows_ = true;
        all_solved = finish(island, lambda_I, nullptr) && all_solved;
      });
      if (large) {
        crossover_in_body_ = true;
        all_solved = finish(p_, lambda, newton_.get());
      }
    }
    stats_.factorizations += newton_->factorizations();
    stats_.updates = newton_->updates();
    return all_solved;
  }

  /// The active-set path's finish on `problem` from lambda (newton: body space, else A(F, F);
  /// a problem whose A was left out gets it formed for that, small as it is).
  bool finish(const BoxedProblem& problem, VecX& lambda, NewtonSystem* newton) {
    if (newton == nullptr && !problem.A_formed()) {
      const SpMat A = formed_A(problem);
      return finish(with_matrix(problem, A), lambda, nullptr);
    }
    const SolverSummary x = finish_active_set(problem, lambda, options_, newton, kCrossoverEpsilon);
    stats_.crossover += x.iterations;
    stats_.pivots += x.pivots;
    stats_.factorizations += x.factorizations;
    stats_.factor_nnz = std::max(stats_.factor_nnz, x.factor_nnz);
    return x.termination == Termination::Direct;
  }

 private:
  const BoxedProblem& p_;
  const SolverOptions& options_;
  SolverSummary& stats_;
  const VecX diagonal_;      ///< A_kk
  const InteriorRows rows_;  ///< the whole problem's rows (one process)
  std::shared_ptr<NewtonSystem> newton_;
  bool crossover_in_rows_ = false;  ///< the crossover factored A(F, F) (small islands)
  bool crossover_in_body_ = false;  ///< the crossover factored in body space (large islands)

 public:
  /// Where the crossover factored: "on A(F, F)", "in body space" or both.
  std::string crossover_space() const {
    if (crossover_in_rows_ && crossover_in_body_) return "on A(F, F) and in body space";
    return crossover_in_body_ ? "in body space" : "on A(F, F)";
  }
};

}  // namespace

double residual_floor(double row_sum, const VecX& b, const VecX& lambda) {
  const double l = lambda.size() > 0 ? lambda.lpNorm<Eigen::Infinity>() : 0.0;
  const double bn = b.size() > 0 ? b.lpNorm<Eigen::Infinity>() : 0.0;
  return residual_floor_of(row_sum, bn, l);
}

bool may_stop(double r, double r_before, double tolerance, double floor) {
  if (r <= tolerance) return true;
  if (!(r <= floor)) return false;
  return tolerance == 0.0 || !(r < r_before);
}

double residual_floor(const BoxedProblem& problem, const VecX& lambda) {
  return residual_floor(max_abs_row_sum(problem), problem.b, lambda);
}

namespace {

/// w = A λ − b (as the problem forms it) and each row's rounding_floors, in one pass over A's
/// entries where A is formed (no copy of |A|: the warm steps check every guess by them).
void w_and_floors(const BoxedProblem& problem, const VecX& lambda, VecX& w, VecX& floors) {
  const Eigen::Index c = problem.rows();
  VecX size;  // |A| |λ|, row by row
  if (problem.A_formed()) {
    w = -problem.b;
    size = VecX::Zero(c);
    for (Eigen::Index j = 0; j < problem.A.outerSize(); ++j) {
      const double l = lambda(j);
      for (SpMat::InnerIterator it(problem.A, j); it; ++it) {
        w(it.row()) += it.value() * l;
        size(it.row()) += std::abs(it.value() * l);
      }
    }
  } else {
    w = times_A(problem, lambda) - problem.b;
    const SpMatRow J = problem.J->cwiseAbs();
    const VecX l = lambda.cwiseAbs();
    size = J * (problem.Minv->cwiseAbs() * (J.transpose() * l)) + std::abs(problem.cfm) * l;
  }
  floors.resize(c);
  for (Eigen::Index k = 0; k < c; ++k)
    floors(k) = residual_floor_of(size(k), std::abs(problem.b(k)), 1.0);
}

}  // namespace

VecX rounding_floors(const BoxedProblem& problem, const VecX& lambda) {
  VecX w, floors;
  w_and_floors(problem, lambda, w, floors);
  return floors;
}

bool within_rounding(const BoxedProblem& problem,
                     const VecX& lambda,
                     const VecX& steps,
                     double tolerance) {
  const Eigen::Index c = problem.rows();
  if (c == 0) return true;
  VecX w, floors;
  w_and_floors(problem, lambda, w, floors);
  w.array() *= steps.array();
  floors.array() *= steps.array();
  const auto within = [&](double term, double floor) {
    return term <= std::max(tolerance, floor);  // false for a NaN term
  };
  std::vector<char> in_cone(std::size_t(c), 0);
  if (problem.cones != nullptr) in_cone = problem.cones->rows_in_cones(c);
  for (Eigen::Index k = 0; k < c; ++k)
    if (!in_cone[std::size_t(k)] &&
        !within(natural_map_row(lambda(k), w(k), problem.cmin(k), problem.cmax(k)), floors(k)))
      return false;
  if (problem.cones == nullptr) return true;
  const FrictionContacts& cones = *problem.cones;
  for (long i = 0; i < cones.contacts(); ++i) {
    const int n = cones.normal[std::size_t(i)];
    // û is positively homogeneous in u: the map with step ρ is the unit-step map of ρ w.
    const Vec3 map =
        cone_natural_map(lambda.segment<3>(n), w.segment<3>(n), cones.mu(i), cones.law);
    if (!within(map.norm(), floors.segment<3>(n).maxCoeff())) return false;
  }
  return true;
}

namespace {

/// A warm start (the last step's answer, carried by contact persistence): the crossover from its
/// partition, in body space where the problem has J and Minv, at most kWarmSteps proximal steps
/// and kWarmRounds pivoting rounds.
/// True, with s filled, when that reaches the tolerance; the interior point is then not needed.
bool warm_finish(const BoxedProblem& problem,
                 VecX& lambda,
                 const SolverOptions& options,
                 double row_sum,
                 SolverSummary& s) {
  SolverOptions o = options;
  o.direct.max_outer_iterations = kWarmSteps;
  const std::shared_ptr<NewtonSystem> newton =
      make_newton_system(problem, options.direct.memory.get());
  VecX x = lambda;
  FinishHints hints;
  hints.max_rounds = kWarmRounds;
  hints.row_sum = row_sum;
  const SolverSummary w = finish_active_set(problem, x, o, newton.get(), kCrossoverEpsilon, hints);
  if (w.termination != Termination::Direct) return false;
  lambda = x;
  s.residual = w.residual;
  s.islands = 1;
  s.space = newton->space();
  s.crossover = w.iterations;
  s.pivots = w.pivots;
  s.factorizations = w.factorizations + newton->factorizations();
  s.updates = newton->updates();
  s.factor_nnz = std::max(w.factor_nnz, newton->factor_nonzeros());
  std::ostringstream msg;
  msg << "direct (warm: the crossover from the guess's partition, " << s.space
      << " space): " << s.crossover << " proximal steps and " << s.pivots << " pivots, "
      << s.factorizations << " factorizations";
  s.message = msg.str();
  return true;
}

/// solve_direct on a problem without null rows (solve_around_null_rows).
SolverSummary solve_direct_coupled(const BoxedProblem& problem,
                                   VecX& lambda,
                                   const SolverOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const Eigen::Index n = problem.rows();
  SolverSummary s;
  if (lambda.size() != n) lambda = VecX::Zero(n);
  s.termination = Termination::Direct;
  // `known`: lambda's residual is already in s.residual (one pass over A saved).
  const auto finish = [&](const std::string& what, bool known = false) {
    if (!known) s.residual = natural_map_residual(problem, lambda);
    if (!std::isfinite(s.residual)) s.termination = Termination::NonFinite;
    s.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::ostringstream msg;
    msg << what << ", residual " << s.residual << " N";
    s.message = msg.str();
    return s;
  };
  bool bounded = false;
  for (Eigen::Index k = 0; k < n && !bounded; ++k) {
    bounded = problem.cmin(k) != problem.cmax(k) &&
              (std::isfinite(problem.cmin(k)) || std::isfinite(problem.cmax(k)));
  }
  if (!bounded) {
    // No bounded row: one linear solve (the active-set path's all-unbounded case).
    s = solve_active_set(problem, lambda, options);
    s.message = "direct (no bounded rows): " + s.message;
    s.route = "linear";
    s.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return s;
  }
  // The guess may already be the answer (a warm start on a resting scene): taken as it is at the
  // rounding floor, since solving again would only move λ by rounding (and a Coulomb fixed
  // point, which solves again from its last answer, would never settle).
  VecX guess = lambda;
  for (Eigen::Index k = 0; k < n; ++k)
    guess(k) = clamp(std::isfinite(guess(k)) ? guess(k) : 0.0, problem.cmin(k), problem.cmax(k));
  const bool warm_tried = !guess.isZero(0.0);
  const double row_sum = warm_tried ? max_abs_row_sum(problem) : 0.0;
  if (warm_tried) {
    s.residual = natural_map_residual(problem, guess);
    if (within_rounding(problem, guess, VecX::Ones(n), options.tolerance)) {
      lambda = guess;
      s.islands = 1;
      s.route = "guess";
      return finish("direct: the guess already solves it", true);
    }
  }
  // The crossover stops at the shared rounding floor: its answer is kept where each row is
  // within its own, else the cold path below solves from scratch.
  if (warm_tried && warm_finish(problem, guess, options, row_sum, s) &&
      within_rounding(problem, guess, VecX::Ones(n), options.tolerance)) {
    lambda = guess;
    s.route = "warm";
    return finish(s.message, true);
  }
  if (n < options.direct.interior_from_rows) {
    // Few rows: the active-set path, exact to round-off where the free blocks are definite.
    s = solve_active_set(problem, lambda, options);
    s.message = "direct (few rows, active set): " + s.message;
    if (warm_tried) s.message += kWarmUnfinished;
    s.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return s;
  }
  SolverSummary inner;
  InteriorSolver solver(problem, options, inner);
  VecX x = lambda;
  const bool solved = solver.solve(x);
  s = inner;
  s.islands = 1;
  s.route = "interior";
  s.termination = solved ? Termination::Direct : Termination::NotConverged;
  lambda = x;
  std::ostringstream what;
  what << "direct (interior point, " << s.space << " space"
       << (s.space == "body" ? " M + Jt D^-1 J" : " A + D") << ", factor nnz " << s.factor_nnz
       << "): " << s.iterations << " interior iterations, crossover (" << solver.crossover_space()
       << ") " << s.crossover << " proximal steps and " << s.pivots << " pivots, "
       << s.factorizations << " factorizations";
  if (s.updates > 0) what << " and " << s.updates << " rows updated in a factor";
  if (warm_tried) what << kWarmUnfinished;
  // The rounding floor grows with ‖λ‖∞, so a λ driven off by inconsistent equality rows would
  // meet it: past 1e8 × λ's natural scale (|b_k| / A_kk, the finite bounds) it is no answer.
  double natural = 1.0;
  const VecX diagonal = diagonal_of_A(problem);
  for (Eigen::Index k = 0; k < n; ++k) {
    if (diagonal(k) > 0.0) natural = std::max(natural, std::abs(problem.b(k)) / diagonal(k));
    if (std::isfinite(problem.cmin(k))) natural = std::max(natural, std::abs(problem.cmin(k)));
    if (std::isfinite(problem.cmax(k))) natural = std::max(natural, std::abs(problem.cmax(k)));
  }
  if (s.termination == Termination::Direct && lambda.lpNorm<Eigen::Infinity>() > 1e8 * natural) {
    s.termination = Termination::NotConverged;
    what << "; lambda grew past 1e8 times its scale (inconsistent equality rows?)";
  }
  if (s.termination != Termination::Direct) what << "; stopped short of the tolerance";
  return finish(what.str());
}

}  // namespace

SolverSummary solve_direct(const BoxedProblem& problem,
                           VecX& lambda,
                           const SolverOptions& options) {
  SolverSummary s;
  if (!check_input(problem, "direct", s)) return s;
  if (!problem.A_formed() && !body_masses(problem)) {
    // A left out, but J and Minv allow no body space (Minv not block diagonal and definite):
    // the row space needs A.
    const SpMat A = formed_A(problem);
    return solve_direct(with_matrix(problem, A), lambda, options);
  }
  // A row with no entry in A (j_c = 0) would make the Newton systems singular (CHOLMOD's
  // analysis of a block without entries fails): its lambda follows from b and its bounds.
  return solve_around_null_rows(problem, lambda, [&](const BoxedProblem& rest, VecX& lambda_R) {
    return solve_direct_coupled(rest, lambda_R, options);
  });
}

// This file's entry in the one table of methods (methods.hpp, gathered by methods.cpp).

namespace {

/// "direct": on friction cones their second-order-cone form (cone/cone_direct.hpp); on the boxed
/// problem the exact path (exact/direct.hpp) aiming at the tolerance read both as N and as a
/// unit-free residual, on a problem in its simulator's units as a unit-free residual alone
/// (UnitFreeTarget::read, at λ = 0: the force scale b alone calls for), the rounding floor still
/// stopping it.
SolverSummary direct_method(const BoxedProblem& problem,
                            VecX& lambda,
                            const SolverOptions& options) {
  if (problem.cones != nullptr) return solve_cone_direct(problem, lambda, options);
  SolverOptions aimed = options;
  aimed.tolerance =
      unit_free_target(problem).read(options.tolerance, VecX(), options.tolerance_unit_free);
  return solve_direct(problem, lambda, aimed);
}

}  // namespace

extern const MethodEntry kDirectEntry;
constexpr MethodEntry kDirectEntry{
    .method = Method::Direct,
    .name = "direct",
    .iterative = false,
    .reads_A = false,
    .symmetric = true,
    .laws = kEitherLaw,
    .solve = direct_method,
    .what = "the exact path: interior point, then active set",
};

}  // namespace cbps
