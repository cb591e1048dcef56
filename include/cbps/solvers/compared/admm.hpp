// ADMM for the boxed problem of 6.2 in the splitting contact codes use (Chrono's ADMM, Tasora,
// Mangoni, Benatti, Garziera, "Solving variational inequalities and cone complementarity
// problems in nonsmooth dynamics using the alternating direction method of multipliers", Int. J.
// Numer. Methods Eng., 2021; ContactBench's ADMM, Le Lidec et al., "Contact models in robotics:
// a comparative analysis", IEEE Trans. Robotics, 2024):
// the boxed problem is the optimality condition of the box QP (6.2)
//   min ½ lambdaᵀ A lambda − bᵀ lambda   subject to cmin ≤ lambda ≤ cmax,
// which ADMM splits as lambda = z with z in the box (Boyd, Parikh, Chu, Peleato, Eckstein,
// "Distributed optimization and statistical learning via the alternating direction method of
// multipliers", Found. Trends Mach. Learn. 3(1), 2011, §3.1.1 scaled form, §5.2 box constraints).
// On a problem with cones under the convex relaxation (cone_problem.hpp, law ccp) the set is
// the cones, as in Tasora et al.'s cone complementarity problem: z is projected onto each
// contact's cone (project_onto_set) and the rest of the iteration is unchanged. Coulomb's law is
// not the optimality condition of a QP, so solve() refuses it for admm.
#pragma once

#include "cbps/solvers/solver.hpp"

namespace cbps {

/// ADMM on the box QP of 6.2 from the guess in lambda (warm start: z = clamp(lambda),
/// u = (b − A z) / rho, a fixed point when lambda solves the problem). One iteration:
///   (A + rho E) lambda_x = b + rho (z − u)        one triangular solve pair with the kept
///                                                 CHOLMOD factor of A + rho E
///   lambda_r = alpha lambda_x + (1 − alpha) z      over-relaxation (§3.4.3)
///   z ← clamp(lambda_r + u, cmin, cmax)            projection onto the box (N), or the cones
///   u ← u + lambda_r − z                           scaled dual, u = y / rho = −w / rho at a
///   solution
/// then residual balancing may change rho (u rescaled by rho_old / rho_new, and A + rho E
/// refactored with the same ordering; SolverSummary::factorizations counts every factorization,
/// the first included). lambda is z after every iteration, so every iterate after_sweep sees
/// lies in [cmin, cmax]. Cost of one iteration: one solve pair with the factor, plus one
/// product with A for the natural-map residual when options.tolerance > 0 (the stopping test of
/// iterate_sweeps), O(nnz(L) + nnz(A)). options.relaxation, order and split_islands are not
/// used (solve() adds islands and CFM). A factorization that fails (A + rho E not positive
/// definite in floating point: NaN in A) ends the solve with Termination::NonFinite.
SolverSummary solve_admm(const BoxedProblem& problem,
                         VecX& lambda,
                         const SolverOptions& options,
                         const AdmmSettings& settings = {});

}  // namespace cbps
