// The unit-free residual (system/unit_free.hpp).
#include "cbps/system/unit_free.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "cbps/base/numbers.hpp"
#include "cbps/system/cone_problem.hpp"

namespace cbps {

UnitFreeResidual unit_free_of(double residual, double scale) {
  UnitFreeResidual u;
  u.residual = residual;
  u.scale = scale;
  if (std::isnan(residual))
    u.relative = std::numeric_limits<double>::quiet_NaN();
  else if (residual == 0.0)
    u.relative = 0.0;
  else
    u.relative = scale > 0.0 ? residual / scale : kInf;
  return u;
}

double unit_free_step(double diagonal, double largest_diagonal) {
  if (diagonal > 0.0) return 1.0 / diagonal;
  return largest_diagonal > 0.0 ? 1.0 / largest_diagonal : 1.0;
}

VecX unit_free_steps(const BoxedProblem& problem, double cfm) {
  const Eigen::Index c = problem.rows();
  if (c == 0) return VecX();
  const VecX diagonal = diagonal_of_A(problem).array() + cfm;
  const double largest = diagonal.maxCoeff();
  VecX rho(c);
  for (Eigen::Index k = 0; k < c; ++k) rho(k) = unit_free_step(diagonal(k), largest);
  if (problem.cones != nullptr) {
    const FrictionContacts& cones = *problem.cones;
    for (long i = 0; i < cones.contacts(); ++i) {
      const int n = cones.normal[std::size_t(i)];
      rho.segment<3>(n).setConstant(unit_free_step(diagonal.segment<3>(n).maxCoeff(), largest));
    }
  }
  return rho;
}

UnitFreeTerms unit_free_terms(const BoxedProblem& problem, const VecX& lambda, double cfm) {
  UnitFreeTerms t;
  const Eigen::Index c = problem.rows();
  t.w = times_A(problem, lambda) + cfm * lambda - problem.b;  // (A + eps E) λ − b (6.2)
  t.rho = unit_free_steps(problem, cfm);
  t.term = VecX::Zero(c);
  std::vector<char> in_cone(std::size_t(c), 0);
  if (problem.cones != nullptr) {
    const FrictionContacts& cones = *problem.cones;
    for (long i = 0; i < cones.contacts(); ++i) {
      const int n = cones.normal[std::size_t(i)];
      const Vec3 r = lambda.segment<3>(n);
      // ρ F(r; u) for the map of u scaled by ρ: the law's û is positively homogeneous in u.
      t.term(n) = cone_natural_map(r, t.rho(n) * t.w.segment<3>(n), cones.mu(i), cones.law).norm();
      in_cone[std::size_t(n)] = in_cone[std::size_t(n + 1)] = in_cone[std::size_t(n + 2)] = 1;
    }
  }
  for (Eigen::Index k = 0; k < c; ++k) {
    if (in_cone[std::size_t(k)]) continue;
    t.term(k) = natural_map_row(lambda(k), t.rho(k) * t.w(k), problem.cmin(k), problem.cmax(k));
  }
  if (c > 0)
    t.scale = std::max(lambda.lpNorm<Eigen::Infinity>(),
                       (t.rho.array() * problem.b.array().abs()).maxCoeff());
  return t;
}

UnitFreeResidual unit_free_residual(const BoxedProblem& problem, const VecX& lambda, double cfm) {
  UnitFreeResidual u;
  if (lambda.size() != problem.rows()) {
    u.relative = kInf;  // no answer to this problem
    return u;
  }
  if (problem.rows() == 0) return u;
  const UnitFreeTerms t = unit_free_terms(problem, lambda, cfm);
  for (Eigen::Index k = 0; k < t.term.size(); ++k) max_keep_nan(u.residual, t.term(k));
  return unit_free_of(u.residual, t.scale);
}

UnitFreeResidual unit_free_rows(const Eigen::Ref<const VecX>& w,
                                const Eigen::Ref<const VecX>& lambda,
                                const Eigen::Ref<const VecX>& b,
                                const Eigen::Ref<const VecX>& cmin,
                                const Eigen::Ref<const VecX>& cmax,
                                const Eigen::Ref<const VecX>& diagonal,
                                double largest_diagonal) {
  double residual = 0.0;
  double scale = 0.0;
  for (Eigen::Index k = 0; k < w.size(); ++k) {
    const double rho = unit_free_step(diagonal(k), largest_diagonal);
    max_keep_nan(residual, natural_map_row(lambda(k), rho * w(k), cmin(k), cmax(k)));
    scale = std::max({scale, std::abs(lambda(k)), rho * std::abs(b(k))});
  }
  UnitFreeResidual u;
  u.residual = residual;
  u.scale = scale;
  u.relative = unit_free_of(residual, scale).relative;
  return u;
}

double UnitFreeTarget::newtons(double relative, const VecX& lambda) const {
  const double l = lambda.size() > 0 ? lambda.lpNorm<Eigen::Infinity>() : 0.0;
  return relative * std::max(l, rho_b) / std::max(1.0, rho_max);
}

UnitFreeTarget unit_free_target(const BoxedProblem& problem, double cfm) {
  UnitFreeTarget t;
  if (problem.rows() == 0) return t;
  const VecX rho = unit_free_steps(problem, cfm);
  t.rho_b = (rho.array() * problem.b.array().abs()).maxCoeff();
  t.rho_max = rho.maxCoeff();
  return t;
}

UnitFreeTarget unit_free_target_rows(const Eigen::Ref<const VecX>& b,
                                     const Eigen::Ref<const VecX>& diagonal,
                                     double largest_diagonal) {
  UnitFreeTarget t;
  t.rho_max = 0.0;
  for (Eigen::Index k = 0; k < b.size(); ++k) {
    const double rho = unit_free_step(diagonal(k), largest_diagonal);
    t.rho_b = std::max(t.rho_b, rho * std::abs(b(k)));
    t.rho_max = std::max(t.rho_max, rho);
  }
  return t;
}

bool is_solved(const UnitFreeResidual& u, const VecX& lambda) {
  return lambda.allFinite() && u.relative <= kSolvedTolerance;
}

}  // namespace cbps
