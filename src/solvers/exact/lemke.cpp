// Lemke's complementary pivoting method, dense tableau (Lemke 1965; Cottle, Pang & Stone 2009,
// "The Linear Complementarity Problem", §4.4, Algorithm 4.4.5 with the lexicographic rule of
// §4.9).
//
// The augmented problem. With the covering vector e = (1, …, 1) and an artificial variable z0,
//   w = q + M z + e z0,  w ≥ 0, z ≥ 0, z0 ≥ 0,  w_i z_i = 0,
// written as the linear system [I, −M, −e] [w; z; z0] = q. The tableau T = B⁻¹ [I, −M, −e, q]
// (n × (2n + 2)) keeps it in the current basis B; its last column is the basic solution
// x_B = B⁻¹ q and its first n columns are B⁻¹ itself (the w columns start as the identity),
// which the lexicographic ratio test reads.
//   1. If q ≥ 0, z = 0 solves the LCP.
//   2. z0 enters; the row of the most negative q_i leaves (ties: lexicographically), after which
//      every basic variable is ≥ 0 and the basis is "almost complementary".
//   3. The complement of the variable that left enters (w_i ↔ z_i). Minimum ratio test: over the
//      rows with T(i, c) > 0 pick the lexicographic minimum of (x_B, B⁻¹)_i / T(i, c); the rows
//      (x_B, B⁻¹) stay lexicographically positive, so no basis repeats and the method cannot
//      cycle on degenerate problems. If z0 is among the rows tied on x_B alone, it leaves.
//   4. If z0 left, the basis is complementary: z = x_B on its z rows, done. If no row blocks
//      (T(:, c) ≤ 0), the path runs off to infinity: ray termination, Lemke has no solution.
// Ray termination proves that no solution exists when M is copositive-plus (e.g. positive
// semidefinite); for other M it is only the method's failure. P-matrices never ray-terminate.
//
// Every answer is checked on the original data, not on the tableau: z is taken from the final
// basis, re-solved once with a fresh full-pivoting LU of the basic columns of [I, −M] (the
// tableau accumulates rounding over many pivots), and the better of the two is kept; Solved
// only if its natural-map residual is ≤ kLcpSolvedTolerance · lcp_scale.
#include "cbps/solvers/exact/lemke.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "cbps/base/error.hpp"
#include "cbps/solvers/methods.hpp"
#include "cbps/system/boxed_problem.hpp"
#include "cbps/system/unit_free.hpp"

namespace cbps {

namespace {

/// |T(i, c)| ≤ kPivotTolerance · max(1, ‖T(:, c)‖∞) counts as zero: such a row does not block.
constexpr double kPivotTolerance = 1e-11;
/// Ratios within kTieTolerance · max(1, |minimum|) of the minimum are ties (broken by the next
/// column of B⁻¹). Rounding over a few hundred pivots stays well below it on the test data.
constexpr double kTieTolerance = 1e-11;

std::string number(double x) {
  std::ostringstream s;
  s.precision(3);
  s << x;
  return s.str();
}

/// The dense tableau of the augmented problem and its basis. Variables are numbered
/// w_i = i, z_i = n + i, z0 = 2n; column 2n + 1 is x_B.
class Tableau {
 public:
  Tableau(const MatX& M, const VecX& q) : n_(static_cast<int>(q.size())), T_(n_, 2 * n_ + 2) {
    T_.leftCols(n_).setIdentity();
    T_.middleCols(n_, n_) = -M;
    T_.col(z0()).setConstant(-1.0);
    T_.col(rhs()) = q;
    basis_.resize(n_);
    for (int i = 0; i < n_; ++i) basis_[i] = i;
  }

  int z0() const { return 2 * n_; }
  int rhs() const { return 2 * n_ + 1; }
  int complement(int v) const { return v < n_ ? v + n_ : v - n_; }
  int basic(int row) const { return basis_[row]; }
  const std::vector<int>& basis() const { return basis_; }

  /// Lexicographic minimum ratio test for entering column c (step 3); first = step 2, where the
  /// ratios are taken against −T(i, c) = 1 over all rows. Returns −1 if no row blocks.
  int leaving_row(int c, bool first) const {
    const double sign = first ? -1.0 : 1.0;
    const double zero = kPivotTolerance * std::max(1.0, T_.col(c).lpNorm<Eigen::Infinity>());
    std::vector<int> rows;
    for (int i = 0; i < n_; ++i)
      if (sign * T_(i, c) > zero) rows.push_back(i);
    if (rows.empty()) return -1;
    // Keys in order: x_B, then the columns of B⁻¹.
    for (int key = -1; key < n_ && rows.size() > 1; ++key) {
      const int col = key < 0 ? rhs() : key;
      auto ratio = [&](int i) { return T_(i, col) / (sign * T_(i, c)); };
      double least = ratio(rows[0]);
      for (int i : rows) least = std::min(least, ratio(i));
      const double tie = kTieTolerance * std::max(1.0, std::abs(least));
      std::vector<int> kept;
      for (int i : rows)
        if (ratio(i) <= least + tie) kept.push_back(i);
      rows.swap(kept);
      if (key < 0 && !first)
        for (int i : rows)
          if (basis_[i] == z0()) return i;
    }
    return rows[0];
  }

  /// Gauss-Jordan pivot on T(r, c): variable c becomes basic in row r.
  void pivot(int r, int c) {
    T_.row(r) /= T_(r, c);
    for (int i = 0; i < n_; ++i) {
      if (i == r || T_(i, c) == 0.0) continue;
      T_.row(i) -= T_(i, c) * T_.row(r);
      T_(i, c) = 0.0;
    }
    T_(r, c) = 1.0;
    basis_[r] = c;
  }

  bool finite() const { return T_.allFinite(); }

  /// z read from the tableau: x_B on the rows where a z_i is basic, 0 elsewhere.
  VecX z_from_tableau() const {
    VecX z = VecX::Zero(n_);
    for (int i = 0; i < n_; ++i)
      if (basis_[i] >= n_ && basis_[i] < 2 * n_) z(basis_[i] - n_) = T_(i, rhs());
    return z;
  }

 private:
  int n_;
  MatX T_;
  std::vector<int> basis_;
};

/// z from a fresh LU of the basic columns of [I, −M] (z0 is nonbasic at termination):
/// B x_B = q. Returns false if B is singular.
bool z_from_fresh_lu(const MatX& M, const VecX& q, const std::vector<int>& basis, VecX& z) {
  const int n = static_cast<int>(q.size());
  MatX B = MatX::Zero(n, n);
  for (int k = 0; k < n; ++k) {
    const int v = basis[k];
    if (v < n)
      B(v, k) = 1.0;
    else if (v < 2 * n)
      B.col(k) = -M.col(v - n);
    else
      return false;  // z0 still basic
  }
  const Eigen::FullPivLU<MatX> lu(B);
  if (!lu.isInvertible()) return false;
  const VecX x = lu.solve(q);
  if (!x.allFinite()) return false;
  z = VecX::Zero(n);
  for (int k = 0; k < n; ++k)
    if (basis[k] >= n) z(basis[k] - n) = x(k);
  return true;
}

/// Fills z, w and the residuals of r from z on the original (boxed) data.
void evaluate(
    const MatX& M, const VecX& q, const VecX& lb, const VecX& ub, const VecX& z, LcpResult& r) {
  r.z = z;
  r.w = M * z + q;
  r.residual = lcp_residual(M, q, lb, ub, z);
  r.relative_residual = r.residual / lcp_scale(M, q);
}

/// Solved if the relative residual passes, else Failed with the numbers.
void verify(LcpResult& r, const std::string& method) {
  const std::string numbers = "residual " + number(r.residual) + " (relative " +
                              number(r.relative_residual) + ") after " + std::to_string(r.pivots) +
                              " pivots";
  if (r.relative_residual <= kLcpSolvedTolerance && r.z.allFinite()) {
    r.status = LcpResult::Status::Solved;
    r.message = method + ": solved, " + numbers;
  } else {
    r.status = LcpResult::Status::Failed;
    r.message = method + ": complementary basis found but the answer fails verification, " +
                numbers + " > " + number(kLcpSolvedTolerance);
  }
}

void check_sizes(const MatX& M, const VecX& q, const char* who) {
  if (M.rows() != M.cols() || M.rows() != q.size())
    throw InputError(std::string(who) + ": M is " + std::to_string(M.rows()) + "×" +
                     std::to_string(M.cols()) + " but q has " + std::to_string(q.size()) +
                     " entries");
  if (!M.allFinite() || !q.allFinite())
    throw InputError(std::string(who) + ": M or q has a non-finite entry");
}

}  // namespace

double lcp_residual(const MatX& M, const VecX& q, const VecX& lb, const VecX& ub, const VecX& z) {
  return natural_map_residual(VecX(M * z + q), z, lb, ub);  // w = M z + q (6.2, Siconos' signs)
}

double lcp_scale(const MatX& M, const VecX& q) {
  double s = 1.0;
  if (q.size() > 0) s = std::max(s, q.lpNorm<Eigen::Infinity>());
  if (M.size() > 0) s = std::max(s, M.cwiseAbs().maxCoeff());
  return s;
}

LcpResult solve_lemke(const MatX& M,
                      const VecX& q,
                      std::chrono::steady_clock::time_point deadline) {
  check_sizes(M, q, "solve_lemke");
  const int n = static_cast<int>(q.size());
  const VecX lb = VecX::Zero(n);
  const VecX ub = VecX::Constant(n, kInf);
  LcpResult result;

  // Step 1: q ≥ 0.
  if (n == 0 || q.minCoeff() >= 0.0) {
    evaluate(M, q, lb, ub, VecX::Zero(n), result);
    verify(result, "Lemke (q ≥ 0, z = 0)");
    return result;
  }

  Tableau tableau(M, q);
  const int pivot_limit = 100 * n + 1000;
  int entering = tableau.z0();
  for (bool first = true; result.pivots < pivot_limit; first = false) {
    const int r = tableau.leaving_row(entering, first);
    if (r < 0) {
      // Step 4, ray termination.
      evaluate(M, q, lb, ub, tableau.z_from_tableau(), result);
      result.status = LcpResult::Status::NoSolution;
      const int v = entering;
      const std::string name = (v < n ? "w" : "z") + std::to_string(v < n ? v : v - n);
      result.message = "Lemke: ray termination after " + std::to_string(result.pivots) +
                       " pivots (entering " + name +
                       " is unblocked); no solution found. This proves there is none only if "
                       "M is copositive-plus";
      return result;
    }
    const int leaving = tableau.basic(r);
    tableau.pivot(r, entering);
    ++result.pivots;
    if (!tableau.finite()) {
      evaluate(M, q, lb, ub, VecX::Zero(n), result);
      result.status = LcpResult::Status::Failed;
      result.message = "Lemke: non-finite tableau after " + std::to_string(result.pivots) +
                       " pivots (numerical breakdown)";
      return result;
    }
    if (leaving == tableau.z0()) {
      // Step 4, complementary basis: the tableau's z and a fresh LU's, the better one kept.
      evaluate(M, q, lb, ub, tableau.z_from_tableau(), result);
      VecX z_lu;
      if (z_from_fresh_lu(M, q, tableau.basis(), z_lu)) {
        LcpResult polished = result;
        evaluate(M, q, lb, ub, z_lu, polished);
        if (polished.residual < result.residual) result = polished;
      }
      verify(result, "Lemke");
      return result;
    }
    entering = tableau.complement(leaving);
    if (std::chrono::steady_clock::now() >= deadline) {
      evaluate(M, q, lb, ub, tableau.z_from_tableau(), result);
      result.status = LcpResult::Status::Failed;
      result.message =
          "Lemke: stopped at the time limit after " + std::to_string(result.pivots) + " pivots";
      return result;
    }
  }
  evaluate(M, q, lb, ub, tableau.z_from_tableau(), result);
  result.status = LcpResult::Status::Failed;
  result.message = "Lemke: pivot limit " + std::to_string(pivot_limit) + " reached";
  return result;
}

// The boxed LCP as a standard LCP. Each row i gets a base value c_i and one or two standard
// variables (all ≥ 0), z = c + S ζ with S an n×p matrix of ±1 entries:
//   lb finite, ub = +∞     z_i = lb_i + x        x ⊥ w_i                 (S: +1)
//   lb = −∞,  ub finite    z_i = ub_i − x        x ⊥ −w_i                (S: −1)
//   lb = −∞,  ub = +∞      z_i = x⁺ − x⁻         x⁺ ⊥ w_i, x⁻ ⊥ −w_i     (S: +1, −1)
//   lb, ub finite, lb < ub z_i = lb_i + x        x ⊥ w_i + y,
//                          and a slack y ≥ 0     y ⊥ (ub_i − lb_i) − x
//   lb = ub                z_i = lb_i            no variable, w_i free
// For a box: x between the bounds ⇒ y = 0 and w_i = 0; x = 0 ⇒ y = 0, w_i ≥ 0; x = ub − lb ⇒
// w_i = −y ≤ 0, exactly the boxed conditions. With E the p×m map from the box slacks y to their
// x rows, the standard LCP in ζ' = (ζ, y) is
//   M' = [ Sᵀ M S   E ]      q' = [ Sᵀ (M c + q) ]
//        [ −Eᵀ      0 ]           [ ub − lb      ]   (over the m boxed rows)
// M' is positive semidefinite whenever M is (the E blocks are skew), so for the paper's
// A = J M⁻¹ Jᵀ Lemke's method always finds the solution.
LcpResult solve_boxed_lemke(const MatX& M,
                            const VecX& q,
                            const VecX& lb,
                            const VecX& ub,
                            std::chrono::steady_clock::time_point deadline) {
  check_sizes(M, q, "solve_boxed_lemke");
  const int n = static_cast<int>(q.size());
  if (lb.size() != n || ub.size() != n)
    throw InputError("solve_boxed_lemke: lb and ub must have " + std::to_string(n) + " entries");
  for (int i = 0; i < n; ++i)
    if (std::isnan(lb(i)) || std::isnan(ub(i)) || lb(i) > ub(i) || lb(i) == kInf || ub(i) == -kInf)
      throw InputError("solve_boxed_lemke: bounds of row " + std::to_string(i) + " are [" +
                       number(lb(i)) + ", " + number(ub(i)) + "]");

  // The columns of S (row i, sign) and the box slacks (column of their x).
  struct Column {
    int row;
    double sign;
  };
  std::vector<Column> columns;
  std::vector<int> box_x, box_row;
  VecX c = VecX::Zero(n);
  for (int i = 0; i < n; ++i) {
    const bool lower = std::isfinite(lb(i)), upper = std::isfinite(ub(i));
    if (lower && upper && lb(i) == ub(i)) {
      c(i) = lb(i);
    } else if (lower) {
      c(i) = lb(i);
      if (upper) {
        box_x.push_back(static_cast<int>(columns.size()));
        box_row.push_back(i);
      }
      columns.push_back({i, 1.0});
    } else if (upper) {
      c(i) = ub(i);
      columns.push_back({i, -1.0});
    } else {
      columns.push_back({i, 1.0});
      columns.push_back({i, -1.0});
    }
  }
  const int p = static_cast<int>(columns.size());
  const int m = static_cast<int>(box_x.size());
  MatX S = MatX::Zero(n, p);
  for (int k = 0; k < p; ++k) S(columns[k].row, k) = columns[k].sign;

  MatX Mbig = MatX::Zero(p + m, p + m);
  VecX qbig(p + m);
  Mbig.topLeftCorner(p, p) = S.transpose() * M * S;
  qbig.head(p) = S.transpose() * (M * c + q);
  for (int j = 0; j < m; ++j) {
    Mbig(box_x[j], p + j) = 1.0;
    Mbig(p + j, box_x[j]) = -1.0;
    qbig(p + j) = ub(box_row[j]) - lb(box_row[j]);
  }

  const LcpResult inner = solve_lemke(Mbig, qbig, deadline);
  LcpResult result;
  result.pivots = inner.pivots;
  const VecX zeta = inner.z.size() == p + m ? VecX(inner.z.head(p)) : VecX::Zero(p);
  evaluate(M, q, lb, ub, c + S * zeta, result);
  if (inner.status == LcpResult::Status::Solved) {
    verify(result, "boxed Lemke (standard LCP of size " + std::to_string(p + m) + ")");
  } else {
    result.status = inner.status;
    result.message = "boxed " + inner.message;
  }
  return result;
}

std::string to_string(LcpResult::Status s) {
  switch (s) {
    case LcpResult::Status::Solved:
      return "solved";
    case LcpResult::Status::NoSolution:
      return "no solution found";
    case LcpResult::Status::Failed:
      return "failed";
  }
  return "unknown";
}

// This file's entry in the one table of methods (methods.hpp, gathered by methods.cpp).

namespace {

/// "lemke": the dense pivoting method of lemke.hpp on M = D A D, q = −D b with A's diagonal
/// scaled to ±1 (the standard LCP when cmin = 0 and cmax = +inf, else the boxed one), verified
/// on the problem itself: Direct when
/// cbps's verdict holds (is_solved, system/unit_free.hpp). A ray termination whose
/// last point passes that check is a solution, and is reported as one, with the ray named.
SolverSummary lemke_method(const BoxedProblem& problem,
                           VecX& lambda,
                           const SolverOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const long c = problem.rows();
  if (c > kMaxDenseLemkeRows)
    throw InputError("lemke: the problem has " + std::to_string(c) +
                     " rows; the dense Lemke solver takes at most " +
                     std::to_string(kMaxDenseLemkeRows) + " (use pgs or direct)");
  // Lemke's pivot and tie tolerances (1e-11 of max(1, a column's largest entry)) and its check
  // (relative to max(1, ‖q‖∞, max |A_ij|)) are in the units of the largest row: on A = diag(1e4,
  // 1e-8) kg⁻¹ with b = (1e4 / 3, 1e-8) it returned λ_2 = 0 after 2 pivots and called that
  // solved, a unit-free residual of 1. It pivots on D A D with D = diag(1 / sqrt|A_kk|) (1 where
  // A_kk = 0), whose diagonal is ±1 or 0: the same LCP with each row in its own units (z = D z',
  // w' = D w, bounds D⁻¹ cmin and D⁻¹ cmax; D > 0 keeps every sign, so the solutions, the
  // copositivity of M and the ray terminations are the same); λ = D z' is verified on A itself.
  VecX d = VecX::Ones(c);
  for (long k = 0; k < c; ++k) {
    const double a = std::abs(problem.A.coeff(k, k));
    if (a > 0.0 && std::isfinite(1.0 / std::sqrt(a))) d(k) = 1.0 / std::sqrt(a);
  }
  const MatX M = d.asDiagonal() * MatX(problem.A) * d.asDiagonal();
  const VecX q = -d.cwiseProduct(problem.b);
  const bool standard = (problem.cmin.array() == 0.0).all() && (problem.cmax.array() == kInf).all();
  const LcpResult r = standard ? solve_lemke(M, q, options.deadline)
                               : solve_boxed_lemke(M,
                                                   q,
                                                   VecX(problem.cmin.cwiseQuotient(d)),
                                                   VecX(problem.cmax.cwiseQuotient(d)),
                                                   options.deadline);
  lambda = r.z.size() == c ? VecX(d.cwiseProduct(r.z)) : VecX::Zero(c);
  SolverSummary s;
  s.iterations = r.pivots;
  s.pivots = r.pivots;
  s.residual = natural_map_residual(problem, lambda);
  const UnitFreeResidual unit_free = unit_free_residual(problem, lambda);
  const bool passes = is_solved(unit_free, lambda);
  s.message = r.message;
  if (passes) {
    s.termination = Termination::Direct;
    if (!r.solved()) {
      std::ostringstream msg;
      msg << "Lemke: solved: its last point has unit-free residual " << unit_free.relative
          << " <= " << kSolvedTolerance << " (" << s.residual << " N)"
          << ", although the pivoting ended "
          << (r.status == LcpResult::Status::NoSolution ? "in a ray termination"
                                                        : "without a verified basis")
          << " after " << r.pivots << " pivots";
      s.message = msg.str();
    }
  } else {
    if (r.solved()) {  // verified on D A D in its own measure, not on A
      std::ostringstream msg;
      msg << "not verified: " << r.message << " on the scaled tableau, but on A its unit-free "
          << "residual is " << unit_free.relative << " > " << kSolvedTolerance;
      s.message = msg.str();
    }
    s.termination = !lambda.allFinite()                         ? Termination::NonFinite
                    : r.status == LcpResult::Status::NoSolution ? Termination::NoSolution
                                                                : Termination::NotConverged;
  }
  s.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return s;
}

}  // namespace

extern const MethodEntry kLemkeEntry;
constexpr MethodEntry kLemkeEntry{
    .method = Method::Lemke,
    .name = "lemke",
    .iterative = false,
    .max_rows = kMaxDenseLemkeRows,
    .pivots = true,
    .solve = lemke_method,
    .what = "Lemke's complementary pivoting on the dense A: any square A, at most 3000 rows",
};

}  // namespace cbps
