// The active-set path for the boxed problem of 6.2: proximal-point outer loop, a primal active-set
// method on the free rows, CHOLMOD's sparse Cholesky for each free block, islands apart.
// The method, its parameters and its sources are described at solve_active_set() in
// active_set.hpp.
#include "cbps/solvers/exact/active_set.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "cbps/solvers/exact/cholmod_factor.hpp"
#include "cbps/solvers/exact/direct.hpp"
#include "cbps/solvers/islands.hpp"
#include "cbps/solvers/methods.hpp"
#include "cbps/solvers/paper/pgs.hpp"
#include "newton_system.hpp"

namespace cbps {

namespace {

/// A free block whose reciprocal condition estimate is below this is treated as singular.
constexpr double kSingularRcond = kDefiniteRcond;
/// Outer iterations without a new best residual before the direct path gives up.
constexpr int kStallLimit = 10;
/// Iterative-refinement passes of a body-space solve before a full step.
constexpr int kRefinements = 2;
/// The factor by which ε falls when the proximal steps converge slowly (and rises back).
constexpr double kEpsilonStep = 10.0;

/// Where a row sits in the active-set partition.
enum class Place : unsigned char {
  Free,   ///< cmin < lambda < cmax, w = 0 (solved for)
  Lower,  ///< lambda = cmin, w ≥ 0
  Upper,  ///< lambda = cmax, w ≤ 0
  Fixed   ///< cmin = cmax: lambda is that value, w free; never exchanged
};

/// One island's boxed problem and the state of its solve.
class IslandSolver {
 public:
  /// With `newton`, the free blocks are solved by it (body space, always with ε ≥ eps_start)
  /// instead of CHOLMOD on A(F, F) + εI.
  IslandSolver(const BoxedProblem& problem,
               const SolverOptions& options,
               SolverSummary& stats,
               NewtonSystem* newton = nullptr,
               double eps_start = 0.0,
               double row_sum = -1.0)
      : problem_(problem),
        A_(problem.A),
        b_(problem.b),
        cmin_(problem.cmin),
        cmax_(problem.cmax),
        options_(options),
        stats_(stats),
        newton_(newton),
        eps_start_(eps_start) {
    const Eigen::Index m = problem.rows();
    if (m > 0) max_diagonal_ = std::max(0.0, diagonal_of_A(problem).maxCoeff());
    for (Eigen::Index j = 0; j < m; ++j)
      bounded_ = bounded_ || std::isfinite(cmin_(j)) || std::isfinite(cmax_(j));
    local_.assign(static_cast<std::size_t>(m), -1);
    row_sum_ = row_sum >= 0.0 ? row_sum : max_abs_row_sum(problem);
    if (newton_ == nullptr && !problem.A_formed())
      throw std::logic_error("active set: A(F, F) factored, but A was left out");
  }

  /// Solves from the guess in lambda; true when the residual reached the tolerance.
  bool solve(VecX& lambda) {
    const Eigen::Index m = problem_.rows();
    for (Eigen::Index i = 0; i < m; ++i) {
      if (!std::isfinite(lambda(i))) lambda(i) = 0.0;
      lambda(i) = clamp(lambda(i), cmin_(i), cmax_(i));
    }
    if (bounded_) {
      for (int s = 0; s < options_.direct.start_sweeps; ++s) pgs_sweep(problem_, lambda);
    }
    place_.assign(static_cast<std::size_t>(m), Place::Free);
    for (Eigen::Index i = 0; i < m; ++i) place_[std::size_t(i)] = initial_place(i, lambda(i));

    double r = natural_map_residual(problem_, lambda);
    // A finish from an interior point takes at least one step on its partition: on a definite
    // free block that step is exact to round-off.
    // A guess at the rounding floor is taken as it is (as solve_direct takes one).
    if (r <= tolerance(lambda) && newton_ == nullptr && eps_start_ == 0.0 && !finishing_) {
      stats_.residual = r;
      return true;
    }
    double best_r = r;
    VecX best = lambda;
    // Plain active set first (exact when the free blocks are definite); the body-space solve
    // needs ε > 0 from the start.
    double eps = eps_start_ * max_diagonal_;
    int stall = 0;
    bool may_reduce = true;  // until an ε once made the active-set search fail
    std::vector<Place> previous = place_;
    for (int k = 0; k < options_.direct.max_outer_iterations; ++k) {
      ++stats_.iterations;
      VecX x = lambda;
      const Pivoting result = pivot(eps, lambda, x);
      if (result == Pivoting::OverBudget) break;
      if (result == Pivoting::Singular) {
        if (eps > 0.0) break;  // A + εI not definite: A is not positive semidefinite
        eps = options_.direct.epsilon * max_diagonal_;
        stats_.singular = true;
        continue;
      }
      if (result == Pivoting::Failed) {
        // Too many pivots: a larger ε makes the subproblem better conditioned and the
        // pivoting shorter; ε then stays.
        if (eps == 0.0 || eps >= max_diagonal_) break;
        eps *= kEpsilonStep;
        may_reduce = false;
        place_ = previous;
        continue;
      }
      const bool settled = place_ == previous;
      previous = place_;
      lambda = x;
      const double r_new = natural_map_residual(problem_, lambda);
      if (!std::isfinite(r_new)) break;
      if (r_new < best_r) {
        best_r = r_new;
        best = lambda;
        stall = 0;
      } else {
        ++stall;
      }
      if (may_stop(r_new, r, options_.tolerance, floor(lambda))) {
        stats_.residual = r_new;
        return true;
      }
      // Proximal steps contract the error by about ε/(σ + ε) for an eigenvalue σ of the free
      // block: once the active set holds, a smaller ε converges faster.
      const double eps_floor = options_.direct.epsilon_floor * max_diagonal_;
      if (may_reduce && eps > eps_floor && settled && r_new > 0.5 * r) {
        eps = std::max(eps / kEpsilonStep, eps_floor);
      }
      if (stall >= kStallLimit) break;
      r = r_new;
    }
    lambda = best;
    stats_.residual = best_r;
    return best_r <= tolerance(best);  // at the floor, though the last steps still reduced it
  }

 private:
  /// OverBudget: the pivoting rounds of the whole solve passed max_rounds_, or the solve's
  /// deadline passed (SolverOptions::time_limit).
  enum class Pivoting { Solved, Singular, Failed, OverBudget };

  Place initial_place(Eigen::Index i, double value) const {
    if (cmin_(i) == cmax_(i)) return Place::Fixed;
    if (value <= cmin_(i)) return Place::Lower;
    if (value >= cmax_(i)) return Place::Upper;
    return Place::Free;
  }

  /// The user's tolerance or, where it is lower, the rounding floor of the natural-map residual
  /// at lambda (no solve can go below that).
  double tolerance(const VecX& lambda) const { return std::max(options_.tolerance, floor(lambda)); }

  /// The rounding floor of the natural-map residual at lambda, N.
  double floor(const VecX& lambda) const { return residual_floor(row_sum_, b_, lambda); }

  /// Factor of (A + εI)(F, F) for the free rows F, reused while F and ε stay.
  bool factor_free_block(const std::vector<int>& F, double eps) {
    if (newton_ != nullptr) {
      if (F == factor_rows_ && eps == factor_eps_) return true;
      dropped_.assign(std::size_t(problem_.rows()), 1);
      for (const int i : F) dropped_[std::size_t(i)] = 0;
      d_ = VecX::Constant(problem_.rows(), eps);
      const bool ok = newton_->factor(d_, dropped_);
      stats_.factor_nnz = std::max(stats_.factor_nnz, newton_->factor_nonzeros());
      factor_rows_ = ok ? F : std::vector<int>{};
      factor_eps_ = ok ? eps : -1.0;
      return ok;
    }
    if (factor_.valid() && F == factor_rows_ && eps == factor_eps_) return true;
    const bool whole = static_cast<Eigen::Index>(F.size()) == problem_.rows();
    bool ok = false;
    if (F == factor_rows_ && factor_eps_ >= 0.0) {
      ok = factor_.refactor(whole ? A_ : block_, eps);
    } else {
      if (!whole) block_ = principal_submatrix(A_, F, local_);
      ok = factor_.factor(whole ? A_ : block_, eps);
      factor_rows_ = F;
    }
    factor_eps_ = eps;
    ++stats_.factorizations;
    if (!ok) {
      factor_rows_.clear();
      factor_eps_ = -1.0;
    }
    return ok && (eps > 0.0 || factor_.rcond() >= kSingularRcond);
  }

  /// The subproblem min ½ xᵀ(A + εI)x − gᵀx over the box, g = b + ε center, by a primal
  /// active-set method from the partition place_ and the guess x (clamped into the box):
  ///   1. with the bound rows at their bounds, the Newton step of the free rows F,
  ///        p_F = (A + εI)_FF⁻¹ (g − (A + εI) x)_F   (the minimiser on that face, in correction
  ///      form: iterative refinement as a side effect);
  ///   2. the longest step α ≤ 1 along p that stays in the box; rows that block are fixed at
  ///      the bound they reach;
  ///   3. after a full step, the bound rows whose gradient y = (A + εI)x − g has the wrong sign
  ///      (y < 0 at cmin, y > 0 at cmax) are freed: all of them, or after a step that made no
  ///      progress only the worst one.
  /// The objective falls at every step (the step is a descent direction and α ≤ 1 does not
  /// overshoot the minimiser on the face), so the method cannot cycle.
  /// (A + εI)x is formed anew after each full step (its gradient is needed there) and before
  /// the refined solve of one; after a blocked step only its free rows are read next, and
  /// those move by α (A + εI)_FF p = α rhs: updated so, a blocked round costs one solve and no
  /// product by A (most rounds block: the base-20 pyramid under PGS, docs/exact-path.md).
  Pivoting pivot(double eps, const VecX& center, VecX& x) {
    const Eigen::Index m = problem_.rows();
    const double tol = tolerance(center);
    VecX g = b_ + eps * center;
    std::vector<int> F;
    VecX rhs, p;
    bool release_one = false;
    for (Eigen::Index i = 0; i < m; ++i) {
      const Place place = place_[std::size_t(i)];
      if (place == Place::Lower || place == Place::Fixed) x(i) = cmin_(i);
      if (place == Place::Upper) x(i) = cmax_(i);
      if (place == Place::Free) x(i) = clamp(x(i), cmin_(i), cmax_(i));
    }
    VecX Hx = times_A(x) + eps * x;  // (A + εI) x
    bool Hx_formed = true;           // formed, not updated, since x last moved
    const auto form_Hx = [&] {
      if (Hx_formed) return;
      Hx = times_A(x) + eps * x;
      Hx_formed = true;
    };
    const long limit = 100 + 5 * static_cast<long>(m);
    for (long round = 0; round < limit; ++round) {
      ++rounds_;
      if (max_rounds_ >= 0 && rounds_ > max_rounds_) return Pivoting::OverBudget;
      if (past_deadline(options_)) return Pivoting::OverBudget;
      F.clear();
      for (Eigen::Index i = 0; i < m; ++i) {
        if (place_[std::size_t(i)] == Place::Free) F.push_back(static_cast<int>(i));
      }
      double alpha = 1.0;
      if (!F.empty()) {
        if (!factor_free_block(F, eps)) return Pivoting::Singular;
        const auto form_rhs = [&] {
          rhs.resize(static_cast<Eigen::Index>(F.size()));
          for (std::size_t k = 0; k < F.size(); ++k) rhs(Eigen::Index(k)) = g(F[k]) - Hx(F[k]);
        };
        form_rhs();
        // In body space a blocked step only needs a direction, so no refinement; a full step
        // is refined, from (A + εI)x formed anew, before it is taken.
        const auto ratio_test = [&] {
          double a = 1.0;
          for (std::size_t k = 0; k < F.size(); ++k) {
            const int i = F[k];
            const double pi = p(Eigen::Index(k));
            if (x(i) + pi < cmin_(i)) a = std::min(a, (cmin_(i) - x(i)) / pi);
            if (x(i) + pi > cmax_(i)) a = std::min(a, (cmax_(i) - x(i)) / pi);
          }
          return std::max(a, 0.0);
        };
        solve_free_block(F, rhs, p, 0);
        if (!p.allFinite()) return Pivoting::Failed;
        alpha = ratio_test();
        if (alpha == 1.0 && newton_ != nullptr) {
          if (!Hx_formed) {
            form_Hx();
            form_rhs();
          }
          solve_free_block(F, rhs, p, kRefinements);
          if (!p.allFinite()) return Pivoting::Failed;
          alpha = ratio_test();
        }
        for (std::size_t k = 0; k < F.size(); ++k) {
          const int i = F[k];
          const double pi = p(Eigen::Index(k));
          const double xi = x(i) + alpha * pi;
          // Only rows moving out of the box block: after a step of 0, a row just freed at its
          // bound whose step points inwards stays free.
          if (alpha < 1.0 && pi < 0.0 && xi <= cmin_(i)) {
            place_[std::size_t(i)] = Place::Lower;  // blocked: fixed at the bound it reached
            x(i) = cmin_(i);
            ++stats_.pivots;
          } else if (alpha < 1.0 && pi > 0.0 && xi >= cmax_(i)) {
            place_[std::size_t(i)] = Place::Upper;
            x(i) = cmax_(i);
            ++stats_.pivots;
          } else {
            x(i) = clamp(xi, cmin_(i), cmax_(i));
          }
          Hx(i) += alpha * rhs(Eigen::Index(k));  // (A + εI)_FF p = rhs
        }
        Hx_formed = false;
      }
      if (alpha < 1.0) {
        release_one = release_one || alpha == 0.0;
        continue;
      }
      // A full step: x minimises the objective on this face. Free the wrong-signed bound rows.
      form_Hx();
      const int released = release_wrong_signed(Hx - g, tol, release_one);
      if (released == 0) return Pivoting::Solved;
      release_one = false;
    }
    return Pivoting::Failed;
  }

  /// Frees the bound rows whose gradient y = (A + εI)x − g has the wrong sign by more than
  /// `tol` (y < 0 at cmin, y > 0 at cmax): all of them, or with `release_one` only the worst.
  /// Returns how many were freed.
  int release_wrong_signed(const VecX& y, double tol, bool release_one) {
    Eigen::Index worst = -1;
    double worst_violation = tol;
    int released = 0;
    for (Eigen::Index i = 0; i < y.size(); ++i) {
      Place& place = place_[std::size_t(i)];
      const double violation = place == Place::Lower ? -y(i) : place == Place::Upper ? y(i) : 0.0;
      if (!(violation > tol)) continue;
      if (violation > worst_violation) {
        worst_violation = violation;
        worst = i;
      }
      if (!release_one) {
        place = Place::Free;
        ++released;
        ++stats_.pivots;
      }
    }
    if (release_one && worst >= 0) {
      place_[std::size_t(worst)] = Place::Free;
      ++released;
      ++stats_.pivots;
    }
    return released;
  }

  /// A x, in body space through J and Minv.
  VecX times_A(const VecX& x) const {
    if (newton_ == nullptr) return A_ * x;
    VecX y;
    newton_->times_A(x, y);
    return y;
  }

  /// p = (A + εI)(F, F)⁻¹ rhs with the current factor.
  void solve_free_block(const std::vector<int>& F, const VecX& rhs, VecX& p, int refinements) {
    if (newton_ == nullptr) {
      factor_.solve(rhs, p);
      return;
    }
    VecX r = VecX::Zero(problem_.rows()), x;
    for (std::size_t k = 0; k < F.size(); ++k) r(F[k]) = rhs(Eigen::Index(k));
    newton_->solve(d_, dropped_, r, x, refinements);
    p.resize(rhs.size());
    for (std::size_t k = 0; k < F.size(); ++k) p(Eigen::Index(k)) = x(F[k]);
  }

  const BoxedProblem& problem_;
  const SpMat& A_;
  const VecX& b_;
  const VecX& cmin_;
  const VecX& cmax_;
  const SolverOptions& options_;
  SolverSummary& stats_;
  double max_diagonal_ = 0.0;
  double row_sum_ = 0.0;  ///< max_i Σ_k |A_ik|, for the rounding floor
  bool bounded_ = false;
  std::vector<Place> place_;
  std::vector<int> local_;
  CholmodFactor factor_;
  std::vector<int> factor_rows_;  ///< the free rows factor_ was made for
  double factor_eps_ = -1.0;      ///< and its ε (−1: none)
  SpMat block_;                   ///< A(F, F) of factor_rows_, kept for refactor()
  NewtonSystem* newton_;          ///< the body-space solve, or null (CHOLMOD on A(F, F))
  double eps_start_;              ///< ε to start from, a fraction of max A_kk

 public:
  bool finishing_ = false;  ///< finish_active_set on A(F, F): at least one step before stopping
  /// Pivoting rounds (each one solve of a free block) allowed in the whole solve; −1: no limit.
  long max_rounds_ = -1;
  long rounds_ = 0;  ///< pivoting rounds so far

 private:
  std::vector<char> dropped_;  ///< the rows not in factor_rows_ (newton_)
  VecX d_;                     ///< ε on every row (newton_)
};

/// solve_active_set on a problem without null rows (solve_around_null_rows).
SolverSummary solve_active_set_coupled(const BoxedProblem& problem,
                                       VecX& lambda,
                                       const SolverOptions& options) {
  const SpMat& A = problem.A;
  const auto start = std::chrono::steady_clock::now();
  const Eigen::Index n = A.rows();
  SolverSummary s;
  if (lambda.size() != n) lambda = VecX::Zero(n);
  s.termination = Termination::Direct;
  std::vector<std::vector<int>> islands;
  if (options.direct.split_islands) {
    islands = find_islands(A);
  } else if (n > 0) {
    islands.emplace_back(static_cast<std::size_t>(n));
    std::iota(islands.back().begin(), islands.back().end(), 0);
  }
  s.islands = static_cast<int>(islands.size());
  int unsolved = 0;
  for_each_island(
      islands, problem, lambda, [&](const BoxedProblem& island_problem, VecX& lambda_I) {
        const SpMat& A_I = island_problem.A;
        const double A_11 = A_I.rows() == 1 ? A_I.coeff(0, 0) : 0.0;
        if (A_11 > 0.0) {  // one row: lambda = clamp(b / A_11), exactly
          lambda_I(0) =
              clamp(island_problem.b(0) / A_11, island_problem.cmin(0), island_problem.cmax(0));
          return;
        }
        const bool warm = !lambda_I.isZero(0.0);
        IslandSolver island(island_problem, options, s);
        if (island.solve(lambda_I)) return;
        if (warm) {
          // Stopped short from the caller's guess: once more from lambda = 0 (the 5 PGS sweeps
          // of step 1 pick the first active set); keep whichever residual is smaller.
          VecX cold = VecX::Zero(lambda_I.size());
          ++s.restarts;
          if (island.solve(cold)) {
            lambda_I = cold;
            return;
          }
          if (natural_map_residual(island_problem, cold) <
              natural_map_residual(island_problem, lambda_I)) {
            lambda_I = cold;
          }
        }
        ++unsolved;
      });
  s.residual = natural_map_residual(problem, lambda);
  if (!std::isfinite(s.residual)) {
    s.termination = Termination::NonFinite;
  } else if (unsolved > 0) {
    s.termination = Termination::NotConverged;
  }
  s.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::ostringstream msg;
  msg << "active set (on CHOLMOD, proximal where singular): " << s.islands << " island"
      << (s.islands == 1 ? "" : "s") << ", " << s.iterations << " outer iterations, "
      << s.factorizations << " factorizations, " << s.pivots << " pivots, residual " << s.residual
      << " N";
  if (s.singular) msg << "; singular blocks regularised";
  if (s.restarts > 0) msg << "; " << s.restarts << " island(s) restarted from lambda = 0";
  if (unsolved > 0) msg << "; " << unsolved << " island(s) stopped short of the tolerance";
  s.message = msg.str();
  return s;
}

}  // namespace

SolverSummary solve_active_set(const BoxedProblem& problem,
                               VecX& lambda,
                               const SolverOptions& options) {
  if (!problem.A_formed()) {  // A left out: this path factors A(F, F) and sweeps A's rows
    const SpMat A = formed_A(problem);
    return solve_active_set(with_matrix(problem, A), lambda, options);
  }
  SolverSummary s;
  s.route = kActiveSetRoute;
  if (!check_input(problem, "active set", s)) return s;
  // A row with no entry in A (j_c = 0): CHOLMOD cannot analyse its empty block, and its lambda
  // follows from b and its bounds alone.
  SolverSummary solved =
      solve_around_null_rows(problem, lambda, [&](const BoxedProblem& rest, VecX& lambda_R) {
        return solve_active_set_coupled(rest, lambda_R, options);
      });
  solved.route = kActiveSetRoute;
  return solved;
}

SolverSummary finish_active_set(const BoxedProblem& problem,
                                VecX& lambda,
                                const SolverOptions& options,
                                NewtonSystem* newton,
                                double eps_start,
                                const FinishHints& hints) {
  SolverSummary s;
  SolverOptions o = options;
  o.direct.start_sweeps = 0;
  IslandSolver island(problem, o, s, newton, newton != nullptr ? eps_start : 0.0, hints.row_sum);
  island.finishing_ = newton == nullptr;
  island.max_rounds_ = hints.max_rounds;
  s.termination = island.solve(lambda) ? Termination::Direct : Termination::NotConverged;
  return s;
}

// This file's entry in the one table of methods (methods.hpp, gathered by methods.cpp).

extern const MethodEntry kActiveSetEntry;
constexpr MethodEntry kActiveSetEntry{
    .method = Method::ActiveSet,
    .name = "active-set",
    .iterative = false,
    .symmetric = true,
    .symmetric_on_cones = true,
    .solve = solve_active_set,
    .what = "the previous exact path, for comparison",
};

}  // namespace cbps
