// Built-in scene `chain`: n links hanging from a fixed point at the origin, joined centre to
// centre by distance constraints (5.2), released horizontally along +x. The last link's mass is
// mass_ratio × link_mass, the case that makes A = J M⁻¹ Jᵀ ill-conditioned for large ratios.
#include "scene_parameters.hpp"

namespace cbps {

Scene build_chain(const std::map<std::string, std::string>& values) {
  const ParameterValues p(*find_builtin_scene("chain"), values);
  const long n = p.integer("n", 1, 10000000);
  const double link_length = p.positive("link_length");
  const double link_mass = p.positive("link_mass");
  const double mass_ratio = p.positive("mass_ratio");
  const double radius = p.positive("radius");

  Scene scene;
  scene.name = "chain";
  scene.world.dt = p.positive("dt");
  scene.world.beta = p.number("beta", 0.0, 1.0);
  scene.duration = p.positive("duration");
  scene.bodies.reserve(static_cast<std::size_t>(n));
  scene.distances.reserve(static_cast<std::size_t>(n));

  for (long k = 0; k < n; ++k) {
    Body link;
    link.name = "link" + std::to_string(k);
    link.shape.kind = Shape::Kind::Sphere;
    link.shape.radius = radius;
    link.collides = false;  // a distance-only scene: no collision stage
    set_mass(link, k == n - 1 ? mass_ratio * link_mass : link_mass);
    link.x = Vec3(static_cast<double>(k + 1) * link_length, 0.0, 0.0);
    scene.bodies.push_back(link);

    DistanceConstraint joint;
    joint.name = "joint" + std::to_string(k);
    joint.a = static_cast<int>(k) - 1;  // -1: the first link hangs from the world origin
    joint.b = static_cast<int>(k);
    joint.length = link_length;
    scene.distances.push_back(joint);
  }
  scene.parameters = p.in_force();
  return scene;
}

}  // namespace cbps
