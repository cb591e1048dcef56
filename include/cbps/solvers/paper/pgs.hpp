// Projected Gauss-Seidel (paper 7.1.1) and its relatives over the explicit A: PSOR (relaxation
// omega), symmetric Gauss-Seidel (SSOR), projected Jacobi, and the sweep orders.
#pragma once

#include <random>
#include <vector>

#include "cbps/solvers/solver.hpp"

namespace cbps {

/// One projected Gauss-Seidel sweep (7.1.1), in place, rows k = 0 … c−1:
///   lambda_k ← clamp((b_k − Σ_{i≠k} A_ki lambda_i) / A_kk, cmin_k, cmax_k),
/// each new lambda_k used at once; with relaxation omega ≠ 1 (PSOR) lambda_k moves omega of the
/// way to that value before the clamp. A row with A_kk = 0 (j_c = 0, acting on nothing) keeps
/// its lambda. Returns max |Δlambda_k| (N).
double pgs_sweep(const BoxedProblem& problem, VecX& lambda, double relaxation = 1.0);

/// The same sweep visiting the rows in the order given (a permutation of 0 … c−1).
double pgs_sweep(const BoxedProblem& problem,
                 VecX& lambda,
                 double relaxation,
                 const std::vector<int>& rows);

/// The rows of a sweep in `order`: natural, reversed, or shuffled by rng (Random).
void sweep_order(RowOrder order, int rows, std::mt19937_64& rng, std::vector<int>& out);

/// The rows of a sweep grouped by kind, the contact rows before the friction rows: every
/// distance row, then every contact normal row, then every friction row, each group in `order`
/// (Random: each group shuffled by rng). Bullet's sequential-impulse solver sweeps this way
/// (its joints, then all contacts, then all friction, shuffled within each pool when it
/// randomises): the friction rows then read this sweep's normal forces.
void sweep_order(RowOrder order,
                 const std::vector<RowKind>& kinds,
                 std::mt19937_64& rng,
                 std::vector<int>& out);

/// The row order of every sweep of a Gauss-Seidel solve (pgs, matrix-free): options.order, and
/// the grouping above when options.contacts_first (std::invalid_argument if the problem has no
/// row kinds, e.g. a stored problem). Random orders draw from options.seed.
class SweepOrder {
 public:
  SweepOrder(const BoxedProblem& problem, const SolverOptions& options);
  /// The rows of the next sweep; empty for the natural order without grouping (0 … c−1).
  const std::vector<int>& next();

 private:
  RowOrder order_;
  const std::vector<RowKind>* kinds_ = nullptr;  ///< grouping by kind, or null
  int rows_ = 0;
  std::mt19937_64 rng_;
  std::vector<int> out_;
};

/// One projected Jacobi sweep: as pgs_sweep but every row reads the previous sweep's lambda
/// (kept in scratch); with relaxation omega, lambda ← clamp(lambda + omega (lambda_J − lambda)).
double jacobi_sweep(const BoxedProblem& problem, VecX& lambda, double relaxation, VecX& scratch);

/// PGS (7.1.1) from the guess in lambda until a tolerance or max_iterations, rows in
/// options.order, relaxation options.relaxation. No islands, no CFM: solve() adds those.
SolverSummary solve_pgs(const BoxedProblem& problem, VecX& lambda, const SolverOptions& options);

/// Symmetric Gauss-Seidel: one iteration is a forward sweep and a backward sweep (SSOR with
/// relaxation omega); its iteration matrix is similar to a symmetric one for symmetric A.
SolverSummary solve_sgs(const BoxedProblem& problem, VecX& lambda, const SolverOptions& options);

/// Projected Jacobi from the guess in lambda.
SolverSummary solve_jacobi(const BoxedProblem& problem, VecX& lambda, const SolverOptions& options);

}  // namespace cbps
