// Projected Gauss-Seidel with subspace minimization (PGS-SM) of M. Silcowitz, S. Niebe and
// K. Erleben, "Projected Gauss-Seidel subspace minimization method for interactive rigid body
// dynamics", GRAPP 2010, after the two-phase method of J.L. Morales, J. Nocedal and
// M. Smelyanskiy, "An algorithm for the fast solution of symmetric linear complementarity
// problems", Numerische Mathematik 111 (2008) 251–266, on the boxed problem of 6.2. It repeats:
//   1. PGS phase: pgs_sweeps sweeps of 7.1.1; they pick the active set, the rows at cmin or cmax
//      (B), and the free rows strictly between (F).
//   2. Subspace phase: conjugate gradients from the current lambda_F on the reduced system
//        A(F,F) lambda_F = b_F − A(F,B) lambda_B                   (w_F = 0 on the free rows, 6.2)
//      for at most cg_iterations steps in the phase, or until ‖r_F‖ ≤ cg_tolerance ‖r_F,0‖. A step
//      that would carry a free row out of the box is cut where the first row meets its bound; that
//      row joins B and CG starts again on the smaller F (the active-set CG of Polyak and
//      O'Leary). Every iterate is therefore in [cmin, cmax], and ½ λᵀAλ − bᵀλ never rises.
//      Departure from the paper, measured: Silcowitz et al. take the full CG solution and project
//      it onto the box; on the 10-box stack that raised the objective and stalled at a relative
//      residual of 1e-6 to 5e-2 (20,000 iterations, 50 to 500 CG iterations per phase), while the
//      cut step reaches 1e-14.
// Where A(F,F) is singular (redundant contacts: four points on one face, a closed loop) the reduced
// system is still consistent when b is (b_F − A(F,B) lambda_B = J_F (…) + upsilon_F / dt lies in
// range(J_F) = range(A(F,F)) whenever the push terms upsilon come from one rigid motion): CG from
// lambda_F starts with r_0 in range(A(F,F)), every direction stays there, p·A p > 0 until r = 0,
// and the iterates converge to lambda_F plus a range correction, one of the solutions. If upsilon
// is not consistent (docs: the stack at steps 1, 3, 4) r keeps its null-space part; a direction
// with p·A p ≤ 0 (relative to round-off) then ends the subspace phase early.
#pragma once

#include "cbps/solvers/solver.hpp"

namespace cbps {

/// PGS-SM from the guess in lambda (warm start). One iteration = one PGS sweep (one pass over
/// A) or one CG step (one product A(F,F) p over A's F columns, plus O(|F|) vector work), so its
/// iteration counts compare with PGS's sweeps. Each start of CG (after a PGS phase, or after a
/// projection shrank F) also forms the reduced residual r_F = b_F − (A lambda)_F, one more such
/// product, counted not in iterations but in SolverSummary::restarts, as is the product of a CG
/// step that breaks down (dᵀAd ≈ 0; that iteration is then a PGS sweep): products with A =
/// iterations + restarts. Every lambda handed to after_sweep is in
/// [cmin, cmax]. Honours max_iterations, tolerance (natural-map residual, N), delta_tolerance
/// (max |Δlambda| in an iteration, N), after_sweep and describe as solve_pgs does; PGS sweeps use
/// options.relaxation. std::invalid_argument for pgs_sweeps < 1 or cg_iterations < 1.
SolverSummary solve_pgs_sm(const BoxedProblem& problem,
                           VecX& lambda,
                           const SolverOptions& options,
                           const PgsSmSettings& settings = {});

}  // namespace cbps
