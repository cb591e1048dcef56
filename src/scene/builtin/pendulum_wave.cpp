// Built-in scene `pendulum-wave`: the paper's Figure 10 (section 10).
//
// Ball k (k = 0 … n−1) hangs from a fixed pivot at (0, 0, k·spacing) and makes n0 + k full
// swings in `cycle` seconds, so all balls are in phase again at t = cycle. Its period is
// T_k = cycle / (n0 + k). The pivot-to-centre length follows from the exact large-amplitude
// period T = 4 sqrt(L/g) K(sin(θ0/2)):   L_k = g (T_k / (4 K(sin(θ0/2))))².
// attach=center: a distance constraint from the pivot to the ball's centre, a simple pendulum
//   whose exact period is T_k.
// attach=top (the paper's picture): the constraint ends at the ball's top point. The ball can
//   turn about that point, so string + ball are a double pendulum (string angle φ, ball angle
//   ψ, string length l, radius r, I = 2/5 m r²). Linearised, with M = m [l², l r; l r, 7/5 r²]
//   and K = m g [l, 0; 0, r], its frequencies solve  2/5 l r ω⁴ − g (l + 7/5 r) ω² + g² = 0.
//   Asking the slow mode for ω² = g/L_k (L_k from the rule above) gives
//     l = L_k (L_k − 7/5 r) / (L_k − 2/5 r),   with mode shape ψ/φ = L_k / (L_k − 2/5 r);
//   the ball is released in that shape (string at θ0, ball at θ0 L_k/(L_k − 2/5 r)), so the fast
//   mode is not excited and the wave realigns as the paper's does. The amplitude correction K is
//   the simple pendulum's, an approximation for the double pendulum (validation/README.md).
#include <cmath>

#include "cbps/base/error.hpp"
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
    // String length and release angles: l = L_k, ψ0 = φ0 = θ0 for attach=center; the slow
    // mode of the double pendulum for attach=top (see above).
    const double l = top ? L_k * (L_k - 1.4 * radius) / (L_k - 0.4 * radius) : L_k;
    const double phi0 = theta0;
    const double psi0 = top ? theta0 * L_k / (L_k - 0.4 * radius) : theta0;
    if (!(l > 0.0)) {
      throw InputError("scene 'pendulum-wave': ball " + std::to_string(k) +
                       " is too large for its period (string length " + std::to_string(l) +
                       " m); lower n0 or radius");
    }
    const Vec3 pivot(0.0, 0.0, static_cast<double>(k) * spacing);
    const Vec3 string_end = pivot + l * Vec3(std::sin(phi0), -std::cos(phi0), 0.0);

    Body ball;
    ball.name = "ball" + std::to_string(k);
    ball.shape.kind = Shape::Kind::Sphere;
    ball.shape.radius = radius;
    ball.collides = false;  // the paper's Figure 10 has no collisions
    set_mass(ball, mass);
    ball.q = Quat(Eigen::AngleAxisd(psi0, Vec3::UnitZ()));  // body +y (its top) turned by ψ0
    ball.x =
        top ? Vec3(string_end + radius * Vec3(std::sin(psi0), -std::cos(psi0), 0.0)) : string_end;

    DistanceConstraint string;
    string.name = "string" + std::to_string(k);
    string.a = -1;  // the world
    string.anchor_a = pivot;
    string.b = static_cast<int>(k);
    string.anchor_b = top ? Vec3(0.0, radius, 0.0) : Vec3::Zero();
    string.length = l;

    scene.bodies.push_back(ball);
    scene.distances.push_back(string);
  }
  scene.parameters = p.in_force();
  return scene;
}

}  // namespace cbps
