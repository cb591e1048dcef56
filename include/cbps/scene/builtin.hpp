// Built-in parametric scenes. Each is written in the same terms as a JSON scene: it fills a
// Scene struct; nothing in the solver knows which scene it runs.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "cbps/scene/scene.hpp"

namespace cbps {

struct SceneParameter {
  std::string name;
  std::string default_value;
  std::string unit;  ///< "" for dimensionless, "-" for a word
  std::string description;
};

struct BuiltinScene {
  std::string name;
  std::string description;
  std::vector<SceneParameter> parameters;
  Scene (*build)(const std::map<std::string, std::string>& values);
};

/// All built-in scenes, in the order `cbps scenes` lists them.
const std::vector<BuiltinScene>& builtin_scenes();

/// Looks a built-in scene up by name; nullptr if there is none.
const BuiltinScene* find_builtin_scene(const std::string& name);

/// Builds a built-in scene with NAME=VALUE overrides. Throws InputError naming the scene and
/// parameter for an unknown parameter (listing the valid ones) or a value that is not valid.
Scene make_builtin_scene(const std::string& name, const std::map<std::string, std::string>& values);

/// The part of the built-in scene `chain` (NAME=VALUE overrides as make_builtin_scene takes
/// them, n the whole chain's links) that holds the joints [first, last) of its n: the links
/// max(first − 1, 0) … last − 1 (body i of the part is link max(first − 1, 0) + i) and those
/// joints, built by the same code as the whole scene (which is the part [0, n)). Throws
/// InputError for a range that is not inside [0, n) or is empty.
Scene build_chain_range(const std::map<std::string, std::string>& values, long first, long last);

/// The boxes in the bottom row of the built-in scene `pyramid` with NAME=VALUE overrides (its
/// parameter `base`); the pyramid has base (base + 1) / 2 boxes. Throws InputError as
/// make_builtin_scene does for a bad base.
long pyramid_base(const std::map<std::string, std::string>& values);

/// The part of the built-in scene `pyramid` (NAME=VALUE overrides as make_builtin_scene takes
/// them) that holds its boxes [first, last), numbered as the whole scene numbers them (row by
/// row from the bottom, left to right in a row): body 0 is the ground, body 1 + i box first + i.
/// Built by the same code as the whole scene (which is the part [0, base (base + 1) / 2)).
/// Throws InputError for a range that is not inside the pyramid's boxes.
Scene build_pyramid_range(const std::map<std::string, std::string>& values, long first, long last);

/// Body builders shared by the built-in scenes and the stress catalogue (src/studies/stress.cpp).
/// A static ground plane through `point` with outward normal `normal` (unit).
Body ground_body(const std::string& name, const Vec3& point, const Vec3& normal);
/// A movable solid box of uniform density: half extents in m, mass in kg, centre x in m.
Body box_body(const std::string& name, const Vec3& half_extents, double mass, const Vec3& x);
/// A movable solid sphere of uniform density: radius in m, mass in kg, centre x in m.
Body sphere_body(const std::string& name, double radius, double mass, const Vec3& x);

/// Complete elliptic integral of the first kind K(k) = ∫₀^{π/2} dθ / sqrt(1 − k² sin²θ), by the
/// arithmetic-geometric mean: K(k) = π / (2 AGM(1, sqrt(1 − k²))). 0 ≤ k < 1.
double elliptic_K(double k);

/// Exact period of a simple pendulum of length L (m) released from rest at theta0 (rad):
/// T = 4 sqrt(L/g) K(sin(theta0/2)), s.
double pendulum_period(double L, double g, double theta0);

}  // namespace cbps
