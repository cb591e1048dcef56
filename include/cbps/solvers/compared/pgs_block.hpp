// Block projected Gauss-Seidel: 7.1.1 over blocks of rows (contact manifolds) instead of rows.
#pragma once

#include <vector>

#include "cbps/solvers/solver.hpp"

namespace cbps {

/// One block projected Gauss-Seidel sweep. Rows in blocks of one are updated as in pgs_sweep; a
/// block B of several rows (consecutive rows with the same id ≥ 0 in problem.blocks, a contact
/// manifold's contact and friction rows) is solved exactly for lambda_B with the other rows
/// held, the boxed LCP
///   A_BB lambda_B − (b_B − A_BR lambda_R) = w_B,  cmin_B ≤ lambda_B ≤ cmax_B,
/// with A_BB + delta I, delta = regularization · max_k (A_BB)_kk, by Lemke's method
/// (solve_boxed_lemke), then lambda_B ← clamp(lambda_B + omega (z − lambda_B)). delta makes the
/// block positive definite: a resting face's 12 rows have rank 6, and on the exact block
/// Lemke's pivots break down (answers failing verification by half the force scale, on the
/// 10-box stack hundreds of times per 600 steps); delta = 1e-7 removed every failure there. The
/// bias it leaves, O(delta lambda), shows in the natural-map residual of the unregularised
/// system, which the solvers report (1.8e-5 N on the 10-box stack, weight 98 N). If Lemke still
/// fails on a block, that block gets one row-by-row pass and *fallbacks (if given) grows.
/// Why blocks: the four contact points of a resting face and their friction rows are redundant
/// and coupled; row-by-row PGS shifts load between them slowly and, warm-started step after step
/// with 20 sweeps, a 10-box stack rocks and walks (docs/contacts.md, "Stacks: block PGS"). Returns
/// max |Δlambda|. problem.blocks must be set.
double block_pgs_sweep(const BoxedProblem& problem,
                       VecX& lambda,
                       double relaxation = 1.0,
                       double regularization = 1e-7,
                       int* fallbacks = nullptr);

/// Block PGS (block_pgs_sweep) over problem.blocks from the guess in lambda; plain PGS when
/// the problem has no blocks.
SolverSummary solve_block_pgs(const BoxedProblem& problem,
                              VecX& lambda,
                              const SolverOptions& options);

}  // namespace cbps
