// Condition number of A (6.2.9): exact for small systems, Lanczos and inverse iteration for large.
#include "cbps/studies/conditioning.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

#include "cbps/solvers/exact/cholmod_factor.hpp"
#include "cbps/solvers/exact/direct.hpp"

namespace cbps {

namespace {

constexpr double kRoundOff = std::numeric_limits<double>::epsilon() / 2;  // u

ConditionEstimate exact_condition(const SpMat& A) {
  ConditionEstimate e;
  e.exact = true;
  e.method = "exact: dense eigenvalues";
  const Eigen::SelfAdjointEigenSolver<MatX> eig(MatX(A), Eigen::EigenvaluesOnly);
  const VecX& ev = eig.eigenvalues();  // ascending
  const Eigen::Index n = ev.size();
  e.lambda_max = ev(n - 1);
  e.lambda_min = std::max(0.0, ev(0));
  const double zero = static_cast<double>(n) * kRoundOff * e.lambda_max;
  e.nullity = 0;
  double smallest_nonzero = kInf;
  for (Eigen::Index k = 0; k < n; ++k) {
    if (ev(k) <= zero) {
      ++e.nullity;
    } else {
      smallest_nonzero = std::min(smallest_nonzero, ev(k));
    }
  }
  if (e.nullity > 0) e.lambda_min = 0.0;
  e.condition = e.nullity > 0 ? kInf : e.lambda_max / e.lambda_min;
  e.range_condition = std::isfinite(smallest_nonzero) ? e.lambda_max / smallest_nonzero : kInf;
  return e;
}

/// lambda_max of A by m steps of Lanczos from a fixed start (deterministic): the largest Ritz
/// value of the tridiagonal T_m, a lower bound on lambda_max that converges fast at that end.
double lanczos_max(const SpMat& A, int m) {
  const Eigen::Index n = A.rows();
  VecX q = VecX::Ones(n) / std::sqrt(static_cast<double>(n));
  VecX q_prev = VecX::Zero(n);
  std::vector<double> alpha, beta;
  double b = 0.0;
  for (int k = 0; k < m; ++k) {
    VecX w = A * q - b * q_prev;
    const double a = q.dot(w);
    w -= a * q;
    alpha.push_back(a);
    b = w.norm();
    if (!(b > 1e-14 * std::abs(a)) || k + 1 == m) break;
    beta.push_back(b);
    q_prev = q;
    q = w / b;
  }
  const auto size = static_cast<Eigen::Index>(alpha.size());
  MatX T = MatX::Zero(size, size);
  for (Eigen::Index k = 0; k < size; ++k) {
    T(k, k) = alpha[static_cast<std::size_t>(k)];
    if (k + 1 < size) T(k, k + 1) = T(k + 1, k) = beta[static_cast<std::size_t>(k)];
  }
  const Eigen::SelfAdjointEigenSolver<MatX> eig(T, Eigen::EigenvaluesOnly);
  return eig.eigenvalues()(size - 1);
}

}  // namespace

ConditionEstimate estimate_condition(const SpMat& A) {
  if (A.rows() == 0) {
    ConditionEstimate e;
    e.condition = 1.0;
    e.range_condition = 1.0;
    e.nullity = 0;
    e.exact = true;
    e.method = "no rows";
    return e;
  }
  if (A.rows() <= kExactConditionRows) return exact_condition(A);

  ConditionEstimate e;
  e.method = "estimate: Lanczos (lambda_max), inverse iteration on a CHOLMOD factor (lambda_min)";
  e.lambda_max = lanczos_max(A, 60);
  CholmodFactor factor;
  if (!factor.factor(A, 0.0) || factor.rcond() < kDefiniteRcond) {
    e.method =
        "estimate: Lanczos (lambda_max); the Cholesky factor breaks down or has rcond < "
        "1e-12: singular";
    e.condition = kInf;
    return e;
  }
  // Inverse iteration: x ← A⁻¹ x / ‖·‖; the Rayleigh quotient xᵀ A x tends to lambda_min.
  VecX x = VecX::Ones(A.rows()) / std::sqrt(static_cast<double>(A.rows()));
  VecX y;
  double rayleigh = 0.0;
  for (int k = 0; k < 20; ++k) {
    factor.solve(x, y);
    x = y / y.norm();
    rayleigh = x.dot(A * x);
  }
  e.lambda_min = rayleigh;
  e.condition = rayleigh > 0.0 ? e.lambda_max / rayleigh : kInf;
  e.range_condition = e.condition;
  return e;
}

}  // namespace cbps
