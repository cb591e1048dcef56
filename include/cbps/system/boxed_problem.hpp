// The boxed problem of 6.2, the hand-off from the system to the solvers:
//   find lambda with cmin ≤ lambda ≤ cmax and w = A lambda − b such that
//   lambda_k = cmin_k ⇒ w_k ≥ 0,  lambda_k = cmax_k ⇒ w_k ≤ 0,  cmin_k < lambda_k < cmax_k ⇒ w_k =
//   0.
// Every solver in solvers/ takes this and nothing about bodies, so a step's system and a stored
// problem (a `cbps matrices` folder, a Siconos file) are solved by the same code.
//
//   Symbol   Shape   Unit    Equation
//   A        c×c     kg⁻¹    6.2.9   J Minv Jᵀ, symmetric positive semidefinite
//   b        c       m/s²    6.2.9   upsilon/dt − J (v1/dt + Minv fext)
//   cmin     c       N       5.1     −∞ allowed
//   cmax     c       N       5.1     +∞ allowed
//   lambda   c       N       6.2.1   the unknown
//   w        c       m/s²    6.2     A lambda − b
#pragma once

#include <cmath>
#include <vector>

#include "cbps/base/row_kind.hpp"
#include "cbps/base/types.hpp"
#include "cbps/system/cone_problem.hpp"

namespace cbps {

/// A view of one boxed problem: it refers to storage owned elsewhere (a System, a stored
/// problem, an island's copy), so handing it on copies nothing. When A's factors J and Minv are
/// known (a step's system, a `cbps matrices` folder) they come along: the matrix-free sweep
/// needs them and never reads A. `blocks` groups rows for block PGS: consecutive rows with the
/// same id ≥ 0 form one block (a contact manifold, System::manifold); null: every row alone.
struct BoxedProblem {
  const SpMat& A;
  const VecX& b;
  const VecX& cmin;
  const VecX& cmax;
  const SpMatRow* J = nullptr;               ///< c×6n with A = J Minv Jᵀ, or null
  const SpMat* Minv = nullptr;               ///< 6n×6n, or null
  const std::vector<int>* blocks = nullptr;  ///< c block ids (−1: a row alone), or null
  /// c row kinds (a step's system), or null (a stored problem): the contacts-first sweep order
  /// (SolverOptions::contacts_first) needs them.
  const std::vector<RowKind>* kinds = nullptr;
  /// Constraint-force mixing already in A: A = J Minv Jᵀ + cfm E when J and Minv are given
  /// (solve() sets it when it forms A + eps E), kg⁻¹.
  double cfm = 0.0;
  /// A's rows for the sweeps of 7.1.1 when A is not symmetric: A_rows = Aᵀ, so that column k of
  /// *A_rows (what a column-major sweep reads) is row k of A. Null: A is symmetric to
  /// kSymmetryTolerance and its columns are its rows. solve() (solvers/solver.hpp) sets it, once
  /// per solve; nothing else needs to.
  const SpMat* A_rows = nullptr;
  /// A is symmetric by construction: a step's A = J Minv Jᵀ (6.2.9, System::problem), so
  /// solve() skips its symmetry test (one pass over A, about two PGS sweeps' time, every step).
  /// False: solve() tests it (a stored problem, Python's A).
  bool symmetric = false;
  /// The contacts whose rows live in Coulomb's cone instead of their boxes (cone_problem.hpp),
  /// or null (the paper's boxed problem). Only the methods that take cones (takes_cones,
  /// solver.hpp) solve such a problem; its residual is the cone law's natural map there.
  const FrictionContacts* cones = nullptr;

  Eigen::Index rows() const { return b.size(); }
  bool has_factors() const { return J != nullptr && Minv != nullptr; }
  /// False when A was left out (issue 32's "leave out what the solver does not read": a step
  /// whose method works in body space or matrix-free): A is then empty and the problem's A is
  /// J Minv Jᵀ + cfm E through its J and Minv, which it must carry. The functions below read
  /// it either way; the methods that sweep or factor A get it formed by solve() (formed_A).
  bool A_formed() const { return A.rows() == rows() && A.cols() == rows(); }
};

/// The contacts under Coulomb's box (FrictionLaw::CoulombBox, 5.4), or none (null): each
/// contact's two friction rows are bounded by ±coulomb_bound(mu, lambda_n) of its normal row.
/// Their bounds move with lambda, so such a problem is a fixed point of boxed problems
/// (solvers/paper/coulomb.hpp); the bounds in the BoxedProblem are then only the other rows'.
struct CoulombRows {
  const FrictionContacts* contacts = nullptr;
  /// True when some contact is under Coulomb's box.
  bool any() const { return contacts != nullptr && !contacts->empty(); }
};

/// How symmetric A must be to count as symmetric (the QP of 6.2 and the exact paths need it; a
/// column of a symmetric A is its row): max |A − Aᵀ| ≤ kSymmetryTolerance max(1, max |A_ij|).
/// The one tolerance: solve(), require_symmetric (io/) and the distributed check of TAO's path.
inline constexpr double kSymmetryTolerance = 1e-12;

/// max |A_ik − A_ki| over A's entries, kg⁻¹ (an entry whose mirror is not stored counts whole),
/// in one pass over A without forming Aᵀ.
double max_asymmetry(const SpMat& A);

/// The largest max |A − Aᵀ| a symmetric A may have: kSymmetryTolerance max(1, max |A_ij|), kg⁻¹.
double symmetry_tolerance(const SpMat& A);

/// The projection onto the box [lo, hi] of 7.1.1 and of the natural map: min(max(x, lo), hi).
double clamp(double x, double lo, double hi);

/// ‖A‖∞ = max_i Σ_k |A_ik|, kg⁻¹, A symmetric (column sums are row sums): by Gershgorin no
/// eigenvalue of A exceeds it.
double max_abs_row_sum(const SpMat& A);

/// The row sum the rounding floor of the exact paths is scaled by, kg⁻¹: ‖A‖∞ when A is formed;
/// when it was left out, ‖ |J| |Minv| |J|ᵀ ‖∞ + |cfm| ≥ ‖A‖∞ (one pass over J, A's entries
/// unknown), which is also the scale of the rounding in w = J (Minv (Jᵀ λ)) as that problem
/// forms it.
double max_abs_row_sum(const BoxedProblem& problem);

/// A x, kg⁻¹ N: the product with A, or J (Minv (Jᵀ x)) + cfm x when A was left out.
VecX times_A(const BoxedProblem& problem, const VecX& x);

/// (J Minv Jᵀ + cfm E) x through the factors, J (Minv (Jᵀ x)) + cfm x (6.2.9), kg⁻¹ N: the one
/// place this product is written (times_A, the body-space Newton system, factors_mismatch).
VecX times_factors(const SpMatRow& J, const SpMat& Minv, double cfm, const VecX& x);

/// How far a stored A is from its J and Minv, measured on the test vector x_k = sin(1 + k)
/// (no zero entry, no pattern): the largest |(A x − J Minv Jᵀ x − cfm x)_i| and the largest
/// Σ_k |A_ik x_k|, both kg⁻¹ N, over the rows measured (all of them, or one rank's: the maxima
/// of several ranks' gaps are the whole problem's). The one definition behind factors_mismatch,
/// the check of a folder's A.mtx against its J.mtx and Minv.mtx (read_problem) and the same
/// check under MPI.
struct FactorsGap {
  double difference = 0.0;  ///< max_i |(A x − J Minv Jᵀ x − cfm x)_i|
  double size = 0.0;        ///< max_i Σ_k |A_ik x_k|
  /// difference / size: 0 when they agree exactly, +inf for A = 0 with J Minv Jᵀ ≠ 0, NaN
  /// stays NaN.
  double ratio() const { return difference == 0.0 ? 0.0 : difference / size; }
};

/// How closely A must agree with J Minv Jᵀ + cfm E: FactorsGap::ratio() ≤ this (round-off of
/// the products, far below any change a user could make to a file).
inline constexpr double kFactorsTolerance = 1e-12;

/// x_k = sin(1 + k) for k = first, …, first + count − 1: FactorsGap's test vector.
VecX factors_test_vector(long first, long count);

/// The gap of `A_rows` (some rows of A, every column; x the whole test vector) given the same
/// rows of J Minv Jᵀ x + cfm x (`factors_x`).
FactorsGap factors_gap(const SpMat& A_rows, const VecX& x, const VecX& factors_x);

/// factors_gap(...).ratio() of a whole problem with J and Minv (BoxedProblem::cfm included); 0
/// for no rows or A left out (then A is J Minv Jᵀ + cfm E by definition). The body-space solve
/// needs it ≤ kFactorsTolerance (else it works in row space, on A); solve() refuses
/// matrix-free above it.
double factors_mismatch(const BoxedProblem& problem);

/// A_kk for every row, kg⁻¹: A's diagonal, or J_k Minv J_kᵀ + cfm when A was left out.
VecX diagonal_of_A(const BoxedProblem& problem);

/// The same view with A replaced by `A` (every other field kept; the caller owns `A`), e.g. the
/// problem with A formed (formed_A) for a method that reads A's entries.
inline BoxedProblem with_matrix(const BoxedProblem& problem, const SpMat& A) {
  BoxedProblem p{A, problem.b, problem.cmin, problem.cmax};
  p.J = problem.J;
  p.Minv = problem.Minv;
  p.blocks = problem.blocks;
  p.kinds = problem.kinds;
  p.cfm = problem.cfm;
  p.A_rows = problem.A_rows;
  p.symmetric = problem.symmetric;
  p.cones = problem.cones;
  return p;
}

/// The problem's A as a matrix: A itself when formed, else J Minv Jᵀ + cfm E (6.2.9, compute_A),
/// for the methods that sweep or factor A's entries.
SpMat formed_A(const BoxedProblem& problem);

/// m ← max(m, x) where a NaN, in m or in x, stays: once m is NaN no later finite x replaces it
/// (a residual or a sweep's change must not hide a NaN row behind a later finite one).
inline void max_keep_nan(double& m, double x) {
  if (!(x <= m) && !std::isnan(m)) m = x;
}

/// Row k's term of the natural map (6.2), |lambda_k − clamp(lambda_k − w_k, cmin_k, cmax_k)|, N:
/// the one place the box's natural map is written (the sums below, the cone problem's box rows).
inline double natural_map_row(double lambda, double w, double cmin, double cmax) {
  return std::abs(lambda - clamp(lambda - w, cmin, cmax));
}

/// The natural-map residual for a given w = A lambda − b (6.2):
///   ‖lambda − clamp(lambda − w, cmin, cmax)‖∞,
/// N; zero exactly at a solution, NaN when any term is NaN. The one place this is written: the
/// sparse, matrix-free and dense (Lemke) forms each compute w their own way and call this.
double natural_map_residual(const VecX& w, const VecX& lambda, const VecX& cmin, const VecX& cmax);

/// The natural-map residual of the problem at lambda, with constraint-force mixing eps on A's
/// diagonal (w = (A + eps E) lambda − b; eps in kg⁻¹, 0: the problem as it is), N. With cones,
/// each contact's part is that of its cone law (cone_problem.hpp).
double natural_map_residual(const BoxedProblem& problem, const VecX& lambda, double cfm = 0.0);

/// A + eps E: the matrix a solve with constraint-force mixing eps (kg⁻¹) works on. A itself
/// always stays J Minv Jᵀ.
SpMat with_cfm(const SpMat& A, double eps);

/// The scale residuals are judged against, max(1, ‖b‖∞, max |A_ij|): a residual is small when
/// it is small beside the data. `cbps lcp`, `--check` and the tests use this one definition.
/// With constraint-force mixing eps (kg⁻¹) it is that of A + eps E. When A was left out, max
/// |A_ij| = max A_kk (A = J Minv Jᵀ + cfm E is positive semidefinite: |A_ij|² ≤ A_ii A_jj).
double scale_of(const BoxedProblem& problem, double cfm = 0.0);

}  // namespace cbps
