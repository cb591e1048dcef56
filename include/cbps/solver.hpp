// Solvers of the boxed problem A lambda = b, cmin ≤ lambda ≤ cmax (paper 6.2, 7).
// They see only (A, b, cmin, cmax), never bodies, so stored problems feed them as well.
#pragma once

#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "cbps/types.hpp"

namespace cbps {

/// The order in which a Gauss-Seidel sweep visits the rows (7.1.1 uses the natural order).
enum class RowOrder {
  Natural,  ///< 0, 1, …, c−1
  Reverse,  ///< c−1, …, 0
  Random    ///< a fresh permutation every sweep, from SolverOptions::seed
};

struct SolverOptions {
  int max_iterations = 100;       ///< sweeps
  double residual_tolerance = 0;  ///< stop when natural_map_residual ≤ this (N); 0 = never
  double delta_tolerance = 0;     ///< stop when max |Δlambda| in a sweep ≤ this (N); 0 = never
  double relaxation = 1.0;        ///< Jacobi damping / SOR factor omega (1 = the paper's 7.1.1)
  bool split_islands = false;     ///< solve independent blocks of A apart (each to tolerance)
  bool describe = true;           ///< write SolverSummary::message (off for each island)
  /// Block PGS: one id per row; consecutive rows with the same id ≥ 0 form a block (a contact
  /// manifold, System::manifold). Null or −1: every row is its own block.
  const std::vector<int>* row_blocks = nullptr;
  /// Block PGS: delta / max_j A_jj of the block, added to the diagonal of each block of
  /// several rows before it is solved (see block_pgs_sweep).
  double block_regularization = 1e-7;
  RowOrder order = RowOrder::Natural;  ///< Gauss-Seidel forms (pgs, psor, matrix-free)
  std::uint64_t seed = 0;              ///< RowOrder::Random: the first permutation's seed
  /// Constraint-force mixing eps, kg⁻¹: every method solves the boxed problem of A + eps E
  /// (with_cfm) instead of A; A itself stays J Minv Jᵀ. Residuals are those of A + eps E. 0: off.
  double cfm = 0.0;
  /// Iterative solvers call this after every sweep with the sweep count, lambda and the seconds
  /// spent in sweeps so far (the call itself is not timed); false ends the solve
  /// (Termination::Stopped). `cbps converge` records its samples here.
  std::function<bool(int, const VecX&, double)> after_sweep;
};

/// Why a solver stopped. NotConverged: the direct path stopped short of its own tolerance (an
/// inconsistent or infeasible system, or stagnation); its best lambda is returned, with the
/// residual that proves how far it is from a solution.
enum class Termination {
  ResidualTolerance,
  DeltaTolerance,
  MaxIterations,
  Direct,
  NotConverged,
  NonFinite,
  Stopped  ///< SolverOptions::after_sweep returned false
};

struct SolverSummary {
  int iterations = 0;      ///< sweeps done; for the direct path its outer (proximal) iterations
  double residual = 0.0;   ///< natural-map residual at the end, N
  double delta = 0.0;      ///< max |Δlambda| of the last sweep, N
  int factorizations = 0;  ///< sparse Cholesky factorizations (direct path)
  int pivots = 0;          ///< active-set exchanges (direct path)
  int restarts = 0;        ///< direct path: islands solved again from 0 after a guess stalled
  int islands = 0;         ///< independent blocks of A solved apart (direct path)
  bool singular = false;   ///< the direct path found a singular block and regularised it
  double wall_time_s = 0.0;
  Termination termination = Termination::MaxIterations;
  std::string message;  ///< one line with the numbers
  bool ok() const { return termination != Termination::NonFinite; }
};

/// Clamp of 7.1.1: min(max(x, lo), hi).
double clamp(double x, double lo, double hi);

/// Natural-map residual ‖lambda − clamp(lambda − w, cmin, cmax)‖∞ with w = (A + cfm E) lambda − b,
/// N. Zero exactly at a solution of the boxed LCP of 6.2 (of A + cfm E when cfm > 0, kg⁻¹).
double natural_map_residual(const SpMat& A,
                            const VecX& b,
                            const VecX& cmin,
                            const VecX& cmax,
                            const VecX& lambda,
                            double cfm = 0.0);

/// A + eps E: the matrix a solve with constraint-force mixing eps (kg⁻¹) works on.
SpMat with_cfm(const SpMat& A, double eps);

/// One projected Gauss-Seidel sweep (7.1.1), in place, rows j = 0 … c−1:
///   lambda_j ← clamp((b_j − Σ_{i≠j} A_ji lambda_i) / A_jj, cmin_j, cmax_j),
/// each new lambda_j used at once. Returns max |Δlambda_j| (N).
double pgs_sweep(const SpMat& A,
                 const VecX& b,
                 const VecX& cmin,
                 const VecX& cmax,
                 VecX& lambda,
                 double relaxation = 1.0);

/// The same sweep visiting the rows in the order given (a permutation of 0 … c−1).
double pgs_sweep(const SpMat& A,
                 const VecX& b,
                 const VecX& cmin,
                 const VecX& cmax,
                 VecX& lambda,
                 double relaxation,
                 const std::vector<int>& rows);

/// The rows of a sweep in `order`: natural, reversed, or shuffled by rng (Random).
void sweep_order(RowOrder order, int rows, std::mt19937_64& rng, std::vector<int>& out);

/// The matrix-free form of PGS (sequential impulses, as game engines write 7.1.1): A is never
/// built. It keeps W = M⁻¹ Jᵀ (6n × c), the diagonal d_j = j_j W_j = A_jj, and u = W lambda, so
/// that (A lambda)_j = j_j u costs one row of J; row j then does
///   lambda_j ← clamp(lambda_j + omega (b_j − j_j u) / d_j),  u ← u + W_j Δlambda_j,
/// which is 7.1.1's update written with A = J M⁻¹ Jᵀ: the same iterates to round-off. u is the
/// velocity change per unit time the constraint forces make: v2 = v1 + Δt (u + M⁻¹ f_ext).
class MatrixFreePgs {
 public:
  /// cfm: constraint-force mixing eps, kg⁻¹: the rows solved are those of A + eps E.
  MatrixFreePgs(const SpMatRow& J, const SpMat& Minv, double cfm = 0.0);
  /// u = W lambda (call after changing lambda outside sweep()).
  VecX impulse(const VecX& lambda) const;
  /// One sweep over `rows` (empty: natural order), lambda and u in place; max |Δlambda|.
  double sweep(const VecX& b,
               const VecX& cmin,
               const VecX& cmax,
               VecX& lambda,
               VecX& u,
               double relaxation,
               const std::vector<int>& rows) const;
  /// w = J u − b, the natural-map residual without A.
  double residual(
      const VecX& b, const VecX& cmin, const VecX& cmax, const VecX& lambda, const VecX& u) const;
  int rows() const { return static_cast<int>(J_.rows()); }

 private:
  const SpMatRow& J_;
  SpMat W_;           ///< M⁻¹ Jᵀ, column j = W_j
  VecX d_;            ///< A_jj + eps = j_j W_j + cfm
  double cfm_ = 0.0;  ///< eps, kg⁻¹
};

/// PGS in the matrix-free form from the guess in lambda; options as for solve_pgs (order,
/// relaxation, tolerances, cfm on the diagonal d; no islands: the rows never meet).
SolverSummary solve_matrix_free(const SpMatRow& J,
                                const SpMat& Minv,
                                const VecX& b,
                                const VecX& cmin,
                                const VecX& cmax,
                                VecX& lambda,
                                const SolverOptions& options);

/// Symmetric Gauss-Seidel: one iteration is a forward sweep and a backward sweep (SSOR with
/// relaxation omega); its iteration matrix is similar to a symmetric one for symmetric A.
SolverSummary solve_sgs(const SpMat& A,
                        const VecX& b,
                        const VecX& cmin,
                        const VecX& cmax,
                        VecX& lambda,
                        const SolverOptions& options);

/// One projected Jacobi sweep: as pgs_sweep but every row reads the previous sweep's lambda;
/// with relaxation omega, lambda ← clamp(lambda + omega (lambda_J − lambda)).
double jacobi_sweep(const SpMat& A,
                    const VecX& b,
                    const VecX& cmin,
                    const VecX& cmax,
                    VecX& lambda,
                    double relaxation,
                    VecX& scratch);

/// One block projected Gauss-Seidel sweep: 7.1.1 over blocks of rows instead of single rows.
/// Rows in blocks of one are updated as in pgs_sweep; a block B of several rows (consecutive
/// rows with the same id ≥ 0 in row_blocks, a contact manifold's contact and friction rows) is
/// solved exactly for lambda_B with the other rows held, the boxed LCP
///   A_BB lambda_B − (b_B − A_BR lambda_R) = w_B,  cmin_B ≤ lambda_B ≤ cmax_B,
/// with A_BB + delta I, delta = regularization · max_j (A_BB)_jj, by Lemke's method
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
/// max |Δlambda|.
double block_pgs_sweep(const SpMat& A,
                       const VecX& b,
                       const VecX& cmin,
                       const VecX& cmax,
                       const std::vector<int>& row_blocks,
                       VecX& lambda,
                       double relaxation = 1.0,
                       double regularization = 1e-7,
                       int* fallbacks = nullptr);

/// PGS (7.1.1) from the guess in lambda until a tolerance or max_iterations.
SolverSummary solve_pgs(const SpMat& A,
                        const VecX& b,
                        const VecX& cmin,
                        const VecX& cmax,
                        VecX& lambda,
                        const SolverOptions& options);

/// Projected Jacobi from the guess in lambda.
SolverSummary solve_jacobi(const SpMat& A,
                           const VecX& b,
                           const VecX& cmin,
                           const VecX& cmax,
                           VecX& lambda,
                           const SolverOptions& options);

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

/// The principal submatrix A(idx, idx) of a symmetric A, idx sorted ascending. `local` is
/// scratch of size A.rows() that holds −1 everywhere on entry and on exit.
SpMat principal_submatrix(const SpMat& A, const std::vector<int>& idx, std::vector<int>& local);

/// The entries v(idx), in the order of idx.
VecX gather_rows(const VecX& v, const std::vector<int>& idx);

/// The independent blocks ("islands") of a symmetric A: connected components of its graph
/// (rows i, j joined when A_ij ≠ 0), each a sorted list of rows, in order of their first row.
std::vector<std::vector<int>> find_islands(const SpMat& A);

/// A solver for one island's sub-problem (A_I, b_I, cmin_I, cmax_I), lambda_I in and out.
using IslandSolve = std::function<void(const SpMat&, const VecX&, const VecX&, const VecX&, VecX&)>;

/// Calls solve_island on each island in turn with its sub-problem (the whole problem as it is
/// when one island covers every row, so nothing is copied) and writes lambda_I back.
void for_each_island(const std::vector<std::vector<int>>& islands,
                     const SpMat& A,
                     const VecX& b,
                     const VecX& cmin,
                     const VecX& cmax,
                     VecX& lambda,
                     const IslandSolve& solve_island);

struct DirectOptions {
  /// Stop when the natural-map residual ≤ max(this, the rounding floor) (N), the floor being
  /// 64 u (max_i Σ_j |A_ij| ‖lambda‖∞ + ‖b‖∞), u the unit roundoff: the rounding of
  /// w = A lambda − b, with room for the regularised solves' own rounding. 0: the floor.
  double tolerance = 0.0;
  int max_outer_iterations = 500;  ///< proximal-point steps per island
  double epsilon = 1e-4;           ///< proximal ε as a fraction of the island's max A_jj
  double epsilon_floor = 1e-10;    ///< smallest ε (same units) once the active set settles
  int start_sweeps = 5;            ///< PGS sweeps (7.1.1) that choose the first active set
  bool split_islands = true;       ///< solve independent blocks of A apart
};

/// The exact path for the boxed problem of 6.2 (cmin ≤ lambda ≤ cmax, w = A lambda − b,
/// complementarity), A symmetric positive semidefinite, sparse. Per island:
///   1. a few PGS sweeps choose the first active set (rows at cmin or cmax);
///   2. a primal active-set method finds the minimiser of
///        min ½ λᵀ (A + εI) λ − (b + ε lambda_k)ᵀ λ  over the box:
///      the Newton step of the free rows (CHOLMOD's sparse Cholesky of the free block, in
///      correction form, i.e. with iterative refinement), the longest step that stays in the
///      box (blocking rows join their bound), then the release of bound rows whose gradient
///      has the wrong sign; the objective falls at every step, so it cannot cycle;
///   3. the proximal-point outer loop lambda_{k+1} = that minimiser converges to a solution of
///      the original problem for any PSD A with a solution. ε = 0 (plain active set, exact in
///      finitely many steps) whenever the free block is numerically positive definite
///      (CHOLMOD's reciprocal condition estimate above 1e-12); otherwise ε starts at
///      options.epsilon · max A_jj and falls by 10× whenever the active set has settled and
///      the residual falls slower than 2× per step, down to options.epsilon_floor · max A_jj;
///      if the active-set search needs too many rounds (100 + 5 rows), ε rises 10× and stays.
/// All-unbounded islands skip step 1 and have nothing to release in step 2: one factorization
/// and refinement; one-row islands are solved in closed form, clamp(b / A_jj). Returns
/// Termination::Direct when the residual reaches the tolerance, NotConverged otherwise (e.g.
/// inconsistent equality rows, an infeasible box), with the best lambda found.
SolverSummary solve_direct(const SpMat& A,
                           const VecX& b,
                           const VecX& cmin,
                           const VecX& cmax,
                           VecX& lambda,
                           const DirectOptions& options = {});

/// Block PGS (block_pgs_sweep) over options.row_blocks, from the guess in lambda; plain PGS
/// when no row shares a block.
SolverSummary solve_block_pgs(const SpMat& A,
                              const VecX& b,
                              const VecX& cmin,
                              const VecX& cmax,
                              VecX& lambda,
                              const SolverOptions& options);

/// By name: "pgs", "block-pgs", "sgs", "jacobi", "direct" (solve_direct). With
/// options.split_islands the iterative solvers run on each island of A apart, each until its own
/// tolerance; the summary then has the largest sweep count and residual of any island. With
/// options.cfm > 0 every method works on with_cfm(A, options.cfm). options.residual_tolerance
/// reaches every method: the direct path stops at max(that, its rounding floor)
/// (DirectOptions::tolerance).
SolverSummary solve(const std::string& method,
                    const SpMat& A,
                    const VecX& b,
                    const VecX& cmin,
                    const VecX& cmax,
                    VecX& lambda,
                    const SolverOptions& options);

/// Names accepted by solve().
bool is_solver_name(const std::string& method);

std::string to_string(Termination t);

/// A solver as named on the command line (`--solver`, `cbps converge --solvers`):
/// NAME[:OMEGA][:order=natural|reverse|random][:warm=on|off], e.g. `psor:1.3`,
/// `pgs:order=random`, `jacobi:0.7`, `sgs`, `matrix-free`, `block-pgs`, `direct`.
///   pgs          7.1.1 (omega = 1); psor:OMEGA is PGS with relaxation 0 < OMEGA < 2
///   jacobi       projected Jacobi; jacobi:OMEGA damps it, 0 < OMEGA ≤ 1
///   sgs          symmetric Gauss-Seidel (forward and backward sweep), sgs:OMEGA is SSOR
///   block-pgs    contact manifolds solved as blocks (block_pgs_sweep)
///   matrix-free  7.1.1 without A (MatrixFreePgs), the sequential-impulse form
///   direct       the exact path (6.2)
/// order applies to pgs, psor and matrix-free; warm=off starts from lambda = 0 instead of the
/// previous step's lambda.
struct SolverSpec {
  std::string text;                    ///< as given
  std::string method;                  ///< pgs, jacobi, sgs, block-pgs, matrix-free, direct
  double relaxation = 1.0;             ///< omega
  RowOrder order = RowOrder::Natural;  ///< Gauss-Seidel forms
  bool warm_start = true;
};

/// Parses one spec; throws InputError naming `what` (the option or JSON path) and the spec:
/// "--solver 'psor:3': relaxation factor '3' must be a number in (0, 2)".
SolverSpec parse_solver_spec(const std::string& text, const std::string& what = "solver");
/// A comma-separated list of specs (`pgs,psor:1.3,direct`).
std::vector<SolverSpec> parse_solver_list(const std::string& text,
                                          const std::string& what = "solvers");
std::string to_string(RowOrder order);

}  // namespace cbps
