// The boxed problem of 6.2: its residual, its scale, and constraint-force mixing.
#include "cbps/system/boxed_problem.hpp"

#include <algorithm>
#include <cmath>

namespace cbps {

bool CoulombRows::any() const {
  return std::any_of(normal_row.begin(), normal_row.end(), [](int n) { return n >= 0; });
}

double clamp(double x, double lo, double hi) { return std::min(std::max(x, lo), hi); }

double natural_map_residual(const VecX& w, const VecX& lambda, const VecX& cmin, const VecX& cmax) {
  double r = 0.0;
  for (Eigen::Index k = 0; k < lambda.size(); ++k) {
    const double projected = clamp(lambda(k) - w(k), cmin(k), cmax(k));
    const double rk = std::abs(lambda(k) - projected);
    max_keep_nan(r, rk);
  }
  return r;
}

double natural_map_residual(const BoxedProblem& problem, const VecX& lambda, double cfm) {
  if (lambda.size() == 0) return 0.0;
  const VecX w = problem.A * lambda + cfm * lambda - problem.b;  // w = (A + eps E) λ − b (6.2)
  return natural_map_residual(w, lambda, problem.cmin, problem.cmax);
}

SpMat with_cfm(const SpMat& A, double eps) {
  SpMat regularised = A;
  if (eps == 0.0) return regularised;
  for (Eigen::Index k = 0; k < A.rows(); ++k) regularised.coeffRef(k, k) += eps;
  return regularised;
}

double scale_of(const BoxedProblem& problem) {
  double s = 1.0;
  if (problem.b.size() > 0) s = std::max(s, problem.b.lpNorm<Eigen::Infinity>());
  for (Eigen::Index j = 0; j < problem.A.outerSize(); ++j)
    for (SpMat::InnerIterator it(problem.A, j); it; ++it) s = std::max(s, std::abs(it.value()));
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

}  // namespace cbps
