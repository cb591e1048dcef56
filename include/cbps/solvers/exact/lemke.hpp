// An exact (pivoting) reference for the boxed LCP of 6.2: Lemke's complementary pivoting method,
// dense, for any square M (not necessarily symmetric or definite). Independent of PGS and
// CHOLMOD, so the iterative solvers can be checked against it and against external problems.
//
// Notation (Siconos sign convention; the paper's system is M = A, q = −b, lb = cmin, ub = cmax):
//   Symbol | Size | Description
//   M      | n×n  | the LCP matrix
//   q      | n    | the constant term
//   z      | n    | the unknown (the paper's lambda)
//   w      | n    | w = M z + q
//   lb, ub | n    | bounds of the boxed form, ±∞ allowed
// Standard LCP:  w = M z + q,  w ≥ 0,  z ≥ 0,  wᵀz = 0.
// Boxed LCP (relay, MCP):  lb ≤ z ≤ ub;  z_i = lb_i ⇒ w_i ≥ 0,  z_i = ub_i ⇒ w_i ≤ 0,
//   lb_i < z_i < ub_i ⇒ w_i = 0 (for lb_i = ub_i, z_i = lb_i and w_i is free).
#pragma once

#include <chrono>
#include <string>

#include "cbps/base/types.hpp"

namespace cbps {

/// The pivoting's own check of its basis: the LCP residual relative to lcp_scale(M, q) above
/// which a basis is not reported Solved. (The method then judges the answer by cbps's one
/// verdict, system/unit_free.hpp.)
inline constexpr double kLcpSolvedTolerance = 1e-9;

struct LcpResult {
  enum class Status {
    Solved,      ///< verified: residual ≤ kLcpSolvedTolerance · scale
    NoSolution,  ///< ray termination: Lemke's method found no solution (there may be none)
    Failed       ///< pivot limit, numerical breakdown, or an answer that failed verification
  };
  Status status = Status::Failed;
  VecX z;                          ///< n, the last basic solution (meaningful only if Solved)
  VecX w;                          ///< n, M z + q computed from z, not read from the tableau
  int pivots = 0;                  ///< complementary pivots done (including the first, on z0)
  double residual = 0.0;           ///< ‖z − mid(lb, z − w, ub)‖∞, natural-map form
  double relative_residual = 0.0;  ///< residual / max(1, ‖q‖∞, max |M_ij|)
  std::string message;             ///< one line with the numbers
  bool solved() const { return status == Status::Solved; }
};

/// Natural-map residual of the boxed LCP, ‖z − clamp(z − (M z + q), lb, ub)‖∞; zero exactly at
/// a solution. With lb = 0, ub = +∞ it is ‖min(z, w)‖∞ of the standard LCP.
double lcp_residual(const MatX& M, const VecX& q, const VecX& lb, const VecX& ub, const VecX& z);

/// The data's scale max(1, ‖q‖∞, max |M_ij|) that residuals are measured against.
double lcp_scale(const MatX& M, const VecX& q);

/// Lemke's method for the standard LCP (Lemke 1965; Cottle, Pang & Stone 2009, §4.4), covering
/// vector e = (1, …, 1), lexicographic minimum ratio test (no cycling on degenerate problems),
/// pivot limit 100 n + 1000. Finds a solution whenever M is copositive-plus and the LCP is
/// feasible, and for P-matrices always; for other M a ray termination (NoSolution) does not
/// prove that no solution exists. Past `deadline` (none by default) it stops after the pivot in
/// hand (Failed, its last basic point).
LcpResult solve_lemke(
    const MatX& M,
    const VecX& q,
    std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max());

/// The boxed LCP by Lemke's method on an equivalent standard LCP (the transformation is written
/// out in src/solvers/exact/lemke.cpp). Throws InputError if sizes differ, a bound is NaN, or lb_i
/// > ub_i. `deadline` as for solve_lemke.
LcpResult solve_boxed_lemke(
    const MatX& M,
    const VecX& q,
    const VecX& lb,
    const VecX& ub,
    std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max());

std::string to_string(LcpResult::Status s);

}  // namespace cbps
