// The interior point of the exact path (direct.hpp, its step 2) on one process's rows of the
// boxed problem of 6.2, and a crossover that moves rows in bulk, written so that both run on rows
// spread over the ranks of an MPI job (src/distributed/exact.cpp): everything here works row by
// row, except the Newton system's products and solves (NewtonSystem) and the sums, maxima and
// minima over all rows (RowReduction), which on one process are the identity. The serial exact
// path (direct.cpp) runs the same interior point, then its pivoting crossover.
//
//   Symbol   This process's part                                 Unit
//   b        its rows of b = upsilon/dt − J (v1/dt + Minv fext)  m/s²
//   cmin     its rows (5.1)                                      N
//   cmax     its rows (5.1)                                      N
//   A_kk     its rows of A's diagonal (6.2.9; with any CFM)      kg⁻¹
//   lambda   its rows                                            N
#pragma once

#include <vector>

#include "cbps/solvers/solver.hpp"

namespace cbps {

/// A + diag(d) of the rows kept (d_k > 0); the rows dropped (fixed rows, rows at a bound) are
/// out of the system, x_k = 0. factor() once per d and dropped rows, then apply() any number of
/// times. Vectors hold this process's rows; on rows spread over ranks every call is collective
/// and returns the same on every rank.
class NewtonSystem {
 public:
  virtual ~NewtonSystem() = default;
  /// Factors with the diagonal d (kept rows) and the dropped rows; false when the factorization
  /// fails.
  virtual bool factor(const VecX& d, const std::vector<char>& dropped) = 0;
  /// x ≈ (A + diag d)⁻¹ r on the kept rows, 0 on the dropped ones (one application).
  virtual void apply(const VecX& r, VecX& x) const = 0;
  /// Nonzeros of the Cholesky factor (the factorizing library's count).
  virtual long factor_nonzeros() const = 0;
  /// Numeric factorizations so far, and rows added or removed by updates of a factor.
  virtual int factorizations() const = 0;
  virtual long updates() const { return 0; }
  /// "body" or "row".
  virtual const char* space() const = 0;
  /// y = A x for the problem's A (with any CFM in it); in body space as J (Minv (Jᵀ x)) + cfm x,
  /// several times cheaper than A's own product where A fills (a row of J has at most 12
  /// nonzeros, a row of A one per row its bodies share: 80 on average on the base-40 pyramid).
  virtual void times_A(const VecX& x, VecX& y) const = 0;
  /// apply() followed by two passes of iterative refinement against A + diag(d); false if the
  /// result is not finite (on this process's rows).
  bool solve(const VecX& d,
             const std::vector<char>& dropped,
             const VecX& r,
             VecX& x,
             int refinements = 2) const;
};

/// A body's 6×6 matrix: its block of Minv (kg⁻¹, kg⁻¹ m⁻²) or of M (kg, kg m²).
using Mat6 = Eigen::Matrix<double, 6, 6>;

/// M_B = (Minv_B)⁻¹ for one body's block of Minv (6.1.2), symmetrised; false when the block is
/// not symmetric (to 1e-12) or not positive definite: body space then cannot factor M + Jᵀ D⁻¹ J.
bool body_mass(const Mat6& Minv_block, Mat6& M_block);

/// Sums, maxima and minima over all rows of the problem from each process's own: the identity
/// on one process (this class), an MPI all-reduce on rows spread over ranks. Collective there.
class RowReduction {
 public:
  virtual ~RowReduction() = default;
  virtual double sum(double x) const { return x; }
  /// The largest; NaN when any process's x is NaN (a residual must not hide a NaN row).
  virtual double max(double x) const { return x; }
  virtual double min(double x) const { return x; }
  /// True when `x` is true on every process.
  bool all(bool x) const { return min(x ? 1.0 : 0.0) > 0.5; }
};

/// This process's rows of a boxed problem (references: they must outlive the solve) and what
/// the interior point needs of the whole problem.
struct InteriorRows {
  const VecX& b;         ///< m/s²
  const VecX& cmin;      ///< N
  const VecX& cmax;      ///< N
  const VecX& diagonal;  ///< A_kk, kg⁻¹
  /// scale_of of the whole problem: max(1, ‖b‖∞, max |A_ij|), the residuals' scale.
  double scale = 1.0;
  /// max_i Σ_k |A_ik| of the whole problem (or a bound above it), kg⁻¹: residual_floor's.
  double row_sum = 0.0;
};

/// Where a row sits in a crossover's partition.
enum class Place : unsigned char { Free, Lower, Upper, Fixed };

/// What the interior point did.
struct InteriorOutcome {
  /// The natural-map residual met the tolerance (or the rounding floor, may_stop) during the
  /// iterations: no crossover is needed.
  bool solved = false;
  int iterations = 0;
  long factor_nnz = 0;  ///< the largest factor's nonzeros
  /// The partition the last iterate suggests (direct.hpp's step 3), this process's rows.
  std::vector<Place> place;
};

/// direct.hpp's step 2 on these rows from the box's centre (lambda is overwritten): Mehrotra's
/// predictor-corrector with Gondzio's correctors, its Newton systems by `newton`, sums and
/// extremes over all rows by `all`. Stops at options.tolerance (may_stop), or at
/// options.direct.interior_mu, or after options.direct.max_interior iterations.
InteriorOutcome run_interior_point(const InteriorRows& rows,
                                   NewtonSystem& newton,
                                   const RowReduction& all,
                                   const SolverOptions& options,
                                   VecX& lambda);

/// What the bulk crossover did.
struct CrossoverOutcome {
  bool solved = false;   ///< the natural-map residual met the tolerance (or may_stop's floor)
  int rounds = 0;        ///< proximal steps
  int steps = 0;         ///< solves with the Newton system (each with kRefinements passes)
  long moved = 0;        ///< rows that changed place, in all
  double residual = 0.;  ///< the natural-map residual at the end, N
};

/// The crossover of direct.hpp's step 3 in a form that runs on rows spread over ranks (the
/// pivoting crossover works on one process's A, its islands and its factor's rank-one updates).
/// From `place` (run_interior_point's), rows at a bound are put at it; then proximal steps, each
/// solving min q(x) = ½ xᵀAx − bᵀx + ε/2 |x − λ|² over the box (strongly convex) by a primal
/// active-set method: the free rows' Newton step with (A + εI)_FF (NewtonSystem with the bound
/// rows dropped, refined twice), clamped into the box; when that lowers q its clamped rows go to
/// their bounds all at once, else the step stops at the first bound a row reaches and the rows
/// reaching theirs there (within 1e-3 of their own step) block; after a full step every bound row
/// whose gradient pulls it inwards is freed at once (after a blocked step of length 0 only the
/// worst). q falls at every round, so partitions never repeat; at most 30 rounds a step. ε starts
/// at 1e-6 max A_kk and falls tenfold, down to options.direct.epsilon_floor · max A_kk, whenever a
/// step moved no row and did not halve the residual (the contraction is ε/(σ + ε) for an
/// eigenvalue σ of the free block). Stops at options.tolerance (may_stop) or after
/// options.direct.max_outer_iterations proximal steps. Only row-by-row work, sums and extremes,
/// and the Newton system, so it runs on rows spread over ranks as on one process; each change of
/// the free rows is a new factorization (or an update, where the NewtonSystem makes one).
CrossoverOutcome bulk_crossover(const InteriorRows& rows,
                                NewtonSystem& newton,
                                const RowReduction& all,
                                const SolverOptions& options,
                                std::vector<Place> place,
                                VecX& lambda);

/// The rounding floor of the residual (direct.hpp's residual_floor) with ‖b‖∞ and ‖λ‖∞ given.
double residual_floor_of(double row_sum, double b_norm, double lambda_norm);

}  // namespace cbps
