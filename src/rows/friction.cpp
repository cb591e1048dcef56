// Friction rows (paper 5.4): the tangent basis, the rows, and the paper's bound.
#include "cbps/rows/friction.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "cbps/rows/contact.hpp"

namespace cbps {

void tangent_basis(const Vec3& n, Vec3& t1, Vec3& t2) {
  // The components of a unit n cannot all reach 0.6 in magnitude (3 · 0.36 > 1).
  Eigen::Index axis = 0;
  while (axis < 2 && std::abs(n(axis)) >= 0.6) ++axis;
  t1 = n.cross(Vec3::Unit(axis)).normalized();
  t2 = n.cross(t1);
}

// Friction rows, paper 5.4. Two tangents t1, t2 ⟂ n at the contact point p.
//   Ċ_k   = t_k · (v_b + ω_b × r_b − v_a − ω_a × r_a)   the sliding speed along t_k
//   j_c   = [ −t_kᵀ, −(r_a × t_k)ᵀ, t_kᵀ, (r_b × t_k)ᵀ ]   the contact row's form with t_k for n
//   υ     = 0                                       friction only stops sliding
//   −μ m |g·n| ≤ λ ≤ μ m |g·n|                      the paper's bound (paper_friction_bound);
//   −μ λ_n ≤ λ ≤ μ λ_n                              or Coulomb's, set by the solve (coulomb.hpp)
Row friction_row(const Manifold& manifold,
                 const ContactPoint& point,
                 int k,
                 const Vec3& t,
                 double bound,
                 const std::vector<Body>& bodies) {
  Row row = direction_row(
      RowKind::Friction, bodies, manifold.a, point.p, manifold.b, point.p, t);  // (5.4)
  row.cmin = -bound;
  row.cmax = bound;
  row.label = "friction " + point_label(manifold, point, bodies) + (k == 1 ? " t1" : " t2");
  row.id = contact_row_id(manifold.a, manifold.b, point.id, k);
  return row;
}

double paper_friction_bound(const Manifold& manifold,
                            const std::vector<Body>& bodies,
                            double mu,
                            const Vec3& g) {
  double mass = 0.0;
  for (const int index : {manifold.a, manifold.b}) {
    const Body& body = bodies[static_cast<std::size_t>(index)];
    if (!body.is_static) mass += body.m;
  }
  const double per_point =
      mass / static_cast<double>(std::max<std::size_t>(1, manifold.points.size()));
  return mu * per_point * std::abs(g.dot(manifold.n));  // mu m |g·n| (5.4)
}

}  // namespace cbps
