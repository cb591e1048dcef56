// The boxed problem of 6.2: its residual, its scale, and constraint-force mixing.
#include "cbps/system/boxed_problem.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace cbps {

bool CoulombRows::any() const {
  return std::any_of(normal_row.begin(), normal_row.end(), [](int n) { return n >= 0; });
}

double clamp(double x, double lo, double hi) { return std::min(std::max(x, lo), hi); }

double natural_map_residual(const VecX& w, const VecX& lambda, const VecX& cmin, const VecX& cmax) {
  double r = 0.0;
  for (Eigen::Index k = 0; k < lambda.size(); ++k) {
    max_keep_nan(r, natural_map_row(lambda(k), w(k), cmin(k), cmax(k)));
  }
  return r;
}

double natural_map_residual(const BoxedProblem& problem, const VecX& lambda, double cfm) {
  if (lambda.size() == 0) return 0.0;
  const VecX w = problem.A * lambda + cfm * lambda - problem.b;  // w = (A + eps E) λ − b (6.2)
  if (problem.cones != nullptr)
    return natural_map_residual(w, lambda, problem.cmin, problem.cmax, *problem.cones);
  return natural_map_residual(w, lambda, problem.cmin, problem.cmax);
}

SpMat with_cfm(const SpMat& A, double eps) {
  SpMat regularised = A;
  if (eps == 0.0) return regularised;
  for (Eigen::Index k = 0; k < A.rows(); ++k) regularised.coeffRef(k, k) += eps;
  return regularised;
}

double scale_of(const BoxedProblem& problem, double cfm) {
  double s = 1.0;
  if (problem.b.size() > 0) s = std::max(s, problem.b.lpNorm<Eigen::Infinity>());
  // eps itself where A has no diagonal entry (a diagonal of J Minv Jᵀ is ≥ 0: |A_kk + eps| ≥ eps)
  if (cfm != 0.0 && problem.rows() > 0) s = std::max(s, std::abs(cfm));
  for (Eigen::Index j = 0; j < problem.A.outerSize(); ++j) {
    for (SpMat::InnerIterator it(problem.A, j); it; ++it)
      s = std::max(s, std::abs(it.value() + (it.row() == it.col() ? cfm : 0.0)));
  }
  return s;
}

double max_abs_row_sum(const SpMat& A) {
  double max_row_sum = 0.0;
  for (Eigen::Index j = 0; j < A.outerSize(); ++j) {  // A symmetric: column sums = row sums
    double sum = 0.0;
    for (SpMat::InnerIterator it(A, j); it; ++it) sum += std::abs(it.value());
    max_row_sum = std::max(max_row_sum, sum);
  }
  return max_row_sum;
}

double max_asymmetry(const SpMat& A) {
  if (!A.isCompressed()) return max_asymmetry(SpMat(A));  // the walk below reads compressed columns
  const Eigen::Index n = A.outerSize();
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();  // ascending within each column (Eigen's invariant)
  const double* value = A.valuePtr();
  // next[i]: the first entry of column i not yet matched. Columns are visited in order j = 0, 1,
  // …; an entry (i, j) below the diagonal (i > j) meets its mirror (j, i) in column i, whose rows
  // above the diagonal come up in the same ascending order of j. So each column's upper part is
  // consumed front to back, and what is skipped over had no mirror.
  std::vector<int> next(outer, outer + n);
  double asymmetry = 0.0;
  for (Eigen::Index j = 0; j < n; ++j) {
    int p = next[std::size_t(j)];
    for (; p < outer[j + 1] && inner[p] < j; ++p)  // (r, j), r < j: its mirror (j, r) is absent
      asymmetry = std::max(asymmetry, std::abs(value[p]));
    for (; p < outer[j + 1]; ++p) {
      const int i = inner[p];
      if (i == j) continue;
      int& q = next[std::size_t(i)];
      for (; q < outer[i + 1] && inner[q] < j; ++q)  // column i's upper entries without a mirror
        asymmetry = std::max(asymmetry, std::abs(value[q]));
      if (q < outer[i + 1] && inner[q] == j) {
        asymmetry = std::max(asymmetry, std::abs(value[p] - value[q]));
        ++q;
      } else {
        asymmetry = std::max(asymmetry, std::abs(value[p]));
      }
    }
  }
  return asymmetry;
}

double symmetry_tolerance(const SpMat& A) {
  double largest = 1.0;
  for (Eigen::Index k = 0; k < A.nonZeros(); ++k)
    largest = std::max(largest, std::abs(A.valuePtr()[k]));
  return kSymmetryTolerance * largest;
}

}  // namespace cbps
