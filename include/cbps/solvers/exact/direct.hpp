// The exact path for the boxed problem of 6.2: a primal-dual interior-point method whose Newton
// systems are factored in body space (M + Jᵀ D⁻¹ J, 6n × 6n) when J and Minv are known, in row
// space (A + D, c × c) otherwise, finished by a crossover to the exact active set. PGS is
// checked against it.
#pragma once

#include "cbps/solvers/solver.hpp"

namespace cbps {

/// The exact path for the boxed problem of 6.2 (cmin ≤ lambda ≤ cmax, w = A lambda − b,
/// complementarity), A symmetric positive semidefinite, sparse: the minimiser of the bound-
/// constrained QP min ½ λᵀAλ − bᵀλ over the box (its optimality conditions are 6.2's).
///   1. A problem with no bounded row goes to the active-set path whole (solve_active_set: one
///      CHOLMOD factorization for an equality system). A guess that already meets the tolerance
///      is returned as it is (route "guess"). Any other nonzero guess (a running scene's last λ)
///      goes to the crossover of 3. first, from its own partition, in body space where it can,
///      for at most 30 proximal steps (kWarmSteps, direct.cpp; route "warm"); only where that does
///      not finish does the rest run. A problem with fewer rows than
///      options.direct.interior_from_rows then goes to the active-set path whole (exact to
///      round-off where the free blocks are definite; route "active-set"). Rows with cmin = cmax
///      are fixed. With options.direct.memory, body space keeps its pattern and CHOLMOD's analysis
///      from one solve to the next while J's pattern stays (make_exact_memory).
///   2. (route "interior") A primal-dual interior-point method with Mehrotra's predictor-corrector
///   (Mehrotra, SIAM
///      J. Optim. 2(4) 1992; for QPs as in Gertz & Wright, OOQP, ACM TOMS 29(1) 2003), from the
///      box's centre: slack s = λ − cmin and multiplier z ≥ 0 on every finite lower bound,
///      t = cmax − λ and y ≥ 0 on every finite upper bound, w = z − y. Each iteration solves
///      twice with the Newton matrix A + Σ, Σ = z/s + y/t, plus a proximal term
///      ρ = options.direct.proximal · max A_kk on every row (a primal regularisation, Friedlander
///      & Orban, Math. Prog. Comp. 4 2012), which keeps unbounded rows (Σ = 0) and singular A
///      well posed.
///        body space (problem.J and Minv given, Minv's 6×6 blocks positive definite): by the
///        Woodbury identity (A + D)⁻¹ r = D⁻¹ (r − J u), u = (M + Jᵀ D⁻¹ J)⁻¹ Jᵀ D⁻¹ r,
///        D = Σ + ρ + problem.cfm, M = Minv⁻¹: a 6n × 6n positive definite matrix whose
///        pattern never changes, so one CHOLMOD analysis serves the whole solve (simplicial
///        LDLᵀ); A x is formed as J (Minv (Jᵀ x)), after a check on one vector that the
///        problem's A is J Minv Jᵀ + cfm I (else row space);
///        row space (otherwise): CHOLMOD on A + D, again one analysis.
///      Up to three of Gondzio's centrality correctors (Comput. Optim. Appl. 6 1996) follow
///      the corrector, each a further solve with the same factor, kept when it lengthens the
///      step. The Newton directions are not refined: each iteration's residuals are computed afresh
///      from λ, s, t, z, y, so an inexact direction costs no accuracy. The iterations stop when the
///      natural-map residual of λ meets the tolerance, or when the duality measure
///      μ = (sᵀz + tᵀy)/(bounds) ≤ options.direct.interior_mu · scale_of · max(1, ‖b‖∞/max A_kk)
///      and the stationarity residual ≤ √interior_mu · scale_of, or after
///      options.direct.max_interior iterations.
///   3. Crossover: a row starts at its bound when its multiplier outweighs its slack
///      (z_k > A_kk s_k, y_k > A_kk t_k) or its slack is below 1e-4 ‖b‖∞ / max A_kk, and the
///      active-set path's method (proximal points around a monotone primal active set,
///      active_set.hpp) finishes from that partition with no PGS sweeps: islands (islands.hpp) of
///      up to 500 rows apart, on their own free blocks of A from ε = 0; larger islands then
///      together in body space (the same pattern, bound rows dropped: D⁻¹ = 0) from ε = 1e-6 · max
///      A_kk. There the factor of H is updated as rows join or leave the free set (CHOLMOD's
///      rank-one update/downdate of H ± ω_k J_kᵀ J_k; Davis & Hager, SIAM J. Matrix Anal. Appl.
///      20(3) 1999) rather than made anew; a step that rows block is taken unrefined (the next
///      right-hand side g − H x corrects it), a full step after two refinement passes.
/// Tolerance: the natural-map residual ≤ options.tolerance, or ≤ residual_floor once steps stop
/// reducing it (may_stop); a guess in lambda already within max(tolerance, floor) is taken as it
/// is (solving again would only move λ by rounding). Returns
/// Termination::Direct when reached, NotConverged otherwise (inconsistent equality rows, an
/// infeasible box), with the best λ found; NonFinite for non-finite A or b. The summary's
/// iterations are the interior iterations; crossover counts the active-set path's outer
/// (proximal) steps; it reports the factorizations, the rows updated in a factor, the largest
/// factor's nonzeros, the space (body or row) and the route (SolverSummary::route). With CFM,
/// solve() hands A + eps E here with problem.cfm = eps, so the body space factors D = Σ + ρ + eps.
SolverSummary solve_direct(const BoxedProblem& problem,
                           VecX& lambda,
                           const SolverOptions& options = {});

/// A fresh ExactMemory for SolverOptions::direct.memory: hand the same one to a sequence of
/// solves of problems that keep J's pattern (the steps of a running scene) and each solve after
/// the first reuses the body-space pattern and CHOLMOD's analysis of it (of the latest two
/// patterns). Not for solves running at the same time.
std::shared_ptr<ExactMemory> make_exact_memory();

/// The natural-map residual no solve can go below at lambda: 64 u (max_i Σ_k |A_ik| ‖λ‖∞ +
/// ‖b‖∞), u the unit roundoff: the rounding of w = A λ − b, with room for the solves' own.
double residual_floor(const BoxedProblem& problem, const VecX& lambda);
/// Whether an exact path may stop at the residual r (N), its previous step having reached
/// r_before (N): at the tolerance; or at or below the rounding floor (N) where the tolerance is 0
/// (the floor asked for) or where the step no longer reduced the residual (a tolerance below the
/// floor is aimed at while steps still make progress; what they cannot reduce is rounding).
bool may_stop(double r, double r_before, double tolerance, double floor);
/// The same with row_sum = max_abs_row_sum(A) given, for solvers that ask it often.
double residual_floor(double row_sum, const VecX& b, const VecX& lambda);
/// Each row's own rounding floor, the rounding of its w_k = (A λ − b)_k alone (b's units):
/// 64 u ((|A| |λ|)_k + |b_k|), with |A| = |J| |Minv| |J|ᵀ + |cfm| where A was left out. No row's
/// exceeds residual_floor, which bounds the largest row's rounding; a row of small entries has a
/// floor of its own size (two contacts of compliances 1e6 and 1e-8 kg⁻¹, forces near 1 N: the
/// shared floor, 5e-9 m/s, passed a λ 50% off on the second, whose w moves 1e-8 m/s per N).
VecX rounding_floors(const BoxedProblem& problem, const VecX& lambda);
/// Whether λ's natural map with each row's step ρ_k (kg; `steps`, c entries: 1 for the map in N,
/// unit_free_steps for the unit-free one; 6.2's map row by row, each contact's cone law on its
/// three rows with its normal row's step, w = A λ − b as the problem forms it) is, row by row
/// and contact by contact, at most max(tolerance, ρ_k f_k) N, f_k that row's rounding_floors (a
/// contact's: the largest of its three). The verdict "at the rounding floor" of the exact paths:
/// each row judged by its own rounding, never by the largest row's. False where a term is NaN.
bool within_rounding(const BoxedProblem& problem,
                     const VecX& lambda,
                     const VecX& steps,
                     double tolerance);

/// Direct solve of A lambda = b with all rows unbounded, by CHOLMOD's sparse Cholesky
/// (supernodal or simplicial, with the fill-reducing ordering CHOLMOD chooses).
/// Throws ComputationError if A is not (numerically) positive definite; solve_direct handles
/// that case.
SolverSummary solve_cholesky(const SpMat& A, const VecX& b, VecX& lambda);

/// CHOLMOD's estimate of the reciprocal condition number of A's Cholesky factor (squared
/// factor diagonal ratio), 0 when the factorization fails. The direct path takes A as
/// numerically definite (lambda unique) when this is ≥ kDefiniteRcond.
double cholesky_rcond(const SpMat& A);
inline constexpr double kDefiniteRcond = 1e-12;

}  // namespace cbps
