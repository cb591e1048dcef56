// Built-in scene `pendulum-wave`: the paper's Figure 10 (section 10).
//
// Ball k (k = 0 … n−1) hangs from a fixed pivot at (0, 0, k·spacing) and makes n0 + k full
// swings in `cycle` seconds, so all balls are in phase again at t = cycle. Its period is
// T_k = cycle / (n0 + k). The pivot-to-centre length follows from the exact large-amplitude
// period T = 4 sqrt(L/g) K(sin(θ0/2)):   L_k = g (T_k / (4 K(sin(θ0/2))))².
// attach=center: a distance constraint from the pivot to the ball's centre, a simple pendulum
//   whose exact period is T_k.
// attach=top (the paper's picture): the constraint ends at the ball's top point, rest length
//   L_k − radius; the ball can turn about that point, so this is a double pendulum whose
//   period differs slightly from T_k.
#include <cmath>

#include "cbps/error.hpp"
#include "scene_parameters.hpp"

namespace cbps {

Scene build_pendulum_wave(const std::map<std::string, std::string>& values) {
  const ParameterValues p(*find_builtin_scene("pendulum-wave"), values);
  const long n = p.integer("n", 1, 100000);
  const long n0 = p.integer("n0", 1, 1000000);
  const double cycle = p.positive("cycle");
  const double theta0 = p.number("theta0_deg", 0.0, 179.0) * kPi / 180.0;
  const bool top = p.word("attach", "top|center") == "top";
  const double radius = p.positive("radius");
  const double mass = p.positive("mass");
  const double spacing = p.number("spacing", 0.0, kInf);

  Scene scene;
  scene.name = "pendulum-wave";
  scene.world.dt = p.positive("dt");
  scene.world.beta = p.number("beta", 0.0, 1.0);
  scene.duration = p.given("duration") ? p.positive("duration") : cycle;
  const double g = -scene.world.gravity.y();
  const double K = elliptic_K(std::sin(0.5 * theta0));

  for (long k = 0; k < n; ++k) {
    const double T_k = cycle / static_cast<double>(n0 + k);  // s
    const double L_k = g * std::pow(T_k / (4.0 * K), 2);     // pivot to centre, m
    if (top && !(L_k > radius)) {
      throw InputError("scene 'pendulum-wave': ball " + std::to_string(k) +
                       " would need a string shorter than its radius; lower n0 or radius");
    }
    const Vec3 pivot(0.0, 0.0, static_cast<double>(k) * spacing);

    Body ball;
    ball.name = "ball" + std::to_string(k);
    ball.shape.kind = Shape::Kind::Sphere;
    ball.shape.radius = radius;
    set_mass(ball, mass);
    ball.x = pivot + L_k * Vec3(std::sin(theta0), -std::cos(theta0), 0.0);
    ball.q = Quat(Eigen::AngleAxisd(theta0, Vec3::UnitZ()));  // its top faces the pivot

    DistanceConstraint string;
    string.name = "string" + std::to_string(k);
    string.a = -1;  // the world
    string.anchor_a = pivot;
    string.b = static_cast<int>(k);
    string.anchor_b = top ? Vec3(0.0, radius, 0.0) : Vec3::Zero();
    string.l = top ? L_k - radius : L_k;

    scene.bodies.push_back(ball);
    scene.distances.push_back(string);
  }
  scene.parameters = p.in_force();
  return scene;
}

}  // namespace cbps
