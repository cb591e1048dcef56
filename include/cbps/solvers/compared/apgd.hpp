// Accelerated projected gradient descent (APGD) on the boxed problem of 6.2, after
//   H. Mazhar, T. Heyn, D. Negrut, A. Tasora, "Using Nesterov's method to accelerate multibody
//   dynamics with friction and contact", ACM Transactions on Graphics 34(3), article 32, 2015
// (their Algorithm 1, APGD, with the box [cmin, cmax] in place of their friction cones). On a
// problem with cones under the convex relaxation (cone_problem.hpp, law ccp) it is their
// Algorithm 1 itself: the projection is onto each contact's cone (project_onto_set), the
// residual the relaxation's natural map. Coulomb's law is not the optimality condition of a QP,
// so solve() refuses it for apgd.
//
// The boxed problem is the optimality condition of
//   min f(λ) = ½ λᵀAλ − bᵀλ   over cmin ≤ λ ≤ cmax,   ∇f(λ) = A λ − b = w  (m/s², 6.2),
// so a projected gradient step is λ ← clamp(λ − w / L) with L (kg⁻¹, A's unit) an estimate of the
// Lipschitz constant of ∇f, the largest eigenvalue of A. One iteration, from λ_k, y_k, θ_k, L_k:
//   g       = A y_k − b
//   λ_{k+1} = clamp(y_k − g / L_k, cmin, cmax)
//   while f(λ_{k+1}) > f(y_k) + gᵀd + ½ L_k ‖d‖², d = λ_{k+1} − y_k:       backtracking
//     L_k ← grow · L_k, λ_{k+1} = clamp(y_k − g / L_k, cmin, cmax)
//   θ_{k+1} = (−θ_k² + θ_k √(θ_k² + 4)) / 2,   β_{k+1} = θ_k (1 − θ_k) / (θ_k² + θ_{k+1})
//   y_{k+1} = λ_{k+1} + β_{k+1} (λ_{k+1} − λ_k)
//   keep λ_{k+1} as the best iterate if its natural-map residual is the smallest so far
//   if gᵀ(λ_{k+1} − λ_k) > 0:  y_{k+1} = λ_{k+1}, θ_{k+1} = 1                adaptive restart
//   L_{k+1} = shrink · L_k
// and the solve returns the best iterate, not the last (the iteration is not monotone).
// Because f is quadratic, the backtracking test is exactly ½ dᵀA d > ½ L_k dᵀd; the code tests
// it in that form, from A d = A λ_{k+1} − A y_k, which has no cancellation between f values.
//
// Differences from the paper, each a choice: (1) the first L is ‖A‖∞ (the largest absolute row
// sum, an upper bound of A's largest eigenvalue by Gershgorin), free to compute and safe, where
// the paper takes the secant ‖A(λ_0 − 1)‖ / ‖λ_0 − 1‖ (a lower estimate, one product); the
// shrink by 0.9 a step brings an overestimate down within a few dozen steps. (2) Stopping and the
// best iterate use the natural-map residual (N) of the rest of the project, where the paper uses
// its projected-gradient norm. (3) The backtracking loop is capped (max_backtracks) so that
// round-off in dᵀA d for tiny d cannot double L for ever; the paper has no cap. (4) The best
// iterate includes the starting guess, so a warm start is never made worse.
//
// Cost: one iteration is one product with A (A λ_{k+1}) plus one more per backtracking trial; A y
// comes without a product by linearity, A y_{k+1} = (1 + β) A λ_{k+1} − β A λ_k, and w for the
// residual is A λ_{k+1} − b. One product touches each nonzero of A once, as one PGS sweep does,
// so an iteration without backtracking is one sweep-equivalent; summary.message reports the
// products (including the one for the starting guess). The iterates are Jacobi-like (every row
// moves together), with the Euclidean metric: unlike PGS it does not divide each row by A_kk.
#pragma once

#include "cbps/solvers/solver.hpp"

namespace cbps {

/// APGD (above) from the guess in lambda until options.tolerance (natural-map residual, N),
/// options.delta_tolerance (max |λ_{k+1} − λ_k|, N) or options.max_iterations; returns in lambda
/// the iterate with the smallest natural-map residual seen (summary.residual is its residual).
/// summary.restarts counts restarts. after_sweep sees each iterate λ_{k+1}, all in [cmin, cmax].
/// options.order and options.relaxation are not used. No islands, no CFM.
SolverSummary solve_apgd(const BoxedProblem& problem,
                         VecX& lambda,
                         const SolverOptions& options,
                         const ApgdSettings& settings = {});

}  // namespace cbps
