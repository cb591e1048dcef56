// The interior point's Newton matrix on cones (interior_system.hpp): row space on A' + B, body
// space by the Woodbury identity on M + Jᵀ Ω J.
#include "interior_system.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <optional>

namespace cbps {

namespace {

/// Iterative refinement passes of a body-space solve against A' + B: Ω reaches 1 / (md ρ) on
/// a sticking contact, where Ω (md r − J u) cancels (as in the boxed body space).
constexpr int kRefinements = 2;

}  // namespace

std::optional<BodyFactors> body_factors(const BoxedProblem& problem) {
  const std::optional<std::vector<Mat6>> M = body_masses(problem);
  if (!M) return std::nullopt;
  BodyFactors f;
  f.J = *problem.J;
  f.Jt = f.J.transpose();
  f.Minv = *problem.Minv;
  f.cfm = problem.cfm;
  std::vector<Triplet> t;
  t.reserve(36 * M->size());
  for (std::size_t b = 0; b < M->size(); ++b)
    for (int j = 0; j < 6; ++j)
      for (int i = 0; i < 6; ++i) t.emplace_back(int(6 * b) + i, int(6 * b) + j, (*M)[b](i, j));
  f.M.resize(f.J.cols(), f.J.cols());
  f.M.setFromTriplets(t.begin(), t.end());
  return f;
}

InteriorSystem::InteriorSystem(const SpMat& A_scaled,
                               double md,
                               const std::vector<char>& fixed,
                               const std::vector<ConeConstraint>& constraints,
                               const BodyFactors* body)
    : A_(A_scaled),
      md_(md),
      fixed_(fixed),
      constraints_(constraints),
      factors_(body),
      body_(body != nullptr) {
  // As the boxed body space: half the time with Debian's reference BLAS.
  if (body_) factor_.set_simplicial(true);
}

bool InteriorSystem::factor(const std::vector<Mat3>& W, const std::vector<Mat3>& Winv, double rho) {
  Winv_ = Winv;
  rho_ = rho;
  return body_ ? factor_bodies(W, Winv, rho) : factor_rows(Winv, rho);
}

bool InteriorSystem::factor_matrix(const SpMat& H) {
  const bool same = analysed_ && H.nonZeros() == pattern_nnz_;
  const bool ok = same ? factor_.refactor(H, 0.0) : factor_.factor(H, 0.0);
  analysed_ = true;
  pattern_nnz_ = H.nonZeros();
  ++factorizations_;
  if (body_) ++body_factorizations_;
  nonzeros_ = std::max(nonzeros_, factor_.nonzeros());
  return ok;
}

SpMat row_space_matrix(const SpMat& A_scaled,
                       const std::vector<char>& fixed,
                       const std::vector<ConeConstraint>& constraints,
                       const std::vector<Mat3>& Winv,
                       double rho) {
  const Eigen::Index c = A_scaled.rows();
  std::vector<Triplet> t;
  t.reserve(std::size_t(A_scaled.nonZeros() + 9 * Eigen::Index(constraints.size()) + c));
  for (int j = 0; j < A_scaled.outerSize(); ++j) {
    if (fixed[std::size_t(j)]) continue;
    for (SpMat::InnerIterator a(A_scaled, j); a; ++a)
      if (!fixed[std::size_t(a.row())]) t.emplace_back(int(a.row()), j, a.value());
  }
  for (Eigen::Index k = 0; k < c; ++k)
    t.emplace_back(int(k), int(k), fixed[std::size_t(k)] ? 1.0 : rho);
  for (std::size_t j = 0; j < constraints.size(); ++j) {
    const ConeConstraint& k = constraints[j];
    if (!k.cone) {
      t.emplace_back(k.row, k.row, Winv[j](0, 0) * Winv[j](0, 0));
      continue;
    }
    const Vec3 scale(k.a, 1.0, 1.0);
    const Mat3 block = scale.asDiagonal() * (Winv[j] * Winv[j]) * scale.asDiagonal();
    for (int r = 0; r < 3; ++r)
      for (int q = 0; q < 3; ++q) t.emplace_back(k.row + r, k.row + q, block(r, q));
  }
  SpMat H(c, c);
  H.setFromTriplets(t.begin(), t.end());
  return H;
}

bool InteriorSystem::factor_rows(const std::vector<Mat3>& Winv, double rho) {
  return factor_matrix(row_space_matrix(A_, fixed_, constraints_, Winv, rho));
}

/// Ω = D⁻¹ (D = md B + cfm I, 0 on fixed rows), then M + Jᵀ Ω J. Ω's pattern (the diagonal and
/// every contact's 3×3 block, zeros stored) and so H's stay the same at every iteration.
bool InteriorSystem::factor_bodies(const std::vector<Mat3>& W,
                                   const std::vector<Mat3>& Winv,
                                   double rho) {
  const Eigen::Index c = A_.rows();
  const BodyFactors& f = *factors_;
  const double delta = md_ * rho + f.cfm;
  VecX diagonal = VecX::Constant(c, rho);  // B on the rows no cone owns
  std::vector<char> in_cone(std::size_t(c), 0);
  std::vector<Triplet> t;
  t.reserve(std::size_t(c) + 9 * constraints_.size());
  for (std::size_t j = 0; j < constraints_.size(); ++j) {
    const ConeConstraint& k = constraints_[j];
    if (!k.cone) {
      diagonal(k.row) += Winv[j](0, 0) * Winv[j](0, 0);
      continue;
    }
    // Ω = S⁻¹ W (md I + δ W S⁻² W)⁻¹ W S⁻¹ with S = diag(mu, 1, 1).
    const Vec3 s_inv(1.0 / k.a, 1.0, 1.0);
    const Mat3 WS = W[j] * s_inv.asDiagonal();  // W S⁻¹
    const Mat3 inner = md_ * Mat3::Identity() + delta * WS * WS.transpose();
    const Mat3 omega = WS.transpose() * inner.ldlt().solve(WS);
    for (int r = 0; r < 3; ++r) {
      in_cone[std::size_t(k.row + r)] = 1;
      for (int q = 0; q < 3; ++q)
        t.emplace_back(k.row + r, k.row + q, 0.5 * (omega(r, q) + omega(q, r)));
    }
  }
  for (Eigen::Index k = 0; k < c; ++k) {
    if (in_cone[std::size_t(k)]) continue;
    const bool out = fixed_[std::size_t(k)] != 0;
    t.emplace_back(int(k), int(k), out ? 0.0 : 1.0 / (md_ * diagonal(k) + f.cfm));
  }
  Omega_.resize(c, c);
  Omega_.setFromTriplets(t.begin(), t.end());
  const SpMat OJ = Omega_ * f.J;
  const SpMat H = f.M + SpMat(f.Jt * OJ);
  return factor_matrix(H);
}

void InteriorSystem::apply(const VecX& r, VecX& x) const {
  const VecX y = Omega_ * (md_ * r);
  const VecX g = factors_->Jt * y;
  VecX u;
  factor_.solve(g, u);
  x = Omega_ * (md_ * r - factors_->J * u);
}

VecX InteriorSystem::A_times(const VecX& x) const {
  const BodyFactors& f = *factors_;
  VecX y = (f.J * (f.Minv * (f.Jt * x)) + f.cfm * x) / md_;
  for (Eigen::Index k = 0; k < y.size(); ++k)
    if (fixed_[std::size_t(k)]) y(k) = 0.0;
  return y;
}

VecX InteriorSystem::B_times(const VecX& x) const {
  VecX y = rho_ * x;
  for (std::size_t j = 0; j < constraints_.size(); ++j) {
    const ConeConstraint& k = constraints_[j];
    if (!k.cone) {
      y(k.row) += Winv_[j](0, 0) * Winv_[j](0, 0) * x(k.row);
      continue;
    }
    const Vec3 scale(k.a, 1.0, 1.0);
    y.segment<3>(k.row) +=
        scale.asDiagonal() * (Winv_[j] * (Winv_[j] * (scale.asDiagonal() * x.segment<3>(k.row))));
  }
  for (Eigen::Index k = 0; k < y.size(); ++k)
    if (fixed_[std::size_t(k)]) y(k) = 0.0;
  return y;
}

double InteriorSystem::backward_error(const VecX& r, const VecX& x) const {
  const VecX Ax = A_times(x), Bx = B_times(x);
  VecX residual = r - Ax - Bx;
  for (Eigen::Index k = 0; k < r.size(); ++k)
    if (fixed_[std::size_t(k)]) residual(k) = 0.0;
  const double size =
      Ax.lpNorm<Eigen::Infinity>() + Bx.lpNorm<Eigen::Infinity>() + r.lpNorm<Eigen::Infinity>();
  return size > 0.0 ? residual.lpNorm<Eigen::Infinity>() / size : 0.0;
}

bool InteriorSystem::solve(const VecX& r, VecX& x) {
  if (body_) {
    apply(r, x);
    for (int pass = 0; pass < kRefinements; ++pass) {
      VecX dx;
      apply(r - A_times(x) - B_times(x), dx);
      x += dx;
    }
    if (backward_error(r, x) <= kBodyAccuracy) return true;
    // Row space from here on: this scaling factored anew, with its own analysis.
    body_ = false;
    analysed_ = false;
    factor_.set_simplicial(false);
    if (!factor_rows(Winv_, rho_)) return false;
  }
  factor_.solve(r, x);
  return true;
}

}  // namespace cbps
