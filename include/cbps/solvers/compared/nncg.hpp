// The nonsmooth nonlinear conjugate gradient method (NNCG) of M. Silcowitz-Hansen, S. Niebe and
// K. Erleben, "A nonsmooth nonlinear conjugate gradient method for interactive contact force
// problems", The Visual Computer 26 (2010) 893–901 (first as "Nonsmooth nonlinear conjugate
// gradient method for interactive contact force problems", VRIPHYS 2009), on the boxed problem
// of 6.2. One projected Gauss-Seidel sweep (7.1.1) plays the part of a gradient step: with
//   r_k = PGS(lambda_k) − lambda_k                      (the negative "gradient", N)
//   beta_k = ‖r_k‖² / ‖r_{k−1}‖²                        (Fletcher–Reeves)
//   beta_k = 0 when beta_k > 1                          (a restart: the direction is dropped)
//   p_k = r_k + beta_k p_{k−1}                          (the search direction, N)
//   lambda_{k+1} = clamp(lambda_k + p_k, cmin, cmax)    (= clamp(PGS(lambda_k) + beta_k p_{k−1}))
// With beta = 0 throughout it is PGS itself; where the active set has settled, the sweep is a
// linear map and the method is PGS accelerated by a conjugate-gradient-like momentum.
//
// How it relates to Bullet's btNNCGConstraintSolver (read, not copied): Bullet also sweeps first
// and then adds beta p_{k−1} with beta from the squared sweep changes, restarting when beta > 1;
// it adds the momentum without projecting (its next sweep clamps each row as it visits it), and on
// a restart it zeroes the whole direction, so p_k = 0 rather than r_k. Here every iterate is
// projected onto [cmin, cmax] at once (the iterates handed to after_sweep and the result are
// feasible, as the paper's PGS steps are) and a restart keeps r_k (beta = 0), as in the paper.
#pragma once

#include "cbps/solvers/solver.hpp"

namespace cbps {

/// NNCG from the guess in lambda (warm start). One iteration = one PGS sweep (7.1.1, one pass
/// over A, relaxation options.relaxation) plus O(c) vector work, so its iteration counts compare
/// one to one with PGS's sweeps. Honours max_iterations, tolerance (natural-map residual, N),
/// delta_tolerance (max |lambda_{k+1} − lambda_k| over the whole iteration, N), after_sweep and
/// describe as solve_pgs does. SolverSummary::restarts counts the restarts (beta_k > restart_beta;
/// the first iteration, which has no previous direction, is not one).
SolverSummary solve_nncg(const BoxedProblem& problem,
                         VecX& lambda,
                         const SolverOptions& options,
                         const NncgSettings& settings = {});

}  // namespace cbps
