// Stored problems for `cbps lcp` and `cbps converge`: a folder written by `cbps matrices` or a
// Siconos .dat file (LCP or relay), held in the paper's convention (6.2).
#pragma once

#include <string>

#include "cbps/io/siconos.hpp"
#include "cbps/system/boxed_problem.hpp"

namespace cbps {

/// The boxed problem of 6.2 as stored: w = A lambda − b, cmin ≤ lambda ≤ cmax. Siconos'
/// w = M z + q, lb ≤ z ≤ ub is M = A, q = −b, lb = cmin, ub = cmax. A `cbps matrices` folder
/// also gives the system's J, Minv, v1, fext and dt (6.1), so v2 (12.3.1) can be formed and the
/// matrix-free sweep can run; has_bodies() says so.
struct StoredProblem {
  SpMat A;    ///< c×c
  VecX b;     ///< c
  VecX cmin;  ///< c, −∞ allowed
  VecX cmax;  ///< c, +∞ allowed
  bool folder = false;
  SpMatRow J;  ///< c×6n, folders only
  SpMat Minv;  ///< 6n×6n, folders only
  VecX v1, fext;
  double dt = 0.0;
  /// Constraint-force mixing eps, kg⁻¹, from the folder's cfm.txt (0 without one): the step
  /// solved the boxed problem of A + eps E (with_cfm), and so do `cbps lcp` and `converge`.
  double cfm = 0.0;
  long rows() const { return static_cast<long>(b.size()); }
  bool has_bodies() const { return J.rows() == rows() && J.rows() > 0 && dt > 0.0; }
  /// The boxed problem, with J and Minv when the folder has them. A view: keep this alive.
  BoxedProblem problem() const {
    return has_bodies() ? BoxedProblem{A, b, cmin, cmax, &J, &Minv}
                        : BoxedProblem{A, b, cmin, cmax};
  }
};

/// A folder (by its A.mtx, b.mtx, cmin.mtx, cmax.mtx, cfm.txt if there is one; J.mtx, Minv.mtx,
/// v1.mtx, fext.mtx and dt.txt when all are there) or a Siconos file. Throws InputError naming
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
