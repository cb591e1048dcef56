// The row stage of a step (paper 5.2–5.4).
#include "cbps/rows/build_rows.hpp"

#include "cbps/rows/contact.hpp"

namespace cbps {

void build_rows(const std::vector<Body>& bodies,
                const std::vector<DistanceConstraint>& distances,
                const std::vector<Manifold>& manifolds,
                const RowSettings& settings,
                std::vector<Row>& rows) {
  const RowSettings& s = settings;
  rows.resize(distances.size());
  for (std::size_t k = 0; k < distances.size(); ++k)
    rows[k] = distance_row(distances[k], bodies, s.beta, s.dt, k);  // (5.2)
  for (std::size_t index = 0; index < manifolds.size(); ++index) {
    const Manifold& manifold = manifolds[index];
    Vec3 t1, t2;
    tangent_basis(manifold.n, t1, t2);
    const double bound = paper_friction_bound(manifold, bodies, s.mu, s.gravity);
    for (const ContactPoint& point : manifold.points) {
      Row contact = contact_row(manifold, point, bodies);  // (5.3)
      const double approach = row_velocity(contact, bodies);
      contact.upsilon =
          contact_bias(point.depth, approach, s.dt, s.restitution, s.restitution_threshold);
      contact.upsilon_push = contact_push(point.depth, s.beta, s.dt);
      contact.depth = point.depth;
      contact.manifold = static_cast<int>(index);
      const int normal = static_cast<int>(rows.size());
      rows.push_back(std::move(contact));
      if (s.mu <= 0.0) continue;  // no friction rows at mu = 0
      rows.back().mu = s.mu;
      rows.back().law = s.friction;
      int k = 1;
      for (const Vec3& t : {t1, t2}) {
        Row friction = friction_row(manifold, point, k++, t, bound, bodies);  // (5.4)
        friction.manifold = static_cast<int>(index);
        friction.normal_row = normal;
        if (s.friction == FrictionLaw::CoulombBox) {
          friction.cmin = 0.0;  // the bounds ±mu lambda_normal are set by the solve
          friction.cmax = 0.0;
        }
        if (is_cone(s.friction)) {  // the cone bounds them, not a box
          friction.cmin = -kInf;
          friction.cmax = kInf;
        }
        rows.push_back(std::move(friction));
      }
    }
  }
}

}  // namespace cbps
