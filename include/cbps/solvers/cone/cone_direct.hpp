// The exact path on friction cones: `direct` on a problem whose contacts live in Coulomb's cone
// (BoxedProblem::cones, system/cone_problem.hpp), for both laws.
#pragma once

#include "cbps/solvers/solver.hpp"

namespace cbps {

/// The exact path for a problem with cones, A sparse, any A: where A is not symmetric (a file's
/// W), stage 1 runs on its symmetric part (A + Aᵀ)/2, a start; every other stage, every residual
/// and the verdict use A itself. Every stage works on the problem scaled to max A_kk = 1 and
/// ‖b‖∞ = 1 and judges by the law's natural-map residual (cone_problem.hpp; the box's for rows
/// no contact owns).
///   0. A cheap start under Coulomb's law, in rounds (kQuickRounds): NSGS sweeps (nsgs.hpp)
///      from the guess, then the Newton steps of stage 3 from their answer with a budget of
///      factorizations; on small problems (kQuickProximalRows), where those stop short, stage
///      2's proximal points on Alart–Curnier's function from the best of them (a W of low rank
///      makes Newton's matrix singular at most points: Siconos' OneObject);
///      where that meets the target the stages below are not run, else its answer is kept if it
///      is better than theirs (quick_start in cone_direct.cpp). A solve from λ = 0 of more than
///      kQuickFirstRows rows runs stage 1 first, and this stage only where stage 1's answer does
///      not already keep the law.
///   1. The convex relaxation (CCP: min ½ λᵀAλ − bᵀλ over the cones and the other rows' boxes)
///      by a primal-dual interior-point method on second-order cones: Nesterov–Todd scaling
///      (Nesterov & Todd, SIAM J. Optim. 8(2) 1998), Mehrotra's predictor-corrector, from the
///      cones' axes, as in Vandenberghe's CVXOPT notes ("The CVXOPT linear and quadratic cone
///      program solvers", 2010). A contact's cone is K_mu, a second-order cone once its normal
///      row is scaled by mu (s = (mu λ_n, λ_t1, λ_t2)); a finite bound of a row no contact owns
///      is a cone of dimension one; rows with cmin = cmax are fixed; a contact with mu = 0 is
///      its normal's bound and two tangent rows fixed at 0. Each iteration solves with
///      A + Eᵀ W⁻² E + ρ I (W the scaling, 3×3 blocks per contact; ρ = options.direct.proximal)
///      by CHOLMOD, in body space (M + Jᵀ Ω J) where the problem has J and Minv and the solves
///      stay accurate, in row space otherwise (src/solvers/cone/interior_system.hpp), one
///      analysis for the solve, steps 0.99 of the way to the
///      cones' boundary (1 − gap once the centring weight σ < 1e-3: the fast local phase), and
///      keeps the iterate of least residual, until that meets the target or the gap closes
///      (1e-14). On a singular A with
///      contacts both unloaded and at rest (a stack's corners) complementarity is not strict
///      and the residual stays near the square root of the gap (base-5 pyramid: 1e-6 N from a gap
///      of 1e-8 to 6e-12), hence stage 2.
///   2. Proximal points around a semismooth Newton method (Rockafellar, SIAM J. Control Optim.
///      14(5) 1976; the PROX of Siconos, Acary, Brémond & Huber 2018): λ_{k+1} solves the law
///      for A + ε_k I and b + ε_k λ_k, each by Newton steps on the per-contact natural map
///      F(λ) = λ − P_K(λ − ρ_α û(w)) (ρ_α = 1/λmax(A_αα); the box's with 1/A_kk for the other
///      rows) with the generalized Jacobian I − D + D ρ_α (∂û/∂w)(A + ε I)
///      (D = cone_projection_jacobian), factored by Eigen's SparseLU (one analysis), an Armijo
///      search on ‖F‖₂. A + ε I is definite, so each subproblem has one answer even where A is
///      singular. ε starts at 1e-2 · the scaled residual, follows it down while outer steps
///      halve it and grows ×100 (to 1e-4) when they do not. The outer steps end at the tolerance,
///      at the residual's rounding floor (residual_floor), or after five without progress.
///   3. Coulomb's law (De Saxcé's û = u + mu ‖u_t‖ e_n): first stage 1 on the CCP, whose
///      answer stands where it keeps Coulomb's law too (a pile at rest, where no contact slides:
///      cone pyramids of 100 to 1,600 contacts); else stage 1 again with De Saxcé's term moved
///      into b and refreshed at every iterate (b_n − mu ‖w_t‖ at the current λ, the iterate kept
///      by Coulomb's residual): a pile settling under the paper's box, whose answer has contacts
///      opening, sticking and sliding at 1e-9 m/s, finishes there (base-3 pyramid: 46
///      iterations, where the rest of this stage stalls at 1.8e-9 N). Where it does not finish
///      (A symmetric), stage 1 once more with the term also differentiated in its Newton
///      matrix, mu (w_tᵀ/‖w_t‖_ε) A_t in each normal row, ‖w_t‖ smoothed by ε = 0.1 √gap
///      (not symmetric: SparseLU), stopped where its steps jam at the cones' boundary; the
///      better of the two goes on (the base-7 pile: 72 iterations, 0.26 s, where stage 5 took
///      17 s). Where neither finishes,
///      semismooth Newton steps on Alart and Curnier's function of the contacts (Alart &
///      Curnier, Comput. Methods Appl. Mech. Engrg. 92, 1991: the same solutions, with u_t
///      entering linearly, so no kink where a contact sticks or slides slowly; the NSN-AC of
///      Siconos), from the better of the two interior answers, then from the other: the
///      Jacobian G is not symmetric (SparseLU); Newton's step where it is whole, else a
///      Levenberg–Marquardt step (GᵀG + ‖F‖ I) d = −Gᵀ F (CHOLMOD; Fan & Yuan, Computing 74,
///      2005: fast where the solutions are not isolated); where those do not finish, the fixed
///      point on s = mu ‖u_t‖ (each round the CCP of b_n − s by stages 1 and 2; Haslinger's
///      approach, Acary et al. 2018) while each round cuts Coulomb's residual by a tenth, at
///      most 20 rounds, then proximal Newton on Alart–Curnier's function, then Newton's steps
///      again from the best point; the best answer of these. Where A is not symmetric the CCP
///      of b_n − s is no QP and its rounds are no map of s: there Newton's steps run from the
///      better interior answer alone, until five in a row lower the residual by less than a
///      tenth, then proximal Newton on Alart–Curnier's function from their best point (Siconos'
///      Capsules: 0.05 to 0.16 s, where the fixed point and stage 4 took 0.2 to 0.46 s).
///   4. Where stages 1 to 3 stop short (either law): rounds of NSGS sweeps (nsgs.hpp) on the
///      problem from the best point so far, then from zero, each followed by Newton's steps on
///      Alart–Curnier's function (the relaxation: stage 2) from the sweeps' answer
///      (sweeps_then_newton in cone_direct.cpp): the sweeps converge linearly where Newton's
///      steps stall on a rank-deficient W, and Newton's steps finish from their answer.
///   5. Coulomb's law on a symmetric A where stages 1 to 4 stop short: the fixed point on De
///      Saxcé's term averaged, s ← (1 − a) s + a mu ‖u_t(s)‖ with a = 0.7, halved where the
///      rounds cycle (Krasnosel'skii 1955, Mann 1953), Newton's steps on Alart–Curnier's
///      function again from the rounds each time they close in tenfold, each round the CCP of b_n −
///      s by stages 1 and 2, to a hundredth of the rounds' best Coulomb residual; the CCP's w is
///      unique (a convex QP's: A symmetric), so the rounds are a map of s alone, whose fixed points
///      solve Coulomb's law (Acary, Cadoux, Lemaréchal & Malick 2011). Where the plain rounds of
///      stage 3 cycle (the larger piles settling under the paper's box) the averaged ones converge,
///      linearly and slowly (averaged_fixed_point in cone_direct.cpp: at most 2,000 rounds and
///      40,000 factorizations of its own, no more than 3e7 / rows, ended by 150 rounds in a row
///      that do not halve the best residual). On an A that is not symmetric, where that argument
///      fails, proximal points in the schedule of Siconos' PROX instead (proximal_points in
///      cone_direct.cpp; Rockafellar 1976): from the best point, each step Coulomb's law with
///      A + ε I and b + ε x_k around the centre x_k, solved by stage 3's steps on Alart–Curnier's
///      function to a hundredth of the centre's residual, its answer the next centre whether or
///      not the residual fell; ε = 0.05 r at first, a quarter of the last (never below 0.05 r)
///      after a solved subproblem, 10 times it after one not solved; at most 5,000
///      factorizations of its own, no more than 3e7 / rows, ended by 1,000 steps in a row that do
///      not lower the best residual by a tenth (Siconos' Capsules with every mu halved, where
///      stages 1 to 4 stop near 1e-8: 0.4 to 2.4 s).
///   6. Coulomb's law where stages 1 to 5 stop short: a search over the contacts' statuses
///      (status_search in cone_direct.cpp): each contact's status fixed (open, sticking,
///      sliding), the law becomes smooth equations, solved by Levenberg–Marquardt's
///      least-squares steps from the best point; the natural map's statuses there first, then
///      one contact's status changed for each of the 8 whose equations are furthest from zero
///      (an active-set step: Stellato et al., "OSQP", Math. Prog. Comp. 12, 2020). Every answer
///      is judged by the law's residual.
///   7. Coulomb's law on an A that is not symmetric, where stages 1 to 6 stop short: the law on
///      A's symmetric part first, by the stages of a symmetric A, then on A itself from that
///      answer (Alart–Curnier's steps, proximal points, the status search; symmetric_part_first
///      in cone_direct.cpp): where A's asymmetry is round-off, the symmetric part's answer is
///      within it of A's. Only where the skew part's w at the best point is at most that
///      point's residual. Where none of this finishes (Siconos' RockPile, docs/cones.md), it
///      says so.
/// Newton's matrices (stages 2 to 4) are factored sparse, or dense (LU with partial pivoting)
/// on problems of at most kDenseRows rows, where the sparse analysis and products cost more than
/// the arithmetic (NewtonMatrix in cone_direct.cpp).
/// Stages 1 to 3 spend at most 300 factorizations, stage 4 at most 100 more, stage 5 its own
/// min(40,000, 3e7 / rows) (A symmetric) or min(5,000, 3e7 / rows), stage 6 min(400, 3e5 /
/// rows), stage 7 the same again for each of its two parts: every stage stops there (the
/// relaxation needs far fewer), and at the deadline (SolverOptions::time_limit). Returns
/// Termination::Direct only when the law's residual of lambda is at most the tolerance read in N
/// and as a unit-free residual (UnitFreeTarget::both, system/unit_free.hpp) or the rounding floor,
/// or, where the tolerance is below 1000 ulps of the force scale or options.tolerance_unit_free is
/// set (a problem in its simulator's units, read through unit-free quantities alone: the stages'
/// path does not change with the units either), when the unit-free residual is at most the
/// tolerance: never an answer it has not verified; otherwise NotConverged with the best lambda
/// found and the message says how far it got (NonFinite for non-finite A or b). The summary:
/// iterations (interior), crossover (proximal steps), factorizations (CHOLMOD and SparseLU
/// together), space "row".
SolverSummary solve_cone_direct(const BoxedProblem& problem,
                                VecX& lambda,
                                const SolverOptions& options);

}  // namespace cbps
