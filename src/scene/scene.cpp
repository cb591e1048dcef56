// Unit rescaling of a scene (paper 9, dimensional analysis).
#include "cbps/scene/scene.hpp"

#include "cbps/base/names.hpp"

namespace cbps {

Scene rescale_units(const Scene& scene, double L, double M, double T) {
  Scene s = scene;
  s.world.gravity *= L / (T * T);  // m/s²
  s.world.dt *= T;                 // s
  s.duration *= T;
  s.world.restitution_threshold *= L / T;    // m/s
  s.world.contact_margin *= L;               // m
  s.world.divergence_speed *= L / T;         // m/s
  s.world.divergence_spin /= T;              // rad/s
  s.world.scheme.contact_hertz /= T;         // Hz
  s.world.scheme.joint_hertz /= T;           // Hz
  s.world.scheme.max_push_speed *= L / T;    // m/s
  s.world.scheme.compliance *= T * T / M;    // m/N = s²/kg per unit of lambda
  s.world.scheme.speculative_distance *= L;  // m
  for (Body& body : s.bodies) {
    body.shape.radius *= L;
    body.shape.half_extents *= L;
    body.x *= L;
    body.m *= M;
    body.I_body *= M * L * L;  // kg m²
    body.I_body_inv /= M * L * L;
    body.p *= M * L / T;              // N s = kg m/s
    body.l *= M * L * L / T;          // N m s = kg m²/s
    body.f *= M * L / (T * T);        // N
    body.tau *= M * L * L / (T * T);  // N m
  }
  for (DistanceConstraint& dc : s.distances) {
    dc.anchor_a *= L;
    dc.anchor_b *= L;
    dc.length *= L;
  }
  s.solver.tolerance *= M * L / (T * T);  // residual in N
  s.solver.delta_tolerance *= M * L / (T * T);
  s.solver.cfm /= M;  // kg⁻¹, as A
  return s;
}

const std::vector<std::string>& scheme_names() {
  static const std::vector<std::string> names{"paper", "tgs", "soft-step", "xpbd"};  // Scheme
  return names;
}

std::optional<Scheme> scheme_named(const std::string& name) {
  return enumerator_named<Scheme>(scheme_names(), name);
}

RowSettings World::rows() const {
  RowSettings s;
  s.beta = beta;
  s.dt = dt;
  s.mu = mu;
  s.friction = friction;
  s.gravity = gravity;
  s.restitution = restitution;
  s.restitution_threshold = restitution_threshold;
  return s;
}

SolverOptions SolverSettings::options() const {
  SolverOptions o;
  static_cast<SolveSettings&>(o) = *this;
  return o;
}

bool Scene::has_contact_pairs() const {
  int colliding = 0, movable = 0;
  for (const Body& body : bodies) {
    if (!body.collides) continue;
    ++colliding;
    if (!body.is_static) ++movable;
  }
  return movable >= 1 && colliding >= 2;
}

}  // namespace cbps
