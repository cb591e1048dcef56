// The unit-free residual (system/unit_free.hpp).
#include "cbps/system/unit_free.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "cbps/base/numbers.hpp"
#include "cbps/system/cone_problem.hpp"

namespace cbps {

UnitFreeResidual unit_free_residual(const BoxedProblem& problem, const VecX& lambda, double cfm) {
  UnitFreeResidual u;
  const Eigen::Index c = problem.rows();
  if (c == 0 || lambda.size() != c) return u;
  const VecX w = times_A(problem, lambda) + cfm * lambda - problem.b;  // (A + eps E) λ − b (6.2)
  const VecX diagonal = diagonal_of_A(problem).array() + cfm;
  const double largest = diagonal.maxCoeff();
  const double fallback = largest > 0.0 ? 1.0 / largest : 1.0;
  VecX rho(c);
  for (Eigen::Index k = 0; k < c; ++k) rho(k) = diagonal(k) > 0.0 ? 1.0 / diagonal(k) : fallback;
  std::vector<char> in_cone(std::size_t(c), 0);
  if (problem.cones != nullptr) {
    const ConeContacts& cones = *problem.cones;
    for (long i = 0; i < cones.contacts(); ++i) {
      const int n = cones.normal[std::size_t(i)];
      const double top = diagonal.segment<3>(n).maxCoeff();
      const double rho_a = top > 0.0 ? 1.0 / top : fallback;
      rho.segment<3>(n).setConstant(rho_a);
      const Vec3 r = lambda.segment<3>(n);
      // ρ F(r; u) for the map of u scaled by ρ: the law's û is positively homogeneous in u.
      max_keep_nan(u.residual,
                   cone_natural_map(r, rho_a * w.segment<3>(n), cones.mu(i), cones.law).norm());
      in_cone[std::size_t(n)] = in_cone[std::size_t(n + 1)] = in_cone[std::size_t(n + 2)] = 1;
    }
  }
  for (Eigen::Index k = 0; k < c; ++k) {
    if (in_cone[std::size_t(k)]) continue;
    max_keep_nan(u.residual,
                 natural_map_row(lambda(k), rho(k) * w(k), problem.cmin(k), problem.cmax(k)));
  }
  u.scale = std::max(lambda.lpNorm<Eigen::Infinity>(),
                     (rho.array() * problem.b.array().abs()).maxCoeff());
  if (std::isnan(u.residual))
    u.relative = std::numeric_limits<double>::quiet_NaN();
  else if (u.residual == 0.0)
    u.relative = 0.0;
  else
    u.relative = u.scale > 0.0 ? u.residual / u.scale : kInf;
  return u;
}

}  // namespace cbps
