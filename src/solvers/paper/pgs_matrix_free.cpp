// The matrix-free form of projected Gauss-Seidel (paper 7.1.1 without A): sequential impulses.
#include "cbps/solvers/paper/pgs_matrix_free.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "../sweep.hpp"
#include "cbps/solvers/methods.hpp"
#include "cbps/solvers/paper/pgs.hpp"

namespace cbps {

MatrixFreePgs::MatrixFreePgs(const SpMatRow& J, const SpMat& Minv, double cfm) : J_(J), cfm_(cfm) {
  W_ = SpMat(Minv * SpMat(J.transpose()));  // W = M⁻¹ Jᵀ, 6n × c, column j = W_j
  d_.resize(J.rows());
  for (Eigen::Index k = 0; k < J.rows(); ++k) {
    d_(k) = J.row(k).dot(W_.col(k));  // A_kk
    if (d_(k) > 0.0) d_(k) += cfm_;   // (A + eps E)_kk; a row on nothing stays skipped
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
  for (Eigen::Index n = 0; n < count; ++n) {
    const Eigen::Index k = rows.empty() ? n : rows[static_cast<std::size_t>(n)];
    if (!(d_(k) > 0.0)) continue;  // j_c = 0: acts on nothing, as in pgs_sweep
    double Ju = cfm_ * lambda(k);  // ((A + eps E) lambda)_k = j_k u + eps lambda_k
    for (SpMatRow::InnerIterator it(J_, k); it; ++it) Ju += it.value() * u(it.col());
    const double target = lambda(k) + (b(k) - Ju) / d_(k);  // 7.1.1's unclamped value
    const double next = clamp(detail::relax(lambda(k), target, relaxation), cmin(k), cmax(k));
    const double change = next - lambda(k);
    max_keep_nan(delta, std::abs(change));
    if (change != 0.0) {
      for (SpMat::InnerIterator it(W_, k); it; ++it) u(it.row()) += it.value() * change;
    }
    lambda(k) = next;
  }
  return delta;
}

double MatrixFreePgs::residual(
    const VecX& b, const VecX& cmin, const VecX& cmax, const VecX& lambda, const VecX& u) const {
  const VecX w = J_ * u + cfm_ * lambda - b;  // (A + eps E) lambda − b (6.2)
  return natural_map_residual(w, lambda, cmin, cmax);
}

SolverSummary solve_matrix_free(const BoxedProblem& problem,
                                VecX& lambda,
                                const SolverOptions& options) {
  if (!problem.has_factors())
    throw std::invalid_argument("solver 'matrix-free' works on J and Minv: the problem has none");
  const MatrixFreePgs pgs(*problem.J, *problem.Minv, options.cfm);
  if (lambda.size() != pgs.rows()) lambda = VecX::Zero(pgs.rows());
  VecX u = pgs.impulse(lambda);  // kept equal to W lambda by every sweep
  SweepOrder order(problem, options);
  SolverSummary s = detail::iterate_sweeps(
      pgs.rows(),
      lambda,
      options,
      [&](VecX& l) {
        const std::vector<int>& rows = order.next();  // empty: the natural order
        return pgs.sweep(problem.b, problem.cmin, problem.cmax, l, u, options.relaxation, rows);
      },
      [&](const VecX& l) { return pgs.residual(problem.b, problem.cmin, problem.cmax, l, u); },
      [&](const VecX& l) { return unit_free_residual(problem, l, options.cfm).relative; });
  if (options.describe) s.message.insert(0, "matrix-free: ");
  return s;
}

// This file's entry in the one table of methods (methods.hpp, gathered by methods.cpp).

extern const MethodEntry kMatrixFreeEntry;
constexpr MethodEntry kMatrixFreeEntry{
    .method = Method::MatrixFree,
    .name = "matrix-free",
    .order = true,
    .contacts_first = true,
    .needs_jacobian = true,
    .sweeps_factors = true,
    .sweeps_alone = true,
    .reads_A = false,
    .reads_A_on_cones = false,
    .solve = solve_matrix_free,
    .what = "7.1.1 on J and Minv, without A",
};

}  // namespace cbps
