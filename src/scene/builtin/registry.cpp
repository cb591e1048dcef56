// The list of built-in scenes, their parameter handling, and the exact pendulum period.
#include <cmath>
#include <sstream>

#include "cbps/base/error.hpp"
#include "cbps/base/numbers.hpp"
#include "scene_parameters.hpp"

namespace cbps {

Scene build_pendulum_wave(const std::map<std::string, std::string>& values);
Scene build_chain(const std::map<std::string, std::string>& values);
Scene build_v_corner(const std::map<std::string, std::string>& values);
Scene build_stack(const std::map<std::string, std::string>& values);
Scene build_pyramid(const std::map<std::string, std::string>& values);
Scene build_card_house(const std::map<std::string, std::string>& values);
Scene build_newtons_cradle(const std::map<std::string, std::string>& values);
Scene build_slide(const std::map<std::string, std::string>& values);
Scene build_bounce(const std::map<std::string, std::string>& values);
Scene build_overlap(const std::map<std::string, std::string>& values);

namespace {

/// A contact scene's own parameters followed by the world settings every contact scene has
/// (read by read_contact_world in contact_scenes.cpp), with this scene's defaults.
std::vector<SceneParameter> with_contact_world(std::vector<SceneParameter> own,
                                               const std::string& dt,
                                               const std::string& mu,
                                               const std::string& restitution,
                                               const std::string& push,
                                               const std::string& duration,
                                               const std::string& friction = "paper") {
  own.push_back({"dt", dt, "s", "time step"});
  own.push_back({"beta", "0.2", "", "push factor (5.3)"});
  own.push_back({"mu", mu, "", "friction coefficient (5.4); 0: no friction rows"});
  own.push_back({"friction",
                 friction,
                 "-",
                 "paper (±mu m |g·n|, 5.4) | coulomb (±mu lambda_n) | cone (Coulomb's cone, "
                 "solved by nsgs unless --solver says, docs/cones.md)"});
  own.push_back(
      {"cone", "coulomb", "-", "with friction=cone: coulomb (De Saxce) | ccp (relaxation)"});
  own.push_back({"restitution", restitution, "", "coefficient of restitution epsilon (8.2.1)"});
  own.push_back({"push", push, "-", "original (Baumgarte, 5.3) | improved (two systems, 8.1)"});
  own.push_back({"margin",
                 "0.001",
                 "m",
                 "contacts kept up to this separation (4)"});  // as kSceneContactMargin
  own.push_back({"persistence",
                 "0.02",
                 "m",
                 "a contact point within this of last step's continues it (its warm start, 7); 0: "
                 "by feature id"});  // as kSceneContactPersistence
  own.push_back({"duration", duration, "s", "simulated time"});
  return own;
}

}  // namespace

const std::vector<BuiltinScene>& builtin_scenes() {
  static const std::vector<BuiltinScene> scenes = {
      {"pendulum-wave",
       "The paper's Figure 10: n balls on distance constraints to fixed points; ball k makes "
       "n0+k swings per cycle, so the wave realigns at the end of the cycle",
       {{"n", "50", "-", "number of balls"},
        {"n0", "51", "-", "swings of the longest pendulum per cycle"},
        {"cycle", "60", "s", "time after which all balls are in phase again"},
        {"theta0_deg", "15", "deg", "release angle from the vertical"},
        {"attach",
         "top",
         "-",
         "top (the paper: string at the ball's top) | center (exact "
         "simple pendulum)"},
        {"radius", "0.02", "m", "ball radius"},
        {"mass", "0.1", "kg", "ball mass"},
        {"spacing", "0.05", "m", "distance between neighbouring pivots (along z)"},
        {"dt", "1/240", "s", "time step"},
        {"beta", "0.2", "", "Baumgarte push factor (5.2.3)"},
        {"duration", "cycle", "s", "simulated time (default: one cycle)"}},
       build_pendulum_wave},
      {"chain",
       "n links hanging from a fixed point by distance constraints, released horizontally; "
       "the last link's mass is mass_ratio times the others",
       {{"n", "10", "-", "number of links (bodies)"},
        {"link_length", "0.1", "m", "distance between neighbouring link centres"},
        {"link_mass", "0.1", "kg", "mass of each link but the last"},
        {"mass_ratio", "1", "", "last link's mass / link_mass"},
        {"radius", "0.02", "m", "link (sphere) radius"},
        {"dt", "1/240", "s", "time step"},
        {"beta", "0.2", "", "Baumgarte push factor (5.2.3)"},
        {"duration", "5", "s", "simulated time"}},
       build_chain},
      {"v-corner",
       "The appendix's Figure 11 (12.2): a sphere resting in a static V of two planes, two "
       "contacts; at rest lambda_1 = m g sin(phi_r)/sin(phi_l + phi_r), lambda_2 likewise",
       with_contact_world({{"angle_left_deg", "45", "deg", "left plane's tilt from horizontal"},
                           {"angle_right_deg", "30", "deg", "right plane's tilt"},
                           {"radius", "0.1", "m", "sphere radius"},
                           {"mass", "1", "kg", "sphere mass"}},
                          "1/60",
                          "0",
                          "0",
                          "original",
                          "2"),
       build_v_corner},
      {"stack",
       "n boxes stacked on a ground plane, in one or more columns on a square grid",
       with_contact_world({{"n", "10", "-", "boxes per column"},
                           {"columns", "1", "-", "number of columns"},
                           {"size", "1", "m", "box edge"},
                           {"mass", "1", "kg", "box mass"},
                           {"gap", "0.5", "m", "gap between columns"}},
                          "1/60",
                          "0.5",
                          "0",
                          "improved",
                          "10"),
       build_stack},
      {"pyramid",
       "A 2-D pyramid of boxes on a ground plane; base b gives b(b+1)/2 boxes",
       with_contact_world({{"base", "10", "-", "boxes in the bottom row"},
                           {"size", "1", "m", "box edge"},
                           {"mass", "1", "kg", "box mass"},
                           {"gap", "0.1", "m", "gap between neighbours in a row"}},
                          "1/60",
                          "0.5",
                          "0",
                          "improved",
                          "5"),
       build_pyramid},
      {"card-house",
       "Solver2D's card house in 3-D: pairs of thin cards leaning on each other in Λs on the "
       "ground, a flat card across each two neighbouring Λs, the next level's Λs on the flat "
       "cards, up to one Λ at the top",
       with_contact_world({{"pairs", "3", "-", "Λs on the ground (levels: as many)"},
                           {"height", "0.5", "m", "card length (the Λs' sides)"},
                           {"thickness", "0.02", "m", "card thickness"},
                           {"width", "0.35", "m", "card width (along z)"},
                           {"mass", "0.1", "kg", "card mass"},
                           {"angle_deg", "25", "deg", "a leaning card's angle from the vertical"},
                           {"gap", "0.005", "m", "gap between neighbouring flat cards' ends"}},
                          "1/60",
                          "0.7",
                          "0",
                          "original",
                          "10",
                          "coulomb"),
       build_card_house},
      {"newtons-cradle",
       "n touching balls on strings; the first is pulled back and released; restitution 1",
       with_contact_world({{"n", "5", "-", "number of balls"},
                           {"radius", "0.05", "m", "ball radius"},
                           {"length", "0.5", "m", "string length (pivot to centre)"},
                           {"theta0_deg", "30", "deg", "release angle of the first ball"},
                           {"mass", "0.2", "kg", "ball mass"},
                           {"gap",
                            "0.002",
                            "m",
                            "gap between neighbouring balls at rest; 0: all touching, and the "
                            "one simultaneous impact sends balls 1..n-1 off together"}},
                          "1/240",
                          "0",
                          "1",
                          "improved",
                          "3"),
       build_newtons_cradle},
      {"slide",
       "A box sliding on a plane with speed v0; it stops after v0^2/(2 mu g)",
       with_contact_world({{"v0", "2", "m/s", "initial speed along x"},
                           {"size", "0.2", "m", "box edge"},
                           {"mass", "1", "kg", "box mass"}},
                          "1/240",
                          "0.3",
                          "0",
                          "improved",
                          "1.5"),
       build_slide},
      {"bounce",
       "A ball dropped on a plane with restitution epsilon: each rebound height is epsilon^2 "
       "times the one before",
       with_contact_world({{"height", "1", "m", "drop height of the ball's lowest point"},
                           {"radius", "0.1", "m", "ball radius"},
                           {"mass", "1", "kg", "ball mass"}},
                          "1/240",
                          "0",
                          "0.8",
                          "improved",
                          "3"),
       build_bounce},
      {"overlap",
       "The push-factor figure (8.1): boxes stacked with each sunk into the one below",
       with_contact_world({{"n", "3", "-", "number of boxes"},
                           {"size", "1", "m", "box edge"},
                           {"mass", "1", "kg", "box mass"},
                           {"overlap", "0.25", "", "overlap as a fraction of the edge"}},
                          "1/60",
                          "0.5",
                          "0",
                          "original",
                          "2"),
       build_overlap},
  };
  return scenes;
}

const BuiltinScene* find_builtin_scene(const std::string& name) {
  for (const BuiltinScene& s : builtin_scenes()) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

Scene make_builtin_scene(const std::string& name,
                         const std::map<std::string, std::string>& values) {
  const BuiltinScene* s = find_builtin_scene(name);
  if (s == nullptr) {
    std::string valid;
    for (const BuiltinScene& b : builtin_scenes()) valid += (valid.empty() ? "" : ", ") + b.name;
    throw InputError("scene '" + name +
                     "': no such built-in scene and no such file (built-in: " + valid + ")");
  }
  return s->build(values);
}

ParameterValues::ParameterValues(const BuiltinScene& scene,
                                 const std::map<std::string, std::string>& values)
    : scene_(scene), given_(values) {
  for (const SceneParameter& p : scene.parameters) values_[p.name] = p.default_value;
  for (const auto& [name, value] : values) {
    if (values_.count(name) == 0) {
      std::string valid;
      for (const SceneParameter& p : scene.parameters)
        valid += (valid.empty() ? "" : ", ") + p.name;
      throw InputError("scene '" + scene.name + "': unknown parameter '" + name +
                       "' (valid: " + valid + ")");
    }
    values_[name] = value;
  }
}

void ParameterValues::fail(const std::string& name, const std::string& why) const {
  throw InputError("scene '" + scene_.name + "': parameter '" + name + "': " + why + " (got '" +
                   values_.at(name) + "')");
}

bool ParameterValues::given(const std::string& name) const { return given_.count(name) > 0; }

std::string ParameterValues::text(const std::string& name) const { return values_.at(name); }

double ParameterValues::number(const std::string& name, double lo, double hi) const {
  double v = 0.0;
  if (!parse_number(values_.at(name), v)) fail(name, "expected a finite number");
  if (v < lo || v > hi) {
    std::ostringstream why;
    why << "must be in [" << lo << ", " << hi << "]";
    fail(name, why.str());
  }
  return v;
}

double ParameterValues::positive(const std::string& name) const {
  const double v = number(name, -kInf, kInf);
  if (!(v > 0.0)) fail(name, "must be > 0");
  return v;
}

long ParameterValues::integer(const std::string& name, long lo, long hi) const {
  const double v = number(name, static_cast<double>(lo), static_cast<double>(hi));
  if (v != std::floor(v)) fail(name, "expected an integer");
  return static_cast<long>(v);
}

std::string ParameterValues::word(const std::string& name, const std::string& choices) const {
  const std::string v = values_.at(name);
  std::istringstream in(choices);
  std::string choice;
  while (std::getline(in, choice, '|')) {
    if (choice == v) return v;
  }
  fail(name, "expected one of " + choices);
}

std::vector<std::pair<std::string, std::string>> ParameterValues::in_force() const {
  std::vector<std::pair<std::string, std::string>> out;
  for (const SceneParameter& p : scene_.parameters) out.emplace_back(p.name, values_.at(p.name));
  return out;
}

double elliptic_K(double k) {
  // K(k) = π / (2 AGM(1, k')), k' = sqrt(1 − k²); the AGM converges quadratically.
  double a = 1.0;
  double g = std::sqrt((1.0 - k) * (1.0 + k));
  for (int it = 0; it < 64 && std::abs(a - g) > 1e-16 * a; ++it) {
    const double a_next = 0.5 * (a + g);
    g = std::sqrt(a * g);
    a = a_next;
  }
  return kPi / (2.0 * a);
}

double pendulum_period(double L, double g, double theta0) {
  return 4.0 * std::sqrt(L / g) * elliptic_K(std::sin(0.5 * theta0));
}

}  // namespace cbps
