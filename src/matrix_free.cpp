// The matrix-free form of projected Gauss-Seidel (paper 7.1.1 without A): sequential impulses.
#include <algorithm>
#include <cmath>

#include "cbps/solver.hpp"

namespace cbps {

MatrixFreePgs::MatrixFreePgs(const SpMatRow& J, const SpMat& Minv, double cfm) : J_(J), cfm_(cfm) {
  W_ = SpMat(Minv * SpMat(J.transpose()));  // W = M⁻¹ Jᵀ, 6n × c, column j = W_j
  d_.resize(J.rows());
  for (Eigen::Index j = 0; j < J.rows(); ++j) {
    d_(j) = J.row(j).dot(W_.col(j));  // A_jj
    if (d_(j) > 0.0) d_(j) += cfm_;   // (A + eps E)_jj; a row on nothing stays skipped
  }
}

VecX MatrixFreePgs::impulse(const VecX& lambda) const { return W_ * lambda; }

double MatrixFreePgs::sweep(const VecX& b,
                            const VecX& cmin,
                            const VecX& cmax,
                            VecX& lambda,
                            VecX& u,
                            double relaxation,
                            const std::vector<int>& rows) const {
  const Eigen::Index count = rows.empty() ? J_.rows() : static_cast<Eigen::Index>(rows.size());
  double delta = 0.0;
  for (Eigen::Index k = 0; k < count; ++k) {
    const Eigen::Index j = rows.empty() ? k : rows[static_cast<std::size_t>(k)];
    if (!(d_(j) > 0.0)) continue;  // j_c = 0: acts on nothing, as in pgs_sweep
    double Ju = cfm_ * lambda(j);  // ((A + eps E) lambda)_j = j_j u + eps lambda_j
    for (SpMatRow::InnerIterator it(J_, j); it; ++it) Ju += it.value() * u(it.col());
    const double target = lambda(j) + (b(j) - Ju) / d_(j);  // 7.1.1's unclamped value
    const double next =
        clamp(relaxation == 1.0 ? target : lambda(j) + relaxation * (target - lambda(j)),
              cmin(j),
              cmax(j));
    const double change = next - lambda(j);
    if (!(std::abs(change) <= delta)) delta = std::abs(change);  // also propagates NaN
    if (change != 0.0) {
      for (SpMat::InnerIterator it(W_, j); it; ++it) u(it.row()) += it.value() * change;
    }
    lambda(j) = next;
  }
  return delta;
}

double MatrixFreePgs::residual(
    const VecX& b, const VecX& cmin, const VecX& cmax, const VecX& lambda, const VecX& u) const {
  const VecX w = J_ * u + cfm_ * lambda - b;  // (A + eps E) lambda − b (6.2)
  double r = 0.0;
  for (Eigen::Index k = 0; k < lambda.size(); ++k) {
    const double rk = std::abs(lambda(k) - clamp(lambda(k) - w(k), cmin(k), cmax(k)));
    if (!(rk <= r)) r = rk;
  }
  return r;
}

}  // namespace cbps
