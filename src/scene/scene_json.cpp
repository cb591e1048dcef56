// JSON scene files (docs/scene-format.md). The reader checks every value and names the first bad
// one as "<source>: <JSON pointer>: <why>"; the writer's output reads back to the same Scene bit
// for bit. The only file of the project that includes nlohmann/json.
#include "cbps/scene/scene_json.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cbps/base/error.hpp"
#include "cbps/base/numbers.hpp"
#include "cbps/scene/settings.hpp"
#include "cbps/solvers/methods.hpp"

namespace cbps {
namespace {

// ordered_json keeps an object's keys in the order they were written, so `parameters` keep
// their order and the files we write read top to bottom in a sensible order.
using Json = nlohmann::ordered_json;

constexpr double kUnitQuaternionTolerance = 1e-6;  // allowed | |q| − 1 | in a file
// A quaternion already unit to rounding is kept as written, so written scenes read back exactly.
constexpr double kUnitRounding = 4.0 * std::numeric_limits<double>::epsilon();
constexpr double kSymmetryTolerance = 1e-12;  // allowed |I_ij − I_ji| / max |I_kl|
const std::vector<std::string> kShapeTypes{"sphere", "box", "plane"};
const std::vector<std::string> kConstraintTypes{"distance"};

std::string join(const std::vector<std::string>& words) {
  std::string out;
  for (const std::string& word : words) out += (out.empty() ? "" : ", ") + word;
  return out;
}

std::string in_quotes(const std::string& text) { return Json(text).dump(); }

bool contains(const std::vector<std::string>& words, const std::string& word) {
  for (const std::string& w : words)
    if (w == word) return true;
  return false;
}

// ---- Where a value sits --------------------------------------------------------------------

/// One JSON pointer reference token (RFC 6901): "~" → "~0", "/" → "~1".
std::string pointer_token(const std::string& key) {
  std::string out;
  for (char c : key) {
    if (c == '~')
      out += "~0";
    else if (c == '/')
      out += "~1";
    else
      out += c;
  }
  return out;
}

/// A JSON value with the source it came from and its JSON pointer, so that every check can
/// report where it failed.
struct Node {
  const Json& json;
  const std::string& source;
  std::string path;  ///< JSON pointer; "" is the document itself
};

[[noreturn]] void fail(const std::string& source, const std::string& path, const std::string& why) {
  throw InputError(source + ": " + (path.empty() ? "/" : path) + ": " + why);
}

[[noreturn]] void fail(const Node& node, const std::string& why) {
  fail(node.source, node.path, why);
}

/// " (got <value as written>)" for messages about a value out of range.
std::string got(const Node& node) { return " (got " + node.json.dump() + ")"; }

bool has(const Node& node, const char* key) { return node.json.contains(key); }

Node child(const Node& node, const std::string& key) {
  return Node{node.json.at(key), node.source, node.path + "/" + pointer_token(key)};
}

Node element(const Node& node, std::size_t i) {
  return Node{node.json.at(i), node.source, node.path + "/" + std::to_string(i)};
}

/// The child `key`, which must be there.
Node required(const Node& node, const char* key) {
  if (!has(node, key)) fail(node.source, node.path + "/" + key, "missing (required)");
  return child(node, key);
}

/// Checks that node is an object whose keys are all in `valid`, so typos are caught.
void check_object(const Node& node, const std::vector<std::string>& valid) {
  if (!node.json.is_object())
    fail(node, "expected an object (got " + std::string(node.json.type_name()) + ")");
  for (const auto& item : node.json.items())
    if (!contains(valid, item.key()))
      fail(child(node, item.key()), "unknown key (valid: " + join(valid) + ")");
}

void check_array(const Node& node) {
  if (!node.json.is_array())
    fail(node, "expected an array (got " + std::string(node.json.type_name()) + ")");
}

// ---- Values --------------------------------------------------------------------------------

double number(const Node& node) {
  if (!node.json.is_number())
    fail(node, "expected a number (got " + std::string(node.json.type_name()) + ")");
  const double value = node.json.get<double>();
  if (!std::isfinite(value)) fail(node, "not a finite number");
  return value;
}

double positive(const Node& node) {
  const double value = number(node);
  if (!(value > 0.0)) fail(node, "must be > 0" + got(node));
  return value;
}

/// A whole number (its range is the setting's, checked where it is set).
double whole(const Node& node) {
  const Json& j = node.json;
  if (!j.is_number()) fail(node, "expected an integer (got " + std::string(j.type_name()) + ")");
  const double value = j.get<double>();
  if (!j.is_number_integer() && std::trunc(value) != value)
    fail(node, "expected an integer" + got(node));
  return value;
}

bool boolean(const Node& node) {
  if (!node.json.is_boolean())
    fail(node, "expected true or false (got " + std::string(node.json.type_name()) + ")");
  return node.json.get<bool>();
}

std::string text(const Node& node) {
  if (!node.json.is_string())
    fail(node, "expected a string (got " + std::string(node.json.type_name()) + ")");
  return node.json.get<std::string>();
}

/// An array of exactly n elements.
void check_size(const Node& node, std::size_t n, const char* what) {
  if (!node.json.is_array() || node.json.size() != n) {
    const std::string seen = node.json.is_array() ? "array of " + std::to_string(node.json.size())
                                                  : std::string(node.json.type_name());
    fail(node, std::string("expected ") + what + " (got " + seen + ")");
  }
}

Vec3 vec3(const Node& node) {
  check_size(node, 3, "an array of 3 numbers");
  return Vec3(number(element(node, 0)), number(element(node, 1)), number(element(node, 2)));
}

Vec3 positive_vec3(const Node& node) {
  check_size(node, 3, "an array of 3 numbers");
  return Vec3(positive(element(node, 0)), positive(element(node, 1)), positive(element(node, 2)));
}

// ---- Scene parts ---------------------------------------------------------------------------

/// One setting's value as the file gives it (settings.hpp): a number (or, where the entry says
/// so, a fraction "p/q" as a string), an integer, one of its words, or true or false. Its
/// range is checked where it is set (set_setting).
template <typename T>
double setting_of_node(const Node& node, const Setting<T>& s) {
  if (s.type == SettingType::Word) {
    std::string why;
    const std::optional<double> index = setting_value(s, text(node), why);
    if (!index) fail(node, why);
    return *index;
  }
  if (s.type == SettingType::Flag) return boolean(node) ? 1.0 : 0.0;
  if (s.type == SettingType::Whole) return whole(node);
  if (s.fraction && node.json.is_string()) {
    double value = 0.0;
    if (!parse_number(node.json.get<std::string>(), value))
      fail(node, "expected a number or a fraction such as \"1/240\"" + got(node));
    return value;
  }
  return number(node);
}

/// Every setting of `settings` that `node` gives, in the table's order, each checked as the
/// command line checks it.
template <typename T>
void read_settings(const Node& node, std::span<const Setting<T>> settings, T& target) {
  for (const Setting<T>& s : settings) {
    const std::string key(s.key);
    if (!has(node, key.c_str())) continue;
    const Node value = child(node, key);
    const std::string why = set_setting(target, s, setting_of_node(value, s));
    if (!why.empty())
      fail(value,
           why + (s.type == SettingType::Word || s.type == SettingType::Flag ? "" : got(value)));
  }
}

/// The settings of `settings` that apply to `target` (and are given, where that matters), as
/// JSON values under their keys.
template <typename T>
void write_settings(Json& out, std::span<const Setting<T>> settings, const T& target) {
  for (const Setting<T>& s : settings) {
    if (s.applies != nullptr && !s.applies(target)) continue;  // means nothing here
    if (s.given != nullptr && !s.given(target)) continue;      // follows another until given
    const std::string key(s.key);
    const double value = s.get(target);
    if (s.type == SettingType::Word)
      out[key] = setting_text(s, target);
    else if (s.type == SettingType::Flag)
      out[key] = value != 0.0;
    else if (s.type == SettingType::Whole)
      out[key] = static_cast<long long>(value);
    else
      out[key] = value;
  }
}

/// /world: gravity, then every world setting the file gives, in the table's order (settings.hpp:
/// a scheme before its own settings), each checked as the command line checks it.
World read_world(const Node& node) {
  std::vector<std::string> valid{"gravity"};
  for (const WorldSetting& s : world_settings()) valid.emplace_back(s.key);
  check_object(node, valid);
  World world = scene_file_world();
  if (has(node, "gravity")) world.gravity = vec3(child(node, "gravity"));
  read_settings(node, world_settings(), world);
  return world;
}

/// /solver/parameters: the method's own parameters, each key one of the table's (methods.hpp)
/// for /solver/method, its value a number, "on"/"off" (or true/false) or a word the key takes,
/// checked as `--solver NAME:key=value` checks it.
void read_method_parameters(const Node& node, SolverSettings& solver) {
  if (!node.json.is_object())
    fail(node,
         "expected an object of the method's parameters (got " +
             std::string(node.json.type_name()) + ")");
  const std::string method(to_string(solver.method));
  std::string valid;
  for (const auto& [key, value] : method_parameters(solver.method, solver.methods))
    valid += (valid.empty() ? "" : ", ") + key;
  for (const auto& item : node.json.items()) {
    const Node value = child(node, item.key());
    const MethodKey* key = find_method_key(solver.method, item.key());
    if (key == nullptr)
      fail(value,
           valid.empty()
               ? "method " + in_quotes(method) + " has no parameters of its own"
               : "unknown parameter for method " + in_quotes(method) + " (valid: " + valid + ")");
    std::string written;
    if (value.json.is_boolean()) {
      written = value.json.get<bool>() ? "on" : "off";
    } else if (value.json.is_number()) {
      char digits[32];
      std::snprintf(digits, sizeof digits, "%.17g", value.json.get<double>());
      written = digits;
    } else if (value.json.is_string()) {
      written = value.json.get<std::string>();
    }
    if (written.empty() || !key->set(written, solver.methods))
      fail(value, "must be " + std::string(key->accepts) + got(value));
  }
}

/// /solver: every solver setting the file gives (settings.hpp), the older warm_start (true is
/// warm 1, false warm 0) and the method's own parameters.
SolverSettings read_solver(const Node& node) {
  std::vector<std::string> valid{"warm_start", "parameters"};
  for (const SolverSetting& s : solver_settings()) valid.emplace_back(s.key);
  check_object(node, valid);
  SolverSettings solver;
  if (has(node, "warm_start")) {
    const Node warm_start = child(node, "warm_start");
    if (has(node, "warm"))
      fail(warm_start,
           "give /solver/warm or /solver/warm_start, not both (warm_start true is "
           "warm 1, false is warm 0)");
    solver.warm = boolean(warm_start) ? 1.0 : 0.0;
  }
  read_settings(node, solver_settings(), solver);
  if (has(node, "parameters")) read_method_parameters(child(node, "parameters"), solver);
  return solver;
}

Shape read_shape(const Node& node) {
  if (!node.json.is_object())
    fail(node, "expected an object (got " + std::string(node.json.type_name()) + ")");
  const Node type = required(node, "type");
  const std::string kind = text(type);
  Shape shape;
  if (kind == "sphere") {
    check_object(node, {"type", "radius"});
    shape.kind = Shape::Kind::Sphere;
    shape.radius = positive(required(node, "radius"));
  } else if (kind == "box") {
    check_object(node, {"type", "half_extents"});
    shape.kind = Shape::Kind::Box;
    shape.half_extents = positive_vec3(required(node, "half_extents"));
  } else if (kind == "plane") {  // a half-space: no size (body.hpp)
    check_object(node, {"type"});
    shape.kind = Shape::Kind::Plane;
  } else {
    fail(type, "unknown shape type " + in_quotes(kind) + " (valid: " + join(kShapeTypes) + ")");
  }
  return shape;
}

/// A body-frame inertia tensor, [Ixx, Iyy, Izz] or a 3×3 array: symmetric (to
/// kSymmetryTolerance, then symmetrised) and positive definite, kg m².
Mat3 read_inertia(const Node& node) {
  const char* expected = "[Ixx, Iyy, Izz] or a 3x3 array of numbers";
  check_size(node, 3, expected);
  Mat3 I = Mat3::Zero();
  if (node.json.at(0).is_array()) {
    for (std::size_t i = 0; i < 3; ++i) {
      const Node row = element(node, i);
      check_size(row, 3, "a row of 3 numbers");
      for (std::size_t j = 0; j < 3; ++j) I(i, j) = number(element(row, j));
    }
  } else {
    I.diagonal() = vec3(node);
  }
  const double scale = I.cwiseAbs().maxCoeff();
  for (int i = 0; i < 3; ++i)
    for (int j = i + 1; j < 3; ++j)
      if (std::abs(I(i, j) - I(j, i)) > kSymmetryTolerance * scale) {
        std::ostringstream why;
        why.precision(17);
        why << "not symmetric (I[" << i << "][" << j << "] = " << I(i, j) << ", I[" << j << "]["
            << i << "] = " << I(j, i) << ")";
        fail(node, why.str());
      }
  I = (0.5 * (I + I.transpose())).eval();
  const Vec3 eigenvalues =
      Eigen::SelfAdjointEigenSolver<Mat3>(I, Eigen::EigenvaluesOnly).eigenvalues();
  if (!(eigenvalues.minCoeff() > 0.0)) {
    std::ostringstream why;
    why << "not positive definite (eigenvalues " << eigenvalues(0) << ", " << eigenvalues(1) << ", "
        << eigenvalues(2) << ")";
    fail(node, why.str());
  }
  // A rigid body's principal moments obey the triangle inequality I_a + I_b ≥ I_c (each is
  // ∫ of a sum of two squared coordinates); no mass distribution has e.g. [1, 1, 5].
  const double slack = 1e-9 * eigenvalues.maxCoeff();
  if (eigenvalues(0) + eigenvalues(1) < eigenvalues(2) - slack) {
    std::ostringstream why;
    why << "no rigid body has these principal moments (" << eigenvalues(0) << ", " << eigenvalues(1)
        << ", " << eigenvalues(2) << " kg m^2): the two smaller must add up to "
        << "at least the largest";
    fail(node, why.str());
  }
  return I;
}

/// Sets `inverse` to I⁻¹ and returns true if I, det I (> 0) and I⁻¹ are all finite: a tiny or
/// huge I can have a determinant that underflows to 0 or overflows to ∞.
bool finite_inverse(const Mat3& I, Mat3& inverse) {
  if (!I.allFinite()) return false;
  const double det = I.determinant();
  if (!(det > 0.0 && std::isfinite(det))) return false;
  inverse = I.inverse();
  return inverse.allFinite();
}

/// [w, x, y, z], unit to within kUnitQuaternionTolerance, normalised.
Quat read_orientation(const Node& node) {
  check_size(node, 4, "a quaternion [w, x, y, z]");
  Eigen::Vector4d wxyz;
  for (std::size_t k = 0; k < 4; ++k) wxyz(k) = number(element(node, k));
  const double norm = wxyz.norm();
  if (!(std::abs(norm - 1.0) <= kUnitQuaternionTolerance)) {
    std::ostringstream why;
    why << "must be a unit quaternion [w, x, y, z] (norm " << norm << ")";
    fail(node, why.str());
  }
  if (std::abs(norm - 1.0) > kUnitRounding) wxyz /= norm;
  return Quat(wxyz(0), wxyz(1), wxyz(2), wxyz(3));
}

/// Reads one of two alternative keys (say "velocity" or "momentum"); returns which was given:
/// 0 none, 1 the first, 2 the second, and the vector in `value`.
int one_of(const Node& node, const char* first, const char* second, Vec3& value) {
  if (has(node, first) && has(node, second))
    fail(node, std::string("give \"") + first + "\" or \"" + second + "\", not both");
  if (has(node, first)) value = vec3(child(node, first));
  if (has(node, second)) value = vec3(child(node, second));
  return has(node, first) ? 1 : has(node, second) ? 2 : 0;
}

/// What a spin beyond the divergence guard's limit is told: "gives a spin of ... beyond ...".
std::string beyond_spin(double spin, const World& world) {
  return "gives a spin of " + number_text(spin) + " rad/s, beyond /world/divergence_spin (" +
         number_text(world.divergence_spin) + " rad/s, where the divergence guard stops a run)";
}

/// The velocities a body is given (kind 1) or the momenta (kind 2; 0: neither), finite but
/// beyond the divergence guard's limits (Simulation::step): refused by name, before any product
/// of them overflows (a 1e200 m/s velocity).
void check_given_motion(const Node& node,
                        const Body& body,
                        const World& world,
                        int linear_kind,
                        const Vec3& linear,
                        int angular_kind,
                        const Vec3& angular) {
  const double speed = linear_kind == 1   ? linear.stableNorm()
                       : linear_kind == 2 ? (linear / body.m).stableNorm()
                                          : 0.0;
  if (speed > world.divergence_speed)
    fail(child(node, linear_kind == 1 ? "velocity" : "momentum"),
         "gives a speed of " + number_text(speed) + " m/s, beyond /world/divergence_speed (" +
             number_text(world.divergence_speed) + " m/s, where the divergence guard stops a run)");
  if (angular_kind == 1 && angular.stableNorm() > world.divergence_spin)
    fail(child(node, "angular_velocity"), beyond_spin(angular.stableNorm(), world));
}

/// A movable body's spin from a given angular momentum, within the divergence guard's limit, and
/// its energy, finite.
void check_motion_range(const Node& node, const Body& body, const World& world) {
  if (body.omega().stableNorm() > world.divergence_spin)
    fail(child(node, "angular_momentum"), beyond_spin(body.omega().stableNorm(), world));
  // The energy the run reports, ½ m v² + ½ ωᵀ I ω − m g·x (J): a position or mass far out of
  // range overflows it.
  const double energy = body.kinetic_energy() - body.m * world.gravity.dot(body.x);
  if (!std::isfinite(energy))
    fail(has(node, "position") ? child(node, "position") : node,
         "overflows the body's energy (1/2 m v^2 + 1/2 w^T I w - m g.x is not finite in a "
         "double): a position, mass or speed out of range");
}

Body read_body(const Node& node, std::size_t i, const World& world) {
  check_object(node,
               {"name",
                "shape",
                "static",
                "collides",
                "mass",
                "density",
                "inertia",
                "position",
                "orientation",
                "velocity",
                "angular_velocity",
                "momentum",
                "angular_momentum"});
  Body body;
  body.name = "body" + std::to_string(i);
  if (has(node, "name")) {
    const Node name = child(node, "name");
    body.name = text(name);
    if (body.name.empty()) fail(name, "must not be empty");
    if (body.name == "world") fail(name, "\"world\" is reserved for the fixed world");
  }
  body.shape = read_shape(required(node, "shape"));
  if (has(node, "static")) body.is_static = boolean(child(node, "static"));
  if (has(node, "collides")) body.collides = boolean(child(node, "collides"));
  if (body.shape.kind == Shape::Kind::Plane) {
    // A half-space has no finite mass or inertia (body.hpp): it is static and keeps the
    // default m = 1, I = 1, which nothing uses.
    if (!body.is_static) fail(node.source, node.path + "/static", "a plane must be static");
    for (const char* key : {"mass", "density", "inertia"})
      if (has(node, key)) fail(child(node, key), "a plane has no mass or inertia");
  }

  // Mass, then inertia: set_mass gives the solid's inertia, which "inertia" overrides.
  if (has(node, "mass") && has(node, "density"))
    fail(node, "give \"mass\" or \"density\", not both");
  // m, m⁻¹, I and I⁻¹ must all be finite; a mass or size far from 1 can overflow them.
  const auto set_checked_mass = [&](const Node& given, double m) {
    if (!std::isfinite(1.0 / m)) fail(given, "too small: 1/mass is not finite" + got(given));
    if (has(node, "inertia")) {  // "inertia" replaces the solid's inertia below
      body.m = m;
      return;
    }
    Mat3 inverse;
    if (!finite_inverse(body.shape.inertia(m), inverse))
      fail(given, "gives an inertia tensor or inverse that is not finite" + got(given));
    set_mass(body, m);
  };
  if (has(node, "mass")) {
    const Node mass = child(node, "mass");
    set_checked_mass(mass, positive(mass));
  } else if (has(node, "density")) {
    const Node density = child(node, "density");
    const double m = positive(density) * body.shape.volume();
    if (!(m > 0.0) || !std::isfinite(m)) fail(density, "gives a mass that is not > 0 and finite");
    set_checked_mass(density, m);
  } else if (!body.is_static) {
    fail(node, "a movable body needs \"mass\" (kg) or \"density\" (kg/m^3)");
  }
  if (has(node, "inertia")) {
    const Node inertia = child(node, "inertia");
    body.I_body = read_inertia(inertia);
    if (!finite_inverse(body.I_body, body.I_body_inv))
      fail(inertia, "its inverse is not finite (determinant out of a double's range)");
  }

  if (has(node, "position")) body.x = vec3(child(node, "position"));
  if (has(node, "orientation")) body.q = read_orientation(child(node, "orientation"));

  // Velocities become momenta p = m v, l = I omega (3.2) once m, I and q are known. Momenta
  // may be given instead; scene_to_json writes them when v and omega would not round-trip.
  Vec3 linear = Vec3::Zero();
  Vec3 angular = Vec3::Zero();
  const int linear_kind = one_of(node, "velocity", "momentum", linear);
  const int angular_kind = one_of(node, "angular_velocity", "angular_momentum", angular);
  if (body.is_static) {
    if (linear_kind != 0 && !linear.isZero(0.0))
      fail(child(node, linear_kind == 1 ? "velocity" : "momentum"),
           "must be zero for a static body");
    if (angular_kind != 0 && !angular.isZero(0.0))
      fail(child(node, angular_kind == 1 ? "angular_velocity" : "angular_momentum"),
           "must be zero for a static body");
    return body;
  }
  check_given_motion(node, body, world, linear_kind, linear, angular_kind, angular);
  body.set_velocity(linear_kind == 1 ? linear : Vec3::Zero(),
                    angular_kind == 1 ? angular : Vec3::Zero());
  if (linear_kind == 2) body.p = linear;
  if (angular_kind == 2) body.l = angular;
  // p = m v and l = I omega can overflow; v = p/m and omega = I⁻¹ l likewise.
  if (linear_kind != 0 && !(body.p.allFinite() && body.v().allFinite()))
    fail(child(node, linear_kind == 1 ? "velocity" : "momentum"),
         "gives a momentum or velocity that is not finite");
  if (angular_kind != 0 && !(body.l.allFinite() && body.omega().allFinite()))
    fail(child(node, angular_kind == 1 ? "angular_velocity" : "angular_momentum"),
         "gives an angular momentum or velocity that is not finite");
  check_motion_range(node, body, world);
  return body;
}

/// A constraint end: a body name, a body index, or "world" (-1).
int read_end(const Node& node, const std::vector<Body>& bodies) {
  const Json& j = node.json;
  if (j.is_string()) {
    const std::string name = j.get<std::string>();
    if (name == "world") return -1;
    for (std::size_t i = 0; i < bodies.size(); ++i)
      if (bodies[i].name == name) return static_cast<int>(i);
    fail(node, "no body named " + in_quotes(name));
  }
  if (j.is_number_integer()) {
    const bool in_range = j.is_number_unsigned() && j.get<std::uint64_t>() < bodies.size();
    if (!in_range)
      fail(node,
           "body index out of range" + got(node) + "; there are " + std::to_string(bodies.size()) +
               " bodies");
    return static_cast<int>(j.get<std::uint64_t>());
  }
  fail(node,
       "expected a body name, a body index or \"world\" (got " + std::string(j.type_name()) + ")");
}

DistanceConstraint read_distance(const Node& node, std::size_t k, const std::vector<Body>& bodies) {
  check_object(node, {"type", "name", "a", "b", "anchor_a", "anchor_b", "length"});
  DistanceConstraint dc;
  dc.name = has(node, "name") ? text(child(node, "name")) : "distance" + std::to_string(k);
  dc.a = read_end(required(node, "a"), bodies);
  dc.b = read_end(required(node, "b"), bodies);
  if (dc.a >= 0 && dc.a == dc.b)
    fail(node, "both ends are on the same body " + in_quotes(bodies[dc.a].name));
  const auto fixed = [&](int i) { return i < 0 || bodies[i].is_static; };
  if (fixed(dc.a) && fixed(dc.b))
    fail(node, "both ends are fixed (the world or static bodies), so there is nothing to move");
  if (has(node, "anchor_a")) dc.anchor_a = vec3(child(node, "anchor_a"));
  if (has(node, "anchor_b")) dc.anchor_b = vec3(child(node, "anchor_b"));
  if (has(node, "length")) {
    dc.length = positive(child(node, "length"));
  } else {
    dc.length =
        (anchor_point(bodies, dc.b, dc.anchor_b) - anchor_point(bodies, dc.a, dc.anchor_a)).norm();
    if (!(dc.length > 0.0))
      fail(node,
           "the anchor points coincide, so the default length (their distance) is 0; "
           "give \"length\"");
    if (!std::isfinite(dc.length))
      fail(node, "the default length (the anchors' distance) is not finite; give \"length\"");
  }
  return dc;
}

void read_constraints(const Node& node, Scene& scene) {
  check_array(node);
  for (std::size_t k = 0; k < node.json.size(); ++k) {
    const Node item = element(node, k);
    if (!item.json.is_object())
      fail(item, "expected an object (got " + std::string(item.json.type_name()) + ")");
    const std::string type = has(item, "type") ? text(child(item, "type")) : "distance";
    if (!contains(kConstraintTypes, type))
      fail(child(item, "type"),
           "unknown constraint type " + in_quotes(type) + " (valid: " + join(kConstraintTypes) +
               ")");
    scene.distances.push_back(read_distance(item, k, scene.bodies));
  }
}

Scene read_scene(const Node& root, const std::string& default_name) {
  check_object(root,
               {"name",
                "description",
                "parameters",
                "duration",
                "world",
                "solver",
                "bodies",
                "constraints"});
  Scene scene;
  scene.name = has(root, "name") ? text(child(root, "name")) : default_name;
  if (has(root, "description")) text(child(root, "description"));
  if (has(root, "parameters")) {  // name → value text, any names
    const Node parameters = child(root, "parameters");
    if (!parameters.json.is_object())
      fail(parameters, "expected an object (got " + std::string(parameters.json.type_name()) + ")");
    for (const auto& item : parameters.json.items())
      scene.parameters.emplace_back(item.key(), text(child(parameters, item.key())));
  }
  if (has(root, "duration")) scene.duration = positive(child(root, "duration"));
  if (has(root, "world")) scene.world = read_world(child(root, "world"));
  if (has(root, "solver")) scene.solver = read_solver(child(root, "solver"));
  if (!(has(root, "solver") && has(child(root, "solver"), "method")))
    scene.solver.method = scene.world.default_method();

  const Node bodies = required(root, "bodies");
  check_array(bodies);
  std::map<std::string, std::size_t> first_seen;
  for (std::size_t i = 0; i < bodies.json.size(); ++i) {
    const Node item = element(bodies, i);
    scene.bodies.push_back(read_body(item, i, scene.world));
    const auto [it, inserted] = first_seen.emplace(scene.bodies.back().name, i);
    if (!inserted)
      fail(item.source,
           item.path + (has(item, "name") ? "/name" : ""),
           "duplicate body name " + in_quotes(it->first) + " (also /bodies/" +
               std::to_string(it->second) + ")");
  }
  if (has(root, "constraints")) read_constraints(child(root, "constraints"), scene);
  return scene;
}

// ---- Parsing the text ----------------------------------------------------------------------

/// Follows the parser through the document so that errors it cannot place itself (a
/// duplicate key, a number too large for a double) get a JSON pointer.
class PathTracker {
 public:
  static constexpr std::size_t kMaxNesting = 64;

  explicit PathTracker(const std::string& source) : source_(source) {}

  bool operator()(int /*depth*/, Json::parse_event_t event, Json& parsed) {
    switch (event) {
      case Json::parse_event_t::object_start:
      case Json::parse_event_t::array_start:
        // A scene nests 5 levels deep. Far deeper documents are refused here, while parsing:
        // nlohmann copies values recursively (ordered_json copies an object's members when it
        // grows), so 10^4 levels or more would overflow the stack.
        if (frames_.size() >= kMaxNesting)
          fail(source_,
               path(),
               "nested deeper than " + std::to_string(kMaxNesting) + " arrays and objects");
        frames_.push_back(Frame{event == Json::parse_event_t::array_start, 0, "", {}});
        break;
      case Json::parse_event_t::key: {
        Frame& frame = frames_.back();
        frame.key = parsed.get<std::string>();
        if (!frame.keys.insert(frame.key).second) fail(source_, path(), "duplicate key");
        break;
      }
      case Json::parse_event_t::object_end:
      case Json::parse_event_t::array_end:
        frames_.pop_back();
        next_element();
        break;
      case Json::parse_event_t::value:
        next_element();
        break;
    }
    return true;
  }

  /// JSON pointer of the value being parsed.
  std::string path() const {
    std::string out;
    for (const Frame& frame : frames_) {
      out.push_back('/');
      out.append(frame.is_array ? std::to_string(frame.index) : pointer_token(frame.key));
    }
    return out;
  }

 private:
  struct Frame {
    bool is_array;
    std::size_t index;           // arrays: the element being parsed
    std::string key;             // objects: the key being parsed
    std::set<std::string> keys;  // objects: keys seen so far
  };

  void next_element() {
    if (!frames_.empty() && frames_.back().is_array) ++frames_.back().index;
  }

  const std::string& source_;
  std::vector<Frame> frames_;
};

/// "line L, column C" of the 1-based byte position nlohmann reports (the last byte it read).
std::string line_column(const std::string& text, std::size_t byte) {
  const std::size_t offset = std::min(byte > 0 ? byte - 1 : 0, text.size());
  std::size_t line = 1;
  std::size_t line_start = 0;
  for (std::size_t k = 0; k < offset; ++k)
    if (text[k] == '\n') {
      ++line;
      line_start = k + 1;
    }
  return "line " + std::to_string(line) + ", column " + std::to_string(offset - line_start + 1);
}

/// nlohmann's message without its "[json.exception...] parse error at ...: " prefix.
std::string parser_reason(const std::string& what) {
  std::size_t start = what.find("] ");
  start = start == std::string::npos ? 0 : start + 2;
  const std::size_t at = what.find("parse error", start);
  if (at != std::string::npos) {
    const std::size_t colon = what.find(": ", at);
    if (colon != std::string::npos) return what.substr(colon + 2);
  }
  return what.substr(start);
}

Scene parse_scene_named(const std::string& text,
                        const std::string& source,
                        const std::string& default_name) {
  PathTracker tracker(source);
  Json root;
  try {
    root = Json::parse(text, std::ref(tracker));
  } catch (const Json::parse_error& e) {
    throw InputError(source + ": " + line_column(text, e.byte) + ": " + parser_reason(e.what()));
  } catch (const Json::out_of_range& e) {  // a number beyond a double's range, such as 1e999
    fail(source, tracker.path(), "not a finite number (" + parser_reason(e.what()) + ")");
  }
  return read_scene(Node{root, source, ""}, default_name);
}

// ---- Writing -------------------------------------------------------------------------------

Json vec_json(const Vec3& v) { return Json::array({v.x(), v.y(), v.z()}); }

constexpr std::size_t kInlineObjectWidth = 60;  // objects up to this wide stay on one line

/// The value on one line: "[1.0, 2.0]", {"type": "sphere", "radius": 0.05}.
std::string one_line(const Json& j) {
  if (!j.is_object() && !j.is_array()) return j.dump();
  std::string out = j.is_object() ? "{" : "[";
  bool first = true;
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (!first) out += ", ";
    first = false;
    if (j.is_object()) out += Json(it.key()).dump() + ": ";
    out += one_line(it.value());
  }
  return out + (j.is_object() ? "}" : "]");
}

bool holds_object(const Json& j) {
  for (const Json& e : j)
    if (e.is_object() || (e.is_array() && holds_object(e))) return true;
  return false;
}

/// Pretty printing with 2-space indents, except that arrays holding no objects (vectors,
/// quaternions, inertia matrices) and short flat objects (shapes) stay on one line. Numbers as
/// nlohmann writes them: the shortest text that reads back to the same double.
void write(const Json& j, int indent, std::string& out) {
  if (!j.is_object() && !j.is_array()) {
    out += j.dump();
    return;
  }
  const std::string flat = holds_object(j) ? "" : one_line(j);
  if (j.empty() || (!flat.empty() && (j.is_array() || flat.size() <= kInlineObjectWidth))) {
    out += one_line(j);
    return;
  }
  const std::string pad(indent + 2, ' ');
  out += j.is_object() ? "{\n" : "[\n";
  bool first = true;
  for (auto it = j.begin(); it != j.end(); ++it) {
    out += first ? pad : ",\n" + pad;
    first = false;
    if (j.is_object()) out += Json(it.key()).dump() + ": ";
    write(it.value(), indent + 2, out);
  }
  out += "\n" + std::string(indent, ' ') + (j.is_object() ? "}" : "]");
}

Json body_json(const Body& body) {
  Json out = Json::object();
  if (!body.name.empty()) out["name"] = body.name;
  Json shape = Json::object();
  if (body.shape.kind == Shape::Kind::Sphere) {
    shape["type"] = "sphere";
    shape["radius"] = body.shape.radius;
  } else if (body.shape.kind == Shape::Kind::Box) {
    shape["type"] = "box";
    shape["half_extents"] = vec_json(body.shape.half_extents);
  } else {
    shape["type"] = "plane";
  }
  out["shape"] = shape;
  if (body.is_static) out["static"] = true;
  if (!body.collides) out["collides"] = false;

  // Write mass and inertia only where the reader would not rebuild them as they are. A plane
  // takes neither: the reader gives it the defaults m = 1, I = 1.
  const bool plane = body.shape.kind == Shape::Kind::Plane;
  Body rebuilt;
  rebuilt.shape = body.shape;
  rebuilt.is_static = body.is_static;
  const bool write_mass = !plane && (!body.is_static || body.m != 1.0);
  bool solid = true;  // the reader can rebuild the solid's inertia from the mass
  if (write_mass) {
    out["mass"] = body.m;
    // The reader rebuilds the solid's inertia from the mass only where its inverse is finite
    // (a tiny shape's I can underflow to 0); otherwise "inertia" is written below.
    solid = finite_inverse(body.shape.inertia(body.m), rebuilt.I_body_inv);
    if (solid) set_mass(rebuilt, body.m);
  }
  if (!plane &&
      (!solid || rebuilt.I_body != body.I_body || rebuilt.I_body_inv != body.I_body_inv)) {
    const Mat3& I = body.I_body;
    if (I(0, 1) == 0.0 && I(0, 2) == 0.0 && I(1, 2) == 0.0 && I(1, 0) == 0.0 && I(2, 0) == 0.0 &&
        I(2, 1) == 0.0) {
      out["inertia"] = vec_json(I.diagonal());
    } else {
      Json rows = Json::array();
      for (int i = 0; i < 3; ++i) rows.push_back(Json::array({I(i, 0), I(i, 1), I(i, 2)}));
      out["inertia"] = rows;
    }
  }
  out["position"] = vec_json(body.x);
  out["orientation"] = Json::array({body.q.w(), body.q.x(), body.q.y(), body.q.z()});

  // Velocities read more easily than momenta; write a momentum only where p = m (p/m) or
  // l = I (I⁻¹ l) would not give back the same bits.
  Body probe = body;
  probe.set_velocity(body.v(), body.omega());
  const bool linear_exact = !body.is_static && probe.p == body.p;
  const bool angular_exact = !body.is_static && probe.l == body.l;
  if (!body.p.isZero(0.0)) {
    if (linear_exact)
      out["velocity"] = vec_json(body.v());
    else
      out["momentum"] = vec_json(body.p);
  }
  if (!body.l.isZero(0.0)) {
    if (angular_exact)
      out["angular_velocity"] = vec_json(body.omega());
    else
      out["angular_momentum"] = vec_json(body.l);
  }
  return out;
}

}  // namespace

Scene read_scene_file(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw InputError(path + ": cannot open");
  std::ostringstream text;
  text << file.rdbuf();
  if (file.bad()) throw InputError(path + ": cannot read");
  const std::string stem = std::filesystem::path(path).stem().string();
  return parse_scene_named(text.str(), path, stem.empty() ? "scene" : stem);
}

Scene parse_scene(const std::string& text, const std::string& source) {
  return parse_scene_named(text, source, "scene");
}

std::string scene_to_json(const Scene& scene) {
  Json root = Json::object();
  root["name"] = scene.name;
  if (!scene.parameters.empty()) {
    Json parameters = Json::object();
    for (const auto& [name, value] : scene.parameters) parameters[name] = value;
    root["parameters"] = parameters;
  }
  root["duration"] = scene.duration;

  Json world = Json::object();
  world["gravity"] = vec_json(scene.world.gravity);
  write_settings(world, world_settings(), scene.world);
  root["world"] = world;

  Json solver = Json::object();
  write_settings(solver, solver_settings(), scene.solver);
  // The method's own parameters, numbers as numbers, words as the grammar writes them.
  Json parameters = Json::object();
  for (const auto& [key, value] : method_parameters(scene.solver.method, scene.solver.methods)) {
    double x = 0.0;
    parameters[key] = parse_number(value, x) ? Json(x) : Json(value);
  }
  if (!parameters.empty()) solver["parameters"] = parameters;
  root["solver"] = solver;

  Json bodies = Json::array();
  std::map<std::string, int> name_count;
  for (const Body& body : scene.bodies) {
    bodies.push_back(body_json(body));
    ++name_count[body.name];
  }
  root["bodies"] = bodies;

  // A constraint end by name where the name finds that body, else by index.
  const auto end_json = [&](int i) -> Json {
    if (i < 0) return "world";
    const std::string& name = scene.bodies.at(i).name;
    if (!name.empty() && name != "world" && name_count[name] == 1) return name;
    return i;
  };
  Json constraints = Json::array();
  for (const DistanceConstraint& dc : scene.distances) {
    Json c = Json::object();
    c["name"] = dc.name;
    c["type"] = "distance";
    c["a"] = end_json(dc.a);
    c["b"] = end_json(dc.b);
    c["anchor_a"] = vec_json(dc.anchor_a);
    c["anchor_b"] = vec_json(dc.anchor_b);
    c["length"] = dc.length;
    constraints.push_back(c);
  }
  root["constraints"] = constraints;

  std::string out;
  write(root, 0, out);
  return out + "\n";
}

}  // namespace cbps
