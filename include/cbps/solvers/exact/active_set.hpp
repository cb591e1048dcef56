// The active-set path for the boxed problem of 6.2: a primal active-set method on CHOLMOD's
// sparse Cholesky of the free rows' block of A inside a proximal-point loop, island by island.
// It was cbps's exact path until the interior-point path of direct.hpp replaced it; it stays
// selectable ("active-set") for comparison, and the interior-point path hands it an answer the
// crossover could not finish.
#pragma once

#include "cbps/solvers/solver.hpp"

namespace cbps {

/// The route (SolverSummary::route) of every answer of this path: as the active-set method and
/// as the direct path's route on few rows (direct.hpp).
inline constexpr const char* kActiveSetRoute = "active-set";

/// The active-set path for the boxed problem of 6.2 (cmin ≤ lambda ≤ cmax, w = A lambda − b,
/// complementarity), A symmetric positive semidefinite, sparse. It solves the equivalent bound-
/// constrained QP min ½ λᵀAλ − bᵀλ over the box. Per island (options.direct.split_islands):
///   1. a few PGS sweeps (options.direct.start_sweeps) choose the first active set (rows at
///      cmin or cmax);
///   2. a primal active-set method (Nocedal & Wright, Numerical Optimization, 2nd ed. 2006,
///      §16.5, here for box constraints) finds the minimiser of
///        min ½ λᵀ (A + εI) λ − (b + ε lambda_k)ᵀ λ  over the box:
///      the Newton step of the free rows (CHOLMOD's sparse Cholesky of the free block, Chen,
///      Davis, Hager & Rajamanickam, ACM TOMS 35(3) 2008, in correction form, i.e. with
///      iterative refinement), the longest step that stays in the box (blocking rows join their
///      bound), then the release of bound rows whose gradient has the wrong sign; the objective
///      falls at every step, so it cannot cycle;
///   3. the proximal-point outer loop lambda_{k+1} = that minimiser (Rockafellar, SIAM J.
///      Control Optim. 14(5) 1976) converges to a solution of the original problem for any PSD
///      A with a solution. ε = 0 (plain active set, exact in finitely many steps) whenever the
///      free block is numerically positive definite (CHOLMOD's reciprocal condition estimate
///      above kDefiniteRcond); otherwise ε starts at options.direct.epsilon · max A_kk and falls
///      by 10× whenever the active set has settled and the residual falls slower than 2× per
///      step, down to options.direct.epsilon_floor · max A_kk; if the active-set search needs
///      too many rounds (100 + 5 rows), ε rises 10× and stays.
/// All-unbounded islands skip step 1 and have nothing to release in step 2: one factorization
/// and refinement; one-row islands are solved in closed form, clamp(b / A_kk). An island that
/// stops short from a warm guess is solved once more from lambda = 0, keeping the better answer.
/// It stops when the natural-map residual ≤ options.tolerance, or at or below the rounding floor
/// 64 u (max_i Σ_k |A_ik| ‖lambda‖∞ + ‖b‖∞), u the unit roundoff (the rounding of
/// w = A lambda − b, with room for the regularised solves' own rounding) at once with tolerance
/// 0 and else once a step no longer reduces it (may_stop, direct.hpp). Returns
/// Termination::Direct when the residual reaches that, NotConverged otherwise (e.g.
/// inconsistent equality rows, an infeasible box), with the best lambda found. No CFM here:
/// solve() adds it (the factor then is of A + eps E + ε I).
SolverSummary solve_active_set(const BoxedProblem& problem,
                               VecX& lambda,
                               const SolverOptions& options = {});

}  // namespace cbps
