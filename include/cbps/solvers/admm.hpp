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
#pragma once

#include "cbps/solvers/solver.hpp"

namespace cbps {

/// The method's own parameters.
struct AdmmSettings {
  /// rho at the start, as a multiple of the mean diagonal of A (rho is in A's unit, kg⁻¹, since
  /// it is added to A's diagonal). Boyd et al. give no default (it is problem-dependent, §3.4.1);
  /// the mean A_kk is the row's own stiffness, and residual balancing corrects a poor start.
  double rho = 1.0;
  /// Over-relaxation alpha (Boyd et al. §3.4.3): the z- and u-updates use
  /// alpha lambda_x + (1 − alpha) z_old in place of lambda_x; 1 = plain ADMM, 1.5–1.8 reported
  /// to speed it up, 1.6 the value quoted there. 0 < alpha < 2.
  double alpha = 1.6;
  /// Residual balancing (Boyd et al. §3.4.1): rho ← tau rho when ‖r‖₂ > mu ‖s‖₂,
  /// rho ← rho / tau when ‖s‖₂ > mu ‖r‖₂, s = rho (z − z_old); mu = 10, tau = 2 are the values
  /// given there. The primal residual is taken at the relaxed point, r = lambda_r − z (the step
  /// of u), as OSQP does with its relaxed iterate (Stellato et al., "OSQP: an operator splitting
  /// solver for quadratic programs", Math. Program. Comput. 12, 2020), not at lambda_x: with
  /// alpha ≠ 1 a free row has lambda_x − z = (1 − alpha)(lambda_x − z_old), which pins
  /// ‖r‖ / ‖s‖ at (alpha − 1) / (alpha rho) and so pins rho (measured on the 20-link chain: rho
  /// stuck at 2.4 kg⁻¹, 792 iterations to 1e-10 relative, against 17 with alpha = 1). Each
  /// change of rho costs one numeric refactorization.
  bool adapt_rho = true;
  double mu = 10.0;
  double tau = 2.0;
  /// The smallest rho balancing may reach, a multiple of the mean diagonal of A. Where no bound
  /// is active ADMM is the proximal point method on A and balancing lowers rho every iteration
  /// (measured on the 20-link chain: to 3e-11 of the mean diagonal); on a singular A (a stack's
  /// four contacts per face) A + rho E then becomes as ill-conditioned as 1 / rho. 1e-8 is a
  /// choice (not from Boyd et al.): it keeps about eight digits in each solve.
  double rho_min = 1e-8;
};

/// ADMM on the box QP of 6.2 from the guess in lambda (warm start: z = clamp(lambda),
/// u = (b − A z) / rho, a fixed point when lambda solves the problem). One iteration:
///   (A + rho E) lambda_x = b + rho (z − u)        one triangular solve pair with the kept
///                                                 CHOLMOD factor of A + rho E
///   lambda_r = alpha lambda_x + (1 − alpha) z      over-relaxation (§3.4.3)
///   z ← clamp(lambda_r + u, cmin, cmax)            projection onto the box (N)
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
