// Built-in scene `chain`: n links hanging from a fixed point at the origin, joined centre to
// centre by distance constraints (5.2), released horizontally along +x. The last link's mass is
// mass_ratio × link_mass, the case that makes A = J M⁻¹ Jᵀ ill-conditioned for large ratios.
//
// build_chain_range builds any contiguous part of it (the distributed generator,
// include/cbps/distributed/generate.hpp); build_chain is the part [0, n), so both paths share
// every link and joint.
#include <algorithm>

#include "cbps/base/error.hpp"
#include "scene_parameters.hpp"

namespace cbps {

Scene build_chain_range(const std::map<std::string, std::string>& values, long first, long last) {
  const ParameterValues p(*find_builtin_scene("chain"), values);
  const long n = p.integer("n", 1, 10000000);
  const double link_length = p.positive("link_length");
  const double link_mass = p.positive("link_mass");
  const double mass_ratio = p.positive("mass_ratio");
  const double radius = p.positive("radius");
  if (first < 0 || last > n || first >= last)
    throw InputError("chain: links [" + std::to_string(first) + ", " + std::to_string(last) +
                     ") are not a part of the " + std::to_string(n) + " links");

  Scene scene;
  scene.name = "chain";
  scene.world.dt = p.positive("dt");
  scene.world.beta = p.number("beta", 0.0, 1.0);
  scene.duration = p.positive("duration");
  // Bodies [lowest, last): the links of the joints [first, last) and the link before the first
  // joint (joint k joins link k − 1 to link k; joint 0 hangs link 0 from the world).
  const long lowest = std::max(first - 1, 0L);
  scene.bodies.reserve(static_cast<std::size_t>(last - lowest));
  scene.distances.reserve(static_cast<std::size_t>(last - first));

  for (long k = lowest; k < last; ++k) {
    Body link;
    link.name = "link" + std::to_string(k);
    link.shape.kind = Shape::Kind::Sphere;
    link.shape.radius = radius;
    link.collides = false;  // a distance-only scene: no collision stage
    set_mass(link, k == n - 1 ? mass_ratio * link_mass : link_mass);
    link.x = Vec3(static_cast<double>(k + 1) * link_length, 0.0, 0.0);
    scene.bodies.push_back(link);
  }
  for (long k = first; k < last; ++k) {
    DistanceConstraint joint;
    joint.name = "joint" + std::to_string(k);
    joint.a = static_cast<int>(k - 1 - lowest);  // -1: the first link hangs from the world origin
    joint.b = static_cast<int>(k - lowest);
    joint.length = link_length;
    scene.distances.push_back(joint);
  }
  scene.parameters = p.in_force();
  return scene;
}

Scene build_chain(const std::map<std::string, std::string>& values) {
  const ParameterValues p(*find_builtin_scene("chain"), values);
  return build_chain_range(values, 0, p.integer("n", 1, 10000000));
}

}  // namespace cbps
