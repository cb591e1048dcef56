// Projected Gauss-Seidel (paper 7.1.1) with Nesterov momentum and adaptive restart.
//
// The boxed problem of 6.2 is the optimality condition of min ½ λᵀAλ − bᵀλ over cmin ≤ λ ≤ cmax
// (its gradient is A λ − b = w), and a PGS sweep is one pass of exact coordinate minimisation of
// that quadratic. This method treats a sweep as the "gradient step" of Nesterov's scheme and
// extrapolates between sweeps, with the momentum sequence and the restart of
//   B. O'Donoghue, E. Candès, "Adaptive restart for accelerated gradient schemes",
//   Foundations of Computational Mathematics 15 (2015) 715–732.
// One iteration, from λ_k (N) and λ_{k−1}:
//   t_{k+1} = (1 + √(1 + 4 t_k²)) / 2,   β_k = (t_k − 1) / t_{k+1},   t_1 = 1 (so β_1 = 0)
//   y       = clamp(λ_k + β_k (λ_k − λ_{k−1}), cmin, cmax)       extrapolate, back into the box
//   λ_{k+1} = one PGS sweep (7.1.1) started from y
//   restart (t ← 1, λ_k taken as λ_{k+1}: no momentum in the next step) when
//     (y − λ_{k+1})ᵀ (λ_{k+1} − λ_k) > 0.
// The restart is the paper's gradient scheme: restart when ∇f(y_k)ᵀ(x_{k+1} − x_k) > 0, with the
// gradient replaced by the sweep's step y − λ_{k+1} (the gradient mapping of a projected step,
// which points downhill from y exactly as −∇f does without bounds). Of the paper's two tests it
// is the one that costs nothing here: the function-value test needs f(λ_{k+1}) = ½λᵀAλ − bᵀλ,
// one more product with A per iteration, and near convergence compares numbers that agree to
// round-off; the gradient test reads only vectors the iteration already holds.
//
// MuJoCo 3.11 (changelog, commit c499f7f2 "Nesterov momentum with O'Donoghue-Candès restarts")
// put the same idea into its PGS: β = (k − 1)/(k + 2) (the asymptotic form of the t-sequence
// above), momentum projected onto the bounds and friction cones, and a restart when the sweep's
// correction opposes the extrapolation, (λ_{k+1} − y)ᵀ(y − λ_k) < 0. Ours differs in the
// sequence (the exact t-sequence of the paper) and in the test (the paper's, measured against
// the step λ_{k+1} − λ_k rather than against the extrapolation y − λ_k); MuJoCo also shuffles the
// rows every sweep, which here is options.order = RowOrder::Random.
//
// On the relaxation's cones (BoxedProblem::cones, law ccp) the sweep is nsgs's (cone/nsgs.hpp:
// 7.1.1 with each contact's three rows projected onto its cone, a descent step of the QP over the
// cones) and y is projected onto the cones (project_onto_set), as MuJoCo projects its momentum;
// Coulomb's law is refused (solve(): takes_cone_law), its sweep descending no function.
//
// Cost: one iteration is one sweep-equivalent: one PGS sweep (one pass over A's nonzeros) plus
// O(c) vector work; no extra product with A. Momentum is not monotone: the natural-map residual
// can rise for some iterations before a restart catches it.
#pragma once

#include "cbps/solvers/solver.hpp"

namespace cbps {

/// PGS with Nesterov momentum (above) from the guess in lambda until options.tolerance,
/// options.delta_tolerance (max |λ_{k+1} − λ_k|, N) or options.max_iterations; rows in
/// options.order, relaxation options.relaxation (PSOR). summary.restarts counts the restarts
/// and the message names them. Every iterate lies in [cmin, cmax]. No islands, no CFM.
SolverSummary solve_pgs_nesterov(const BoxedProblem& problem,
                                 VecX& lambda,
                                 const SolverOptions& options,
                                 const PgsNesterovSettings& settings = {});

}  // namespace cbps
