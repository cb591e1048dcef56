// The matrix-free form of projected Gauss-Seidel (7.1.1 without A), as game engines write it
// (sequential impulses): the same iterates as pgs_sweep to round-off.
#pragma once

#include <vector>

#include "cbps/solvers/solver.hpp"

namespace cbps {

/// A is never built. The sweep keeps W = M⁻¹ Jᵀ (6n × c), the diagonal d_k = j_k W_k = A_kk and
/// u = W lambda, so that (A lambda)_k = j_k u costs one row of J; row k then does
///   lambda_k ← clamp(lambda_k + omega (b_k − j_k u) / d_k),  u ← u + W_k Δlambda_k,
/// which is 7.1.1's update written with A = J M⁻¹ Jᵀ. u is the velocity change per unit time the
/// constraint forces make: v2 = v1 + Δt (u + M⁻¹ f_ext).
class MatrixFreePgs {
 public:
  /// cfm: constraint-force mixing eps, kg⁻¹: the rows solved are those of A + eps E.
  MatrixFreePgs(const SpMatRow& J, const SpMat& Minv, double cfm = 0.0);
  /// u = W lambda (call after changing lambda outside sweep()).
  VecX impulse(const VecX& lambda) const;
  /// One sweep over `rows` (empty: natural order), lambda and u in place; max |Δlambda|.
  double sweep(const VecX& b,
               const VecX& cmin,
               const VecX& cmax,
               VecX& lambda,
               VecX& u,
               double relaxation,
               const std::vector<int>& rows) const;
  /// The natural-map residual with w = J u + eps lambda − b, without A.
  double residual(
      const VecX& b, const VecX& cmin, const VecX& cmax, const VecX& lambda, const VecX& u) const;
  int rows() const { return static_cast<int>(J_.rows()); }

 private:
  const SpMatRow& J_;
  SpMat W_;           ///< M⁻¹ Jᵀ, column k = W_k
  VecX d_;            ///< A_kk + eps = j_k W_k + cfm
  double cfm_ = 0.0;  ///< eps, kg⁻¹
};

/// PGS in the matrix-free form on problem.J and problem.Minv (problem.A is not read) from the
/// guess in lambda; options as for solve_pgs (order, relaxation, tolerances, cfm on the
/// diagonal d; no islands: the rows never meet).
SolverSummary solve_matrix_free(const BoxedProblem& problem,
                                VecX& lambda,
                                const SolverOptions& options);

}  // namespace cbps
