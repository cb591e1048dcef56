// Stored problems for `cbps lcp` and `cbps converge`: a folder written by `cbps matrices` or a
// Siconos .dat file (LCP or relay), held in the paper's convention (6.2).
#pragma once

#include <string>

#include "cbps/io/siconos.hpp"
#include "cbps/system/boxed_problem.hpp"

namespace cbps {

/// The boxed problem of 6.2 as stored: w = A lambda − b, cmin ≤ lambda ≤ cmax. Siconos'
/// w = M z + q, lb ≤ z ≤ ub is M = A, q = −b, lb = cmin, ub = cmax. A `cbps matrices` folder
/// also gives the system's J and Minv (6.1), with which the direct path factors in body space
/// and the matrix-free and shock sweeps can run (has_jacobian()), and its v1, fext and dt, with
/// which v2 (12.3.1) can be formed (has_bodies()).
struct StoredProblem {
  SpMat A;    ///< c×c
  VecX b;     ///< c
  VecX cmin;  ///< c, −∞ allowed
  VecX cmax;  ///< c, +∞ allowed
  bool folder = false;
  SpMatRow J;     ///< c×6n, from J.mtx when the folder has J.mtx and Minv.mtx
  SpMat Minv;     ///< 6n×6n, from Minv.mtx likewise
  VecX v1, fext;  ///< 6n, from v1.mtx and fext.mtx when these, dt.txt, J and Minv are all there
  double dt = 0.0;
  /// Why J and Minv are not here ("no J.mtx in the folder", "a Siconos file carries no J and
  /// Minv"); empty when they are.
  std::string without_jacobian;
  /// Constraint-force mixing eps, kg⁻¹, from the folder's cfm.txt (0 without one): the step
  /// solved the boxed problem of A + eps E (with_cfm), and so do `cbps lcp` and `converge`.
  double cfm = 0.0;
  long rows() const { return static_cast<long>(b.size()); }
  /// J and Minv are here (A = J Minv Jᵀ, 6.2.9): body space for the direct path.
  bool has_jacobian() const { return J.rows() == rows() && J.rows() > 0; }
  /// J, Minv, v1, fext and dt are all here: v2 can be formed (12.3.1).
  bool has_bodies() const { return has_jacobian() && dt > 0.0; }
  /// The boxed problem, with J and Minv when the folder has them. A view: keep this alive.
  BoxedProblem problem() const {
    return has_jacobian() ? BoxedProblem{A, b, cmin, cmax, &J, &Minv}
                          : BoxedProblem{A, b, cmin, cmax};
  }
};

/// A folder (by its A.mtx, b.mtx, cmin.mtx, cmax.mtx, cfm.txt if there is one; J.mtx and
/// Minv.mtx when both are there, and then v1.mtx, fext.mtx and dt.txt when all three are) or a
/// Siconos file. Throws InputError naming
/// the file and line.
/// `kind` says what a .dat file holds (SiconosKind::Auto: from its contents).
StoredProblem read_problem(const std::string& path, SiconosKind kind = SiconosKind::Auto);

/// The bounds and right-hand side of a problem's rows (all of them, or one rank's rows from
/// `first_row`, which the messages number from): cmin ≤ cmax, neither NaN, cmin < +inf and
/// cmax > −inf (a bound no lambda can meet), b finite. Throws InputError naming the file, the
/// vector and its row.
void check_bounds(const VecX& b,
                  const VecX& cmin,
                  const VecX& cmax,
                  const std::string& cmin_file,
                  const std::string& cmax_file,
                  const std::string& b_file,
                  long first_row = 0);

/// A folder's constraint-force mixing eps from its cfm.txt, kg⁻¹; 0 without one. Throws
/// InputError for a text that is not a number >= 0.
double read_cfm(const std::string& dir);

/// InputError naming `what` and max |A − Aᵀ| unless A is symmetric to kSymmetryTolerance
/// (system/boxed_problem.hpp; solve() makes the same test on every solve):
/// the direct path solves the QP of 6.2, which needs it.
void require_symmetric(const StoredProblem& p, const std::string& what);

}  // namespace cbps
