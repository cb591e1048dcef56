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
///   1. Rows with cmin = cmax are fixed at that value. A problem with no bounded row is one
///      linear solve (solve_active_set: one CHOLMOD factorization of A and refinement).
///   2. A primal-dual interior-point method with Mehrotra's predictor-corrector (Mehrotra, SIAM
///      J. Optim. 2(4) 1992; for QPs as in Gertz & Wright, OOQP, ACM TOMS 29(1) 2003): slack
///      s = λ − cmin and multiplier z ≥ 0 on every finite lower bound, t = cmax − λ and y ≥ 0 on
///      every finite upper bound, w = z − y. Each iteration solves twice with the Newton matrix
///      A + Σ, Σ = z/s + y/t, plus a proximal term ρ = options.direct.proximal · max A_kk on
///      every row (a primal regularisation, Friedlander & Orban, Math. Prog. Comp. 4 2012),
///      which keeps unbounded rows (Σ = 0) and singular A well posed.
///        body space (problem.J and Minv given, Minv's 6×6 blocks positive definite): by the
///        Woodbury identity (A + D)⁻¹ r = D⁻¹ (r − J u), u = (M + Jᵀ D⁻¹ J)⁻¹ Jᵀ D⁻¹ r,
///        D = Σ + ρ + problem.cfm, M = Minv⁻¹: a 6n × 6n positive definite matrix whose
///        pattern never changes, so one CHOLMOD analysis serves the whole solve;
///        row space (otherwise): CHOLMOD on A + D, again one analysis.
///      Each solve is refined twice against A + D (iterative refinement). It stops when the
///      duality measure μ = (sᵀz + tᵀy)/(bounds) ≤ options.direct.interior_mu · scale_of
///      and the stationarity residual is as small, or after options.direct.max_interior
///      iterations.
///   3. Crossover: the active set is read from the interior point (row k at cmin when
///      z_k > A_kk s_k, at cmax when y_k > A_kk t_k, free otherwise), then primal-dual
///      active-set steps (Hintermüller, Ito & Kunisch, SIAM J. Optim. 13(3) 2002): the bound
///      rows at their bounds, the free rows F solved from A_FF λ_F = b_F − A_FB λ_B (consistent
///      but singular: proximal-point steps Δλ_F = −(A_FF + εI)⁻¹ w_F, each in the same body-
///      space pattern with D⁻¹ = 0 on bound rows), then the rows re-partitioned by the sign of
///      λ_k − w_k / A_kk against the box, until the natural-map residual ≤ the tolerance.
///   4. If the crossover does not get there in options.direct.max_crossover partitions, the
///      active-set path (solve_active_set) finishes from the best λ found.
/// Tolerance: the natural-map residual ≤ max(options.tolerance, residual_floor). Returns
/// Termination::Direct when reached, NotConverged otherwise (inconsistent equality rows, an
/// infeasible box), with the best λ found; NonFinite for non-finite A or b. The summary's
/// iterations are the interior iterations; it reports the crossover partitions, the
/// factorizations, the largest factor's nonzeros and the space (body or row). With CFM, solve()
/// hands A + eps E here with problem.cfm = eps, so the body space factors D = Σ + ρ + eps.
SolverSummary solve_direct(const BoxedProblem& problem,
                           VecX& lambda,
                           const SolverOptions& options = {});

/// The natural-map residual no solve can go below at lambda: 64 u (max_i Σ_k |A_ik| ‖λ‖∞ +
/// ‖b‖∞), u the unit roundoff: the rounding of w = A λ − b, with room for the solves' own.
double residual_floor(const BoxedProblem& problem, const VecX& lambda);

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
