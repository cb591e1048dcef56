// Built-in contact scenes (paper 4, 5.3, 5.4, 8, 12.2): v-corner, stack, pyramid,
// newtons-cradle, slide, bounce, overlap. Each has an analytic expectation stated where it is
// built; validation/ and tests/ compare against it.
#include <algorithm>
#include <cmath>

#include "cbps/base/error.hpp"
#include "cbps/base/numbers.hpp"
#include "scene_parameters.hpp"

namespace cbps {

namespace {

/// The world settings every contact scene reads: dt, beta, mu, friction, restitution, push,
/// duration.
void read_contact_world(const ParameterValues& p, Scene& scene) {
  scene.world.dt = p.positive("dt");
  scene.world.beta = p.number("beta", 0.0, 1.0);
  scene.world.mu = p.number("mu", 0.0, kInf);
  const std::string friction = p.word("friction", "paper|coulomb|cone");
  FrictionLaw cone = FrictionLaw::CoulombCone;
  cone_law_from_string(p.word("cone", "coulomb|ccp"), cone);
  scene.world.friction = friction == "coulomb" ? FrictionLaw::CoulombBox
                         : friction == "cone"  ? cone
                                               : FrictionLaw::PaperBox;
  scene.solver.method = scene.world.default_method();
  scene.world.restitution = p.number("restitution", 0.0, 1.0);
  scene.world.push =
      p.word("push", "original|improved") == "improved" ? PushMode::Improved : PushMode::Original;
  scene.world.contact_margin = p.number("margin", 0.0, kInf);
  scene.world.contact_persistence = p.number("persistence", 0.0, kInf);
  scene.duration = p.positive("duration");
}

}  // namespace

/// A static ground plane through `point` with outward normal `normal` (unit).
Body ground_body(const std::string& name, const Vec3& point, const Vec3& normal) {
  Body plane;
  plane.name = name;
  plane.shape.kind = Shape::Kind::Plane;
  plane.is_static = true;
  plane.x = point;
  plane.q = Quat::FromTwoVectors(Vec3::UnitY(), normal);  // local +y is the outward normal
  return plane;
}

Body box_body(const std::string& name, const Vec3& half_extents, double mass, const Vec3& x) {
  Body b;
  b.name = name;
  b.shape.kind = Shape::Kind::Box;
  b.shape.half_extents = half_extents;
  set_mass(b, mass);
  b.x = x;
  return b;
}

Body sphere_body(const std::string& name, double radius, double mass, const Vec3& x) {
  Body b;
  b.name = name;
  b.shape.kind = Shape::Kind::Sphere;
  b.shape.radius = radius;
  set_mass(b, mass);
  b.x = x;
  return b;
}

// The appendix's Figure 11 (12.2): a sphere of mass m resting in a static V of two planes
// tilted by angle_left and angle_right from the horizontal. Normals a = (sin φ_l, cos φ_l, 0),
// b = (−sin φ_r, cos φ_r, 0); at rest a λ₁ + b λ₂ = m g ŷ, so
//   λ₁ = m g sin φ_r / sin(φ_l + φ_r),   λ₂ = m g sin φ_l / sin(φ_l + φ_r)   (N).
Scene build_v_corner(const std::map<std::string, std::string>& values) {
  const ParameterValues p(*find_builtin_scene("v-corner"), values);
  Scene scene;
  scene.name = "v-corner";
  read_contact_world(p, scene);
  const double phi_l = p.number("angle_left_deg", 1.0, 89.0) * kPi / 180.0;
  const double phi_r = p.number("angle_right_deg", 1.0, 89.0) * kPi / 180.0;
  const double r = p.positive("radius");
  const Vec3 a(std::sin(phi_l), std::cos(phi_l), 0.0);
  const Vec3 b(-std::sin(phi_r), std::cos(phi_r), 0.0);
  scene.bodies.push_back(ground_body("left", Vec3::Zero(), a));
  scene.bodies.push_back(ground_body("right", Vec3::Zero(), b));
  // The centre c touching both planes: a·c = r and b·c = r (z = 0).
  Eigen::Matrix2d N;
  N << a.x(), a.y(), b.x(), b.y();
  const Eigen::Vector2d c = N.inverse() * Eigen::Vector2d(r, r);
  scene.bodies.push_back(sphere_body("ball", r, p.positive("mass"), Vec3(c.x(), c.y(), 0.0)));
  scene.parameters = p.in_force();
  return scene;
}

// n boxes of edge `size` stacked on a ground plane, in `columns` columns on a square grid
// `gap` apart; each box starts exactly touching the one below (depth 0).
Scene build_stack(const std::map<std::string, std::string>& values) {
  const ParameterValues p(*find_builtin_scene("stack"), values);
  Scene scene;
  scene.name = "stack";
  read_contact_world(p, scene);
  const long n = p.integer("n", 1, 100000);
  const long columns = p.integer("columns", 1, 100000);
  const double h = 0.5 * p.positive("size");
  const double gap = p.number("gap", 0.0, kInf);
  const double mass = p.positive("mass");
  scene.bodies.push_back(ground_body("ground", Vec3::Zero(), Vec3::UnitY()));
  const auto side = static_cast<long>(std::ceil(std::sqrt(static_cast<double>(columns))));
  for (long c = 0; c < columns; ++c) {
    const double x = static_cast<double>(c % side) * (2 * h + gap);
    const double z = static_cast<double>(c / side) * (2 * h + gap);
    for (long k = 0; k < n; ++k) {
      const double y = h + 2 * h * static_cast<double>(k);
      scene.bodies.push_back(box_body("box" + std::to_string(c) + "_" + std::to_string(k),
                                      Vec3::Constant(h),
                                      mass,
                                      Vec3(x, y, z)));
    }
  }
  scene.parameters = p.in_force();
  return scene;
}

// A 2-D pyramid of boxes on a ground plane: row k (from the bottom) has base − k boxes, each
// resting on two below; neighbours in a row are `gap` apart so only the rows touch.
// build_pyramid_range builds the ground and any contiguous run of its boxes (the distributed
// generator, include/cbps/distributed/generate.hpp); build_pyramid is the run of all of them, so
// both paths share every box.
Scene build_pyramid(const std::map<std::string, std::string>& values) {
  const long base = pyramid_base(values);
  return build_pyramid_range(values, 0, base * (base + 1) / 2);
}

long pyramid_base(const std::map<std::string, std::string>& values) {
  return ParameterValues(*find_builtin_scene("pyramid"), values).integer("base", 1, 10000);
}

Scene build_pyramid_range(const std::map<std::string, std::string>& values, long first, long last) {
  const ParameterValues p(*find_builtin_scene("pyramid"), values);
  Scene scene;
  scene.name = "pyramid";
  read_contact_world(p, scene);
  const long base = p.integer("base", 1, 10000);
  const long boxes = base * (base + 1) / 2;
  if (first < 0 || last > boxes || first > last)
    throw InputError("pyramid: boxes [" + std::to_string(first) + ", " + std::to_string(last) +
                     ") are not a part of the " + std::to_string(boxes) + " boxes");
  const double h = 0.5 * p.positive("size");
  const double gap = p.number("gap", 0.0, kInf);
  const double mass = p.positive("mass");
  scene.bodies.reserve(static_cast<std::size_t>(last - first + 1));
  scene.bodies.push_back(ground_body("ground", Vec3::Zero(), Vec3::UnitY()));
  const double pitch = 2 * h + gap;
  long index = 0;  // of the row's first box, counting row by row from the bottom
  for (long row = 0; row < base && index < last; index += base - row, ++row) {
    for (long i = std::max(first - index, 0L); i < base - row && index + i < last; ++i) {
      const double x = (static_cast<double>(i) + 0.5 * static_cast<double>(row)) * pitch;
      const double y = h + 2 * h * static_cast<double>(row);
      scene.bodies.push_back(box_body("box" + std::to_string(row) + "_" + std::to_string(i),
                                      Vec3::Constant(h),
                                      mass,
                                      Vec3(x, y, 0.0)));
    }
  }
  scene.parameters = p.in_force();
  return scene;
}

// Solver2D's card house (Catto, "Solver2D", 2024) in 3-D, in the x-y plane. A card is a box of
// half extents (t/2, L/2, w/2). A Λ centred at x = c on a floor at y0 is two cards turned by
// ∓theta about z, their inner top corners meeting at the apex (c, y0 + L cos theta) and each
// standing on its inner bottom corner; its feet span c ± (L sin theta + t cos theta) and its
// outer top corners sit at c ± t cos theta, t sin theta above the apex. Λs on a level are
// `pitch` = L + gap apart, so the flat cards (turned 90°), each lying across two neighbouring Λs
// on their outer top corners, are `gap` apart end to end; the next level's Λs stand on the flat
// cards, centred between the Λs below, one fewer a level. Everything starts exactly touching.
Scene build_card_house(const std::map<std::string, std::string>& values) {
  const ParameterValues p(*find_builtin_scene("card-house"), values);
  Scene scene;
  scene.name = "card-house";
  read_contact_world(p, scene);
  const long pairs = p.integer("pairs", 1, 1000);
  const double L = p.positive("height"), t = p.positive("thickness"), w = p.positive("width");
  const double mass = p.positive("mass");
  const double theta = p.number("angle_deg", 0.0, 60.0) * kPi / 180.0;
  const double gap = p.number("gap", 0.0, kInf);
  const double s = std::sin(theta), c = std::cos(theta);
  const double foot = L * s + t * c;  // half the Λ's span, m
  const double pitch = L + gap;
  if (!(gap < 2.0 * t * c))
    throw InputError(
        "card-house: gap " + number_text(gap) + " m: a flat card no longer reaches " +
        "the next Λ (the gap must be below 2 t cos(angle) = " + number_text(2.0 * t * c) + " m)");
  if (!(2.0 * foot < pitch))
    throw InputError(
        "card-house: neighbouring Λs' feet overlap (2 (L sin(angle) + t cos(angle)) "
        "= " +
        number_text(2.0 * foot) + " m against L + gap = " + number_text(pitch) +
        " m): a smaller angle, please");
  const Vec3 half(0.5 * t, 0.5 * L, 0.5 * w);
  scene.bodies.push_back(ground_body("ground", Vec3::Zero(), Vec3::UnitY()));
  const Quat flat = axis_angle_quaternion(Vec3(0.0, 0.0, 0.5 * kPi));
  double y0 = 0.0;
  for (long level = 0; level < pairs; ++level) {
    const long count = pairs - level;
    const double first = 0.5 * pitch * static_cast<double>(level);  // centre of the first Λ
    const double centre_y = y0 + 0.5 * t * s + 0.5 * L * c;
    for (long k = 0; k < count; ++k) {
      const double x = first + pitch * static_cast<double>(k);
      const std::string name = "card" + std::to_string(level) + "_" + std::to_string(k);
      const double dx = 0.5 * t * c + 0.5 * L * s;  // centre to apex, along x
      Body left = box_body(name + "l", half, mass, Vec3(x - dx, centre_y, 0.0));
      left.q = axis_angle_quaternion(Vec3(0.0, 0.0, -theta));
      Body right = box_body(name + "r", half, mass, Vec3(x + dx, centre_y, 0.0));
      right.q = axis_angle_quaternion(Vec3(0.0, 0.0, theta));
      scene.bodies.push_back(std::move(left));
      scene.bodies.push_back(std::move(right));
    }
    // The Λ's highest points: its outer top corners, t sin theta above the apex.
    const double top = y0 + L * c + t * s;
    for (long k = 0; k + 1 < count; ++k) {
      const double x = first + pitch * (static_cast<double>(k) + 0.5);
      Body card = box_body("flat" + std::to_string(level) + "_" + std::to_string(k),
                           half,
                           mass,
                           Vec3(x, top + 0.5 * t, 0.0));
      card.q = flat;
      scene.bodies.push_back(std::move(card));
    }
    y0 = top + t;
  }
  scene.parameters = p.in_force();
  return scene;
}

// Newton's cradle: n balls of radius r hanging from pivots 2r + gap apart by distance
// constraints of length L (5.2); the first is pulled back to theta0 and released. With
// restitution 1 and a gap (default 2 mm) the impacts come one after another and the momentum
// passes along the row: the last ball rises to about the first's release height h0. With gap 0
// every contact is in the one LCP of the first impact, whose least-impulse answer with
// restitution 1 moves balls 1..n-1 together: for n = 5, momentum and the restitution condition
// give them 2/5 of the speed (each rises (2/5)² h0 = 0.16 h0) and ball 0 rebounds at 3/5 (0.36
// h0), energy kept: simultaneous impact is not the cradle (docs/contacts.md).
Scene build_newtons_cradle(const std::map<std::string, std::string>& values) {
  const ParameterValues p(*find_builtin_scene("newtons-cradle"), values);
  Scene scene;
  scene.name = "newtons-cradle";
  read_contact_world(p, scene);
  const long n = p.integer("n", 2, 1000);
  const double r = p.positive("radius");
  const double L = p.positive("length");
  const double theta0 = p.number("theta0_deg", -89.0, 89.0) * kPi / 180.0;
  const double mass = p.positive("mass");
  const double gap = p.number("gap", 0.0, kInf);
  for (long k = 0; k < n; ++k) {
    const Vec3 pivot(static_cast<double>(k) * (2 * r + gap), L, 0.0);
    const double angle = k == 0 ? theta0 : 0.0;  // pulled back along −x
    const Vec3 x = pivot + L * Vec3(-std::sin(angle), -std::cos(angle), 0.0);
    scene.bodies.push_back(sphere_body("ball" + std::to_string(k), r, mass, x));
    DistanceConstraint string;
    string.name = "string" + std::to_string(k);
    string.a = -1;
    string.anchor_a = pivot;
    string.b = static_cast<int>(k);
    string.length = L;
    scene.distances.push_back(string);
  }
  scene.parameters = p.in_force();
  return scene;
}

// A box sliding on a plane with initial speed v0 along x: with friction mu (the paper's bound
// mu m |g·n| spread over its four contacts) it stops after v0² / (2 mu g), at t = v0 / (mu g).
Scene build_slide(const std::map<std::string, std::string>& values) {
  const ParameterValues p(*find_builtin_scene("slide"), values);
  Scene scene;
  scene.name = "slide";
  read_contact_world(p, scene);
  const double h = 0.5 * p.positive("size");
  scene.bodies.push_back(ground_body("ground", Vec3::Zero(), Vec3::UnitY()));
  Body b = box_body("box", Vec3::Constant(h), p.positive("mass"), Vec3(0.0, h, 0.0));
  b.set_velocity(Vec3(p.positive("v0"), 0.0, 0.0), Vec3::Zero());
  scene.bodies.push_back(b);
  scene.parameters = p.in_force();
  return scene;
}

// A ball dropped from `height` (lowest point above the plane) with restitution epsilon
// (8.2.1): it comes back at epsilon times its impact speed, so each rebound height is epsilon²
// times the previous one.
Scene build_bounce(const std::map<std::string, std::string>& values) {
  const ParameterValues p(*find_builtin_scene("bounce"), values);
  Scene scene;
  scene.name = "bounce";
  read_contact_world(p, scene);
  const double r = p.positive("radius");
  scene.bodies.push_back(ground_body("ground", Vec3::Zero(), Vec3::UnitY()));
  scene.bodies.push_back(
      sphere_body("ball", r, p.positive("mass"), Vec3(0.0, r + p.positive("height"), 0.0)));
  scene.parameters = p.in_force();
  return scene;
}

// The push-factor figure (8.1): n boxes stacked on a ground plane, each sunk `overlap` (a
// fraction of the edge) into the one below, the lowest into the ground. Original Baumgarte
// leaves the separating velocity in the bodies (they fly apart, kinetic energy appears);
// the improved technique separates them with the position system only.
Scene build_overlap(const std::map<std::string, std::string>& values) {
  const ParameterValues p(*find_builtin_scene("overlap"), values);
  Scene scene;
  scene.name = "overlap";
  read_contact_world(p, scene);
  const long n = p.integer("n", 1, 1000);
  const double h = 0.5 * p.positive("size");
  const double depth = p.number("overlap", 0.0, 0.9) * 2 * h;
  const double mass = p.positive("mass");
  scene.bodies.push_back(ground_body("ground", Vec3::Zero(), Vec3::UnitY()));
  for (long k = 0; k < n; ++k) {
    const double y = h - depth + static_cast<double>(k) * (2 * h - depth);
    scene.bodies.push_back(
        box_body("box" + std::to_string(k), Vec3::Constant(h), mass, Vec3(0, y, 0)));
  }
  scene.parameters = p.in_force();
  return scene;
}

}  // namespace cbps
