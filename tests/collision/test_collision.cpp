// Collision detection (4) and the contact manifold of the contact constraint (5.3). Every expected
// value is worked by hand from the geometry in the comment beside it.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "cbps/collision/collision.hpp"

using namespace cbps;

namespace {

constexpr double kTol = 1e-12;  // m: round-off of a few operations on unit-sized boxes
const double kSqrt2 = std::sqrt(2.0);
const double kSqrt3 = std::sqrt(3.0);

Body make_sphere(const Vec3& x, double radius, bool is_static = false) {
  Body body;
  body.shape.kind = Shape::Kind::Sphere;
  body.shape.radius = radius;
  body.x = x;
  body.is_static = is_static;
  return body;
}

Body make_box(const Vec3& x,
              const Vec3& half_extents,
              const Quat& q = Quat::Identity(),
              bool is_static = false) {
  Body body;
  body.shape.kind = Shape::Kind::Box;
  body.shape.half_extents = half_extents;
  body.x = x;
  body.q = q;
  body.is_static = is_static;
  return body;
}

Body make_plane(const Vec3& x, const Quat& q = Quat::Identity()) {
  Body body;
  body.shape.kind = Shape::Kind::Plane;
  body.x = x;
  body.q = q;
  body.is_static = true;
  return body;
}

const Vec3 kUnitHalf(0.5, 0.5, 0.5);

Quat turn(double angle, const Vec3& axis) {
  return Quat(Eigen::AngleAxisd(angle, axis.normalized()));
}

/// collide(a, b) with indices 0 and 1, which must report a contact.
Manifold hit(const Body& a, const Body& b, double margin = 0.0) {
  Manifold m;
  REQUIRE(collide(a, b, 0, 1, m, margin));
  CHECK(m.a == 0);
  CHECK(m.b == 1);
  CHECK(m.n.norm() == Approx(1.0).epsilon(1e-14));
  CHECK(!m.points.empty());
  CHECK(m.points.size() <= static_cast<std::size_t>(kMaxContactPoints));
  return m;
}

bool collides(const Body& a, const Body& b, double margin = 0.0) {
  Manifold m;
  return collide(a, b, 0, 1, m, margin);
}

/// The manifold's point at p (within tol), or nullptr.
const ContactPoint* find_point(const Manifold& m, const Vec3& p, double tol = kTol) {
  for (const ContactPoint& c : m.points)
    if ((c.p - p).norm() < tol) return &c;
  return nullptr;
}

/// Checks that m has exactly the expected points (in any order), each with depth d.
void check_points(const Manifold& m, const std::vector<Vec3>& expected, double d) {
  REQUIRE(m.points.size() == expected.size());
  for (const Vec3& p : expected) {
    INFO("expected point " << p.transpose());
    const ContactPoint* c = find_point(m, p);
    REQUIRE(c != nullptr);
    CHECK(c->depth == Approx(d).margin(kTol));
  }
}

double max_depth(const Manifold& m) {
  double d = -kInf;
  for (const ContactPoint& c : m.points) d = std::max(d, c.depth);
  return d;
}

std::set<std::uint32_t> features(const Manifold& m) {
  std::set<std::uint32_t> ids;
  for (const ContactPoint& c : m.points) ids.insert(c.feature);
  return ids;
}

/// Applies the rigid transform x → Q x + t to a body.
Body transformed(Body body, const Quat& Q, const Vec3& t) {
  body.x = Q * body.x + t;
  body.q = Q * body.q;
  return body;
}

/// A named pair of bodies in contact.
struct Case {
  std::string name;
  Body a;
  Body b;
};

/// One pair of every type and contact configuration, each overlapping by a known depth.
std::vector<Case> contact_cases() {
  const Quat tilt = turn(0.4, Vec3(1, 0, 1));
  const Quat corner_down = Quat::FromTwoVectors(Vec3(-1, -1, -1), Vec3(0, -1, 0));
  const Vec3 big(2.0, 0.5, 2.0);
  std::vector<Case> cases;
  cases.push_back(
      {"sphere-sphere", make_sphere(Vec3(1, 2, 3), 0.7), make_sphere(Vec3(1.6, 2, 3.8), 0.5)});
  cases.push_back({"plane-sphere",
                   make_plane(Vec3(1, -2, 0.5), tilt),
                   make_sphere(Vec3(1, -2, 0.5) + tilt * Vec3(3, 0.4, 1), 0.5)});
  cases.push_back({"sphere-plane",
                   make_sphere(Vec3(1, -2, 0.5) + tilt * Vec3(3, 0.4, 1), 0.5),
                   make_plane(Vec3(1, -2, 0.5), tilt)});
  cases.push_back({"box-sphere (edge region)",
                   make_box(Vec3::Zero(), kUnitHalf, turn(0.2, Vec3(0, 1, 0))),
                   make_sphere(turn(0.2, Vec3(0, 1, 0)) * Vec3(0.8, 0.8, 0), 0.5)});
  cases.push_back({"sphere-box (centre inside)",
                   make_sphere(Vec3(0.3, 0.4, -0.5), 0.2),
                   make_box(Vec3::Zero(), Vec3(1, 0.5, 2))});
  cases.push_back({"plane-box flat",
                   make_plane(Vec3(0.5, 1, -0.3), tilt),
                   make_box(Vec3(0.5, 1, -0.3) + tilt * Vec3(0.2, 0.5 - 1e-3, -0.1),
                            kUnitHalf,
                            tilt * turn(0.3, Vec3(0, 1, 0)))});
  cases.push_back({"box-plane on a vertex",
                   make_box(Vec3(0.5, 1, -0.3) + tilt * Vec3(0, kSqrt3 / 2 - 1e-3, 0),
                            kUnitHalf,
                            tilt * corner_down),
                   make_plane(Vec3(0.5, 1, -0.3), tilt)});
  cases.push_back({"box-box small on big",
                   make_box(Vec3::Zero(), big, Quat::Identity(), true),
                   make_box(Vec3(0.3, 0.99, -0.2), kUnitHalf)});
  cases.push_back({"box-box big on small",
                   make_box(Vec3::Zero(), kUnitHalf),
                   make_box(Vec3(0.1, 0.98, 0.1), big)});
  cases.push_back({"box-box turned 45 degrees (octagon)",
                   make_box(Vec3::Zero(), kUnitHalf),
                   make_box(Vec3(0, 0.99, 0), kUnitHalf, turn(kPi / 4, Vec3(0, 1, 0)))});
  cases.push_back(
      {"box-box on an edge",
       make_box(Vec3::Zero(), big),
       make_box(Vec3(0.2, 0.5 + kSqrt2 / 2 - 0.01, 0.1), kUnitHalf, turn(kPi / 4, Vec3(0, 0, 1)))});
  cases.push_back({"box-box vertex-face",
                   make_box(Vec3::Zero(), big),
                   make_box(Vec3(0.2, 0.5 + kSqrt3 / 2 - 0.01, 0.1), kUnitHalf, corner_down)});
  cases.push_back(
      {"box-box vertex-face, the face on b",
       make_box(Vec3::Zero(), kUnitHalf, Quat::FromTwoVectors(Vec3(1, 1, 1), Vec3(0, 1, 0))),
       make_box(Vec3(0.1, kSqrt3 / 2 + 0.5 - 0.01, -0.2), big)});
  cases.push_back(
      {"box-box edge-edge",
       make_box(Vec3::Zero(), kUnitHalf, turn(kPi / 4, Vec3(0, 0, 1))),
       make_box(Vec3(0.1, kSqrt2 - 0.01, -0.15), kUnitHalf, turn(kPi / 4, Vec3(1, 0, 0)))});
  return cases;
}

/// A deterministic uniform number in [lo, hi) from the (fully specified) mt19937 stream.
double uniform(std::mt19937& rng, double lo, double hi) {
  return lo + (hi - lo) * (static_cast<double>(rng()) / 4294967296.0);
}

/// All pairs i < j by their world AABBs, planes by their vertices or sphere bottoms: the broad
/// phase's definition, evaluated quadratically.
std::vector<std::pair<int, int>> brute_force_pairs(const std::vector<Body>& bodies, double margin) {
  std::vector<std::pair<int, int>> pairs;
  const int count = static_cast<int>(bodies.size());
  for (int i = 0; i < count; ++i) {
    for (int j = i + 1; j < count; ++j) {
      const Body& a = bodies[static_cast<std::size_t>(i)];
      const Body& b = bodies[static_cast<std::size_t>(j)];
      if (a.is_static && b.is_static) continue;
      const bool plane_a = a.shape.kind == Shape::Kind::Plane;
      const bool plane_b = b.shape.kind == Shape::Kind::Plane;
      if (plane_a && plane_b) continue;
      bool candidate = false;
      if (plane_a || plane_b) {
        const Body& plane = plane_a ? a : b;
        const Body& other = plane_a ? b : a;
        const Vec3 n = plane.q * Vec3::UnitY();
        double lowest = kInf;  // height of the lowest point above the plane
        if (other.shape.kind == Shape::Kind::Sphere) {
          lowest = n.dot(other.x - plane.x) - other.shape.radius;
        } else {
          const Vec3 h = other.shape.half_extents;
          for (int v = 0; v < 8; ++v) {
            const Vec3 local(
                (v & 1) ? h.x() : -h.x(), (v & 2) ? h.y() : -h.y(), (v & 4) ? h.z() : -h.z());
            lowest = std::min(lowest, n.dot(other.world_point(local) - plane.x));
          }
        }
        candidate = lowest <= margin;
      } else {
        candidate = aabbs_overlap(world_aabb(a), world_aabb(b), margin);
      }
      if (candidate) pairs.emplace_back(i, j);
    }
  }
  return pairs;
}

}  // namespace

TEST_CASE("collision: sphere–sphere: n from a to b, d = r_a + r_b − |x_b − x_a|, p midway (4, 5.3)",
          "[collision]") {
  // Centres 1 m apart along n = (0.6, 0, 0.8); radii 0.7 and 0.5: d = 0.2. Surface of a at 0.7
  // along n, surface of b at 1 − 0.5 = 0.5: p = x_a + 0.6 n.
  const Body a = make_sphere(Vec3(1, 2, 3), 0.7);
  const Body b = make_sphere(Vec3(1.6, 2, 3.8), 0.5);
  const Vec3 n(0.6, 0, 0.8);
  SECTION("overlapping") {
    const Manifold m = hit(a, b);
    CHECK((m.n - n).norm() < kTol);
    check_points(m, {a.x + 0.6 * n}, 0.2);
  }
  SECTION("the other order flips n, keeps p and d") {
    const Manifold m = hit(b, a);
    CHECK((m.n + n).norm() < kTol);
    check_points(m, {a.x + 0.6 * n}, 0.2);
  }
  SECTION("separated, touching, within a margin") {
    const Body apart = make_sphere(a.x + 1.3 * n, 0.5);  // gap 0.1
    CHECK_FALSE(collides(a, apart));
    const Manifold within = hit(a, apart, 0.15);
    check_points(within, {a.x + 0.75 * n}, -0.1);
    // Exactly touching (dyadic numbers): one point with d = 0 at the touching point.
    const Manifold touching = hit(make_sphere(Vec3(0, 0, 0), 1.0), make_sphere(Vec3(2, 0, 0), 1.0));
    check_points(touching, {Vec3(1, 0, 0)}, 0.0);
    CHECK(touching.points[0].depth == 0.0);
  }
}

TEST_CASE("collision: sphere–plane: n is the plane normal from the plane to the sphere (4, 5.3)",
          "[collision]") {
  // Plane turned 30° about z: n_p = (−sin 30°, cos 30°, 0). Sphere r = 0.5 with its centre 0.4
  // above the plane: d = 0.1, p midway between its lowest point (height −0.1) and the plane.
  const Quat q = turn(kPi / 6, Vec3(0, 0, 1));
  const Vec3 n_p(-0.5, kSqrt3 / 2, 0);
  const Body plane = make_plane(Vec3(1, -2, 0.5), q);
  const Vec3 foot = plane.x + q * Vec3(3, 0, -1);  // a point on the plane
  SECTION("plane as body a, sphere as body b") {
    const Manifold m = hit(plane, make_sphere(foot + 0.4 * n_p, 0.5));
    CHECK((m.n - n_p).norm() < kTol);
    check_points(m, {foot - 0.05 * n_p}, 0.1);
  }
  SECTION("sphere as body a, plane as body b: n points into the plane") {
    const Manifold m = hit(make_sphere(foot + 0.4 * n_p, 0.5), plane);
    CHECK((m.n + n_p).norm() < kTol);
    check_points(m, {foot - 0.05 * n_p}, 0.1);
  }
  SECTION("centre below the plane: d = r + depth of the centre") {
    const Manifold m = hit(plane, make_sphere(foot - 1.0 * n_p, 0.5));
    check_points(m, {foot - 0.75 * n_p}, 1.5);
  }
  SECTION("above the plane: only within a margin") {
    const Body sphere = make_sphere(foot + 0.6 * n_p, 0.5);
    CHECK_FALSE(collides(plane, sphere));
    check_points(hit(plane, sphere, 0.2), {foot + 0.05 * n_p}, -0.1);
  }
}

TEST_CASE("collision: box–plane: the box's vertices below the plane, n from plane to box (4)",
          "[collision]") {
  // A unit box aligned with a tilted plane (then spun about the plane normal), its bottom face
  // 1 mm below the plane: its 4 bottom corners (vertices 0, 1, 4, 5: bit 1 (+y) clear), d = 1e-3,
  // each p 0.5 mm below the plane.
  const Quat tilt = turn(0.4, Vec3(1, 0, 1));
  const Vec3 n_p = tilt * Vec3::UnitY();
  const Body plane = make_plane(Vec3(0.5, 1, -0.3), tilt);
  SECTION("lying flat: 4 points") {
    const Quat q = tilt * turn(0.3, Vec3(0, 1, 0));
    const Body box = make_box(plane.x + tilt * Vec3(0.2, 0.5 - 1e-3, -0.1), kUnitHalf, q);
    std::vector<Vec3> corners;
    for (int v : {0, 1, 4, 5}) {
      const Vec3 local(v & 1 ? 0.5 : -0.5, -0.5, v & 4 ? 0.5 : -0.5);
      corners.push_back(box.world_point(local) + 0.5e-3 * n_p);
    }
    const Manifold m = hit(plane, box);
    CHECK((m.n - n_p).norm() < kTol);
    check_points(m, corners, 1e-3);
    CHECK(features(m) == std::set<std::uint32_t>{0, 1, 4, 5});
    const Manifold reversed = hit(box, plane);  // box is body a: n points into the plane
    CHECK((reversed.n + n_p).norm() < kTol);
    check_points(reversed, corners, 1e-3);
  }
  SECTION("on an edge: 2 points") {
    // Turned 45° about z: vertices 0 (−,−,−) and 4 (−,−,+) lowest, √2/2 below the centre.
    const Body box = make_box(plane.x + tilt * Vec3(0.3, kSqrt2 / 2 - 1e-3, 0),
                              kUnitHalf,
                              tilt * turn(kPi / 4, Vec3(0, 0, 1)));
    const Manifold m = hit(plane, box);
    check_points(
        m,
        {plane.x + tilt * Vec3(0.3, -0.5e-3, -0.5), plane.x + tilt * Vec3(0.3, -0.5e-3, 0.5)},
        1e-3);
    CHECK(features(m) == std::set<std::uint32_t>{0, 4});
  }
  SECTION("on a vertex: 1 point") {
    // Vertex 0 turned straight down, √3/2 below the centre.
    const Body box = make_box(plane.x + tilt * Vec3(0, kSqrt3 / 2 - 1e-3, 0),
                              kUnitHalf,
                              tilt * Quat::FromTwoVectors(Vec3(-1, -1, -1), Vec3(0, -1, 0)));
    const Manifold m = hit(plane, box);
    check_points(m, {plane.x + tilt * Vec3(0, -0.5e-3, 0)}, 1e-3);
    CHECK(m.points[0].feature == 0u);
  }
  SECTION("sunk whole: the deepest vertex and 3 more") {
    const Body box = make_box(plane.x - 2.0 * n_p, kUnitHalf, turn(0.7, Vec3(1, 2, 3)));
    const Manifold m = hit(plane, box);
    CHECK(m.points.size() == 4);
    double deepest = 0.0;
    for (int v = 0; v < 8; ++v) {
      const Vec3 local(v & 1 ? 0.5 : -0.5, v & 2 ? 0.5 : -0.5, v & 4 ? 0.5 : -0.5);
      deepest = std::max(deepest, -n_p.dot(box.world_point(local) - plane.x));
    }
    CHECK(max_depth(m) == Approx(deepest).margin(kTol));
    CHECK(features(m).size() == 4);
  }
  SECTION("above the plane, and exactly touching") {
    CHECK_FALSE(collides(plane, make_box(plane.x + tilt * Vec3(0, 0.51, 0), kUnitHalf, tilt)));
    const Body ground = make_plane(Vec3::Zero());
    const Manifold m = hit(ground, make_box(Vec3(3, 0.5, -2), kUnitHalf));
    check_points(
        m, {Vec3(2.5, 0, -2.5), Vec3(3.5, 0, -2.5), Vec3(2.5, 0, -1.5), Vec3(3.5, 0, -1.5)}, 0.0);
  }
}

TEST_CASE("collision: box–box face contact: the incident face clipped by the reference face (4)",
          "[collision]") {
  const Vec3 big(2.0, 0.5, 2.0);
  SECTION("a unit box resting on a larger box: the 4 corners of its bottom face, equal depths") {
    // Top box's bottom face at y = 0.49, the big box's top at 0.5: d = 0.01, p at y = 0.495.
    const Manifold m = hit(make_box(Vec3::Zero(), big, Quat::Identity(), true),
                           make_box(Vec3(0.3, 0.99, -0.2), kUnitHalf));
    CHECK((m.n - Vec3::UnitY()).norm() < kTol);
    check_points(m,
                 {Vec3(-0.2, 0.495, -0.7),
                  Vec3(0.8, 0.495, -0.7),
                  Vec3(-0.2, 0.495, 0.3),
                  Vec3(0.8, 0.495, 0.3)},
                 0.01);
    CHECK(features(m).size() == 4);
  }
  SECTION("exactly touching gives d = 0; a gap only within a margin") {
    const Body base = make_box(Vec3::Zero(), big);
    const Manifold m = hit(base, make_box(Vec3(0.25, 1.0, -0.25), kUnitHalf));
    check_points(m,
                 {Vec3(-0.25, 0.5, -0.75),
                  Vec3(0.75, 0.5, -0.75),
                  Vec3(-0.25, 0.5, 0.25),
                  Vec3(0.75, 0.5, 0.25)},
                 0.0);
    for (const ContactPoint& c : m.points) CHECK(c.depth == 0.0);
    const Body above = make_box(Vec3(0.25, 1.0 + 1.0 / 1024, -0.25), kUnitHalf);
    CHECK_FALSE(collides(base, above));
    const Manifold within = hit(base, above, 0.01);
    CHECK(within.points.size() == 4);
    for (const ContactPoint& c : within.points) CHECK(c.depth == Approx(-1.0 / 1024).margin(kTol));
  }
  SECTION(
      "an equal box turned 45° about the vertical: 4 of the octagon's corners, inside both faces") {
    // The two unit squares overlap in a regular octagon of circumradius 0.5 / cos(22.5°).
    const Body a = make_box(Vec3::Zero(), kUnitHalf);
    const Body b = make_box(Vec3(0, 0.99, 0), kUnitHalf, turn(kPi / 4, Vec3(0, 1, 0)));
    const Manifold m = hit(a, b);
    CHECK((m.n - Vec3::UnitY()).norm() < kTol);
    REQUIRE(m.points.size() == 4);
    std::vector<double> angles;
    for (const ContactPoint& c : m.points) {
      CHECK(c.depth == Approx(0.01).margin(kTol));
      CHECK(c.p.y() == Approx(0.495).margin(kTol));
      const Vec3 in_b = b.q.conjugate() * (c.p - b.x);
      CHECK(std::abs(c.p.x()) <= 0.5 + kTol);  // inside a's top face
      CHECK(std::abs(c.p.z()) <= 0.5 + kTol);
      CHECK(std::abs(in_b.x()) <= 0.5 + kTol);  // inside b's bottom face
      CHECK(std::abs(in_b.z()) <= 0.5 + kTol);
      CHECK(std::hypot(c.p.x(), c.p.z()) == Approx(0.5 / std::cos(kPi / 8)).margin(kTol));
      angles.push_back(std::atan2(c.p.z(), c.p.x()));
    }
    // Well spread: the 4 points surround the centre (no angular gap of π or more).
    std::sort(angles.begin(), angles.end());
    double gap = angles.front() + 2 * kPi - angles.back();
    for (std::size_t k = 1; k < angles.size(); ++k) gap = std::max(gap, angles[k] - angles[k - 1]);
    CHECK(gap < kPi - 0.1);
    CHECK(features(m).size() == 4);
  }
  SECTION("small on big and big on small: the patch is the smaller face either way") {
    // Small unit box below, big box (half 2, 0.5, 2) above, 0.02 into it: the small box's top
    // face is the patch, p at y = 0.49.
    const Body small = make_box(Vec3::Zero(), kUnitHalf);
    const Body large = make_box(Vec3(0.1, 0.98, 0.1), big);
    const std::vector<Vec3> corners{
        Vec3(-0.5, 0.49, -0.5), Vec3(0.5, 0.49, -0.5), Vec3(-0.5, 0.49, 0.5), Vec3(0.5, 0.49, 0.5)};
    const Manifold m = hit(small, large);
    CHECK((m.n - Vec3::UnitY()).norm() < kTol);
    check_points(m, corners, 0.02);
    // Equal separations on both faces: the reference face is a's (bits 16..23 below 6).
    for (const ContactPoint& c : m.points) CHECK(((c.feature >> 16) & 0xffu) < 6u);
    const Manifold swapped = hit(large, small);
    CHECK((swapped.n + Vec3::UnitY()).norm() < kTol);
    check_points(swapped, corners, 0.02);
    for (const ContactPoint& c : swapped.points) CHECK(((c.feature >> 16) & 0xffu) < 6u);
  }
  SECTION("a box on an edge: 2 points at the ends of the edge") {
    // Turned 45° about z, its lowest edge √2/2 below its centre, 0.01 into the big box.
    const Manifold m = hit(
        make_box(Vec3::Zero(), big),
        make_box(Vec3(0.2, 0.5 + kSqrt2 / 2 - 0.01, 0.1), kUnitHalf, turn(kPi / 4, Vec3(0, 0, 1))));
    CHECK((m.n - Vec3::UnitY()).norm() < kTol);
    check_points(m, {Vec3(0.2, 0.495, -0.4), Vec3(0.2, 0.495, 0.6)}, 0.01);
  }
}

TEST_CASE("collision: box–box vertex–face: a box standing on a corner touches at that vertex (4)",
          "[collision]") {
  // Vertex 0 turned straight down, √3/2 below the centre, 0.01 into the big box's top (y = 0.5).
  const Manifold m = hit(make_box(Vec3::Zero(), Vec3(2, 0.5, 2)),
                         make_box(Vec3(0.2, 0.5 + kSqrt3 / 2 - 0.01, 0.1),
                                  kUnitHalf,
                                  Quat::FromTwoVectors(Vec3(-1, -1, -1), Vec3(0, -1, 0))));
  CHECK((m.n - Vec3::UnitY()).norm() < kTol);
  check_points(m, {Vec3(0.2, 0.495, 0.1)}, 0.01);
}

TEST_CASE("collision: box–box vertex–face with the face on body b: n still points from a to b (4)",
          "[collision]") {
  // a stands on vertex 7 (+,+,+) turned straight up, √3/2 above its centre; the big box b rests
  // on it 0.01 deep (its bottom at y = √3/2 − 0.01): the reference face is b's, p halfway.
  const Manifold m =
      hit(make_box(Vec3::Zero(), kUnitHalf, Quat::FromTwoVectors(Vec3(1, 1, 1), Vec3(0, 1, 0))),
          make_box(Vec3(0.1, kSqrt3 / 2 + 0.5 - 0.01, -0.2), Vec3(2, 0.5, 2)));
  CHECK((m.n - Vec3::UnitY()).norm() < kTol);
  check_points(m, {Vec3(0, kSqrt3 / 2 - 0.005, 0)}, 0.01);
  CHECK(((m.points[0].feature >> 16) & 0xffu) == 6u + 2u);  // b's face −y (2k + s = 2)
}

TEST_CASE("collision: box–box edge–edge: crossed edges touch at one point, n ∥ e_a × e_b (4)",
          "[collision]") {
  // a: unit box turned 45° about z, its top edge along z at x = 0, y = √2/2.
  // b: unit box turned 45° about x, its bottom edge along x at z = −0.15, y = √2/2 − 0.01.
  // Closest points (0, √2/2, −0.15) and (0, √2/2 − 0.01, −0.15): p halfway, d = 0.01, n = z × x.
  const Body a = make_box(Vec3::Zero(), kUnitHalf, turn(kPi / 4, Vec3(0, 0, 1)));
  const Body b = make_box(Vec3(0.1, kSqrt2 - 0.01, -0.15), kUnitHalf, turn(kPi / 4, Vec3(1, 0, 0)));
  const Manifold m = hit(a, b);
  const Vec3 e_a = a.q * Vec3::UnitZ();
  const Vec3 e_b = b.q * Vec3::UnitX();
  CHECK(std::abs(m.n.dot(e_a.cross(e_b).normalized())) == Approx(1.0).epsilon(1e-14));
  CHECK((m.n - Vec3::UnitY()).norm() < kTol);
  check_points(m, {Vec3(0, kSqrt2 / 2 - 0.005, -0.15)}, 0.01);
  CHECK((m.points[0].feature >> 24) == 2u);  // an edge–edge contact
  const Manifold reversed = hit(b, a);
  CHECK((reversed.n + Vec3::UnitY()).norm() < kTol);
  check_points(reversed, {Vec3(0, kSqrt2 / 2 - 0.005, -0.15)}, 0.01);
}

TEST_CASE("collision: sphere–box: closest point outside, least-penetration face inside (4)",
          "[collision]") {
  SECTION("centre inside the box leaves through the nearest face") {
    // Box half (1, 0.5, 2); centre (0.3, 0.4, −0.5) is 0.7, 0.1, 1.5 from the faces +x, +y, −z:
    // out through +y. d = r + 0.1 = 0.3; box surface y = 0.5, sphere bottom y = 0.2: p.y = 0.35.
    const Body box = make_box(Vec3::Zero(), Vec3(1, 0.5, 2));
    const Body sphere = make_sphere(Vec3(0.3, 0.4, -0.5), 0.2);
    const Manifold m = hit(box, sphere);
    CHECK((m.n - Vec3::UnitY()).norm() < kTol);
    check_points(m, {Vec3(0.3, 0.35, -0.5)}, 0.3);
    CHECK(m.points[0].feature == 27u + 3u);  // face 2k + s = 3 (+y)
    const Manifold reversed = hit(sphere, box);
    CHECK((reversed.n + Vec3::UnitY()).norm() < kTol);
  }
  SECTION("centre outside near an edge: n from the closest point to the centre") {
    // Box frame: centre (0.8, 0.8, 0), closest point (0.5, 0.5, 0), distance 0.3√2; r = 0.5.
    const Quat q = turn(0.2, Vec3(0, 1, 0));
    const Body box = make_box(Vec3(1, 1, 1), kUnitHalf, q);
    const Body sphere = make_sphere(Vec3(1, 1, 1) + q * Vec3(0.8, 0.8, 0), 0.5);
    const Manifold m = hit(box, sphere);
    const Vec3 n = q * Vec3(1, 1, 0).normalized();
    CHECK((m.n - n).norm() < kTol);
    const double d = 0.5 - 0.3 * kSqrt2;
    const Vec3 surface_box = Vec3(1, 1, 1) + q * Vec3(0.5, 0.5, 0);
    check_points(m, {surface_box + 0.5 * (0.3 * kSqrt2 - 0.5) * n}, d);
    CHECK(m.points[0].feature == 2u + 3u * 2u + 9u * 1u);  // above x, above y, within z
  }
  SECTION("far away: no contact") {
    CHECK_FALSE(collides(make_box(Vec3::Zero(), kUnitHalf), make_sphere(Vec3(1.2, 0, 0), 0.5)));
  }
}

TEST_CASE("collision: moving b along +n by the depth separates every pair type (5.3)",
          "[collision]") {
  for (const Case& c : contact_cases()) {
    INFO(c.name);
    const Manifold m = hit(c.a, c.b);
    const double d = max_depth(m);
    Body b = c.b;
    if (b.is_static || b.shape.kind == Shape::Kind::Plane) continue;  // moving the plane is moot
    b.x = c.b.x + (d + 1e-9) * m.n;
    CHECK_FALSE(collides(c.a, b));
    b.x = c.b.x + (d - 1e-6) * m.n;  // d is the penetration along n: a little less still touches
    CHECK(collides(c.a, b));
  }
  // The pairs whose b is a plane: move a the other way.
  for (const Case& c : contact_cases()) {
    if (c.b.shape.kind != Shape::Kind::Plane) continue;
    INFO(c.name);
    const Manifold m = hit(c.a, c.b);
    Body a = c.a;
    a.x = c.a.x - (max_depth(m) + 1e-9) * m.n;
    CHECK_FALSE(collides(a, c.b));
  }
}

TEST_CASE("collision: the manifold moves with a rigid motion of both bodies (4)", "[collision]") {
  const Quat Q = turn(2.1, Vec3(0.3, -1.0, 0.7));
  const Vec3 t(4.0, -1.5, 2.5);
  for (const Case& c : contact_cases()) {
    INFO(c.name);
    const Manifold m = hit(c.a, c.b);
    const Manifold moved = hit(transformed(c.a, Q, t), transformed(c.b, Q, t));
    CHECK((moved.n - Q * m.n).norm() < kTol);
    REQUIRE(moved.points.size() == m.points.size());
    for (std::size_t k = 0; k < m.points.size(); ++k) {
      CHECK((moved.points[k].p - (Q * m.points[k].p + t)).norm() < 1e-11);
      CHECK(moved.points[k].depth == Approx(m.points[k].depth).margin(kTol));
      CHECK(moved.points[k].feature == m.points[k].feature);
    }
  }
}

TEST_CASE("collision: feature ids are distinct within a manifold and kept under a 1e-6 m move",
          "[collision]") {
  for (const Case& c : contact_cases()) {
    INFO(c.name);
    const Manifold m = hit(c.a, c.b);
    CHECK(features(m).size() == m.points.size());
    Body b = c.b;
    b.x += Vec3(1e-6, -1e-6, 0.7e-6);
    const Manifold moved = hit(c.a, b);
    REQUIRE(moved.points.size() == m.points.size());
    for (std::size_t k = 0; k < m.points.size(); ++k)
      CHECK(moved.points[k].feature == m.points[k].feature);
  }
  SECTION(
      "equal boxes stacked exactly: corners on the side planes keep their ids under round-off") {
    const Body a = make_box(Vec3::Zero(), kUnitHalf);
    const Manifold m = hit(a, make_box(Vec3(0, 1, 0), kUnitHalf));
    check_points(
        m,
        {Vec3(-0.5, 0.5, -0.5), Vec3(0.5, 0.5, -0.5), Vec3(-0.5, 0.5, 0.5), Vec3(0.5, 0.5, 0.5)},
        0.0);
    CHECK(features(m).size() == 4);
    for (const Vec3& shift : {Vec3(1e-9, 0, 0), Vec3(-1e-9, 0, 3e-10), Vec3(0, -1e-9, 1e-9)}) {
      const Manifold moved = hit(a, make_box(Vec3(0, 1, 0) + shift, kUnitHalf));
      CHECK(features(moved) == features(m));
    }
  }
}

TEST_CASE("collision: two static bodies and two planes never collide", "[collision]") {
  CHECK_FALSE(collides(make_box(Vec3::Zero(), kUnitHalf, Quat::Identity(), true),
                       make_sphere(Vec3::Zero(), 1.0, true)));
  CHECK_FALSE(collides(make_plane(Vec3::Zero()), make_plane(Vec3(0, -1, 0))));
  CHECK_FALSE(collides(make_plane(Vec3::Zero()),
                       make_box(Vec3::Zero(), kUnitHalf, Quat::Identity(), true)));
}

TEST_CASE("collision: world AABBs of a sphere, a turned box and a plane", "[collision]") {
  const Aabb sphere = world_aabb(make_sphere(Vec3(1, 2, 3), 0.5));
  CHECK((sphere.min - Vec3(0.5, 1.5, 2.5)).norm() < kTol);
  CHECK((sphere.max - Vec3(1.5, 2.5, 3.5)).norm() < kTol);
  // Half extents (0.5, 0.5, 0.25) turned 45° about z: half widths (√2/2, √2/2, 0.25).
  const Aabb box =
      world_aabb(make_box(Vec3(1, 0, 0), Vec3(0.5, 0.5, 0.25), turn(kPi / 4, Vec3(0, 0, 1))));
  CHECK((box.min - Vec3(1 - kSqrt2 / 2, -kSqrt2 / 2, -0.25)).norm() < kTol);
  CHECK((box.max - Vec3(1 + kSqrt2 / 2, kSqrt2 / 2, 0.25)).norm() < kTol);
  const Aabb plane = world_aabb(make_plane(Vec3::Zero()));
  CHECK(plane.min.x() == -kInf);
  CHECK(plane.max.y() == kInf);
  // Touching boxes overlap; a gap counts only within the margin.
  CHECK(aabbs_overlap({Vec3::Zero(), Vec3::Ones()}, {Vec3(1, 0, 0), Vec3(2, 1, 1)}));
  CHECK_FALSE(aabbs_overlap({Vec3::Zero(), Vec3::Ones()}, {Vec3(1.25, 0, 0), Vec3(2, 1, 1)}));
  CHECK(aabbs_overlap({Vec3::Zero(), Vec3::Ones()}, {Vec3(1.25, 0, 0), Vec3(2, 1, 1)}, 0.25));
}

TEST_CASE("collision: broad phase equals the all-pairs test on random scenes (4)", "[collision]") {
  std::mt19937 rng(20150707);
  for (int scene = 0; scene < 5; ++scene) {
    std::vector<Body> bodies;
    bodies.push_back(make_plane(Vec3(0, -4, 0)));
    for (int i = 0; i < 300; ++i) {
      const Vec3 x(uniform(rng, -5, 5), uniform(rng, -5, 5), uniform(rng, -5, 5));
      const bool is_static = uniform(rng, 0, 1) < 0.2;
      if (uniform(rng, 0, 1) < 0.5) {
        bodies.push_back(make_sphere(x, uniform(rng, 0.05, 0.6), is_static));
      } else {
        const Vec3 h(uniform(rng, 0.05, 0.8), uniform(rng, 0.05, 0.8), uniform(rng, 0.05, 0.8));
        const Vec3 axis(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
        bodies.push_back(make_box(x, h, turn(uniform(rng, 0, kPi), axis), is_static));
      }
      if (i == 150) bodies.push_back(make_plane(Vec3(0, 0, 3), turn(1.0, Vec3(1, 0.2, 0))));
    }
    for (const double margin : {0.0, 0.05}) {
      INFO("scene " << scene << ", margin " << margin);
      const auto pairs = broad_phase(bodies, margin);
      const auto expected = brute_force_pairs(bodies, margin);
      CHECK(pairs == expected);
      CHECK(expected.size() > 100);  // the scenes are crowded enough to test something
    }
  }
}

TEST_CASE("collision: broad phase on 1000 boxes in 100 resting columns equals the all-pairs test",
          "[collision]") {
  // 10 × 10 columns 2 m apart, each of 10 unit boxes exactly touching, on a ground plane: 9 pairs
  // per column plus one floor pair per column, 1000 pairs, all touching with d = 0.
  std::vector<Body> bodies;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      for (int k = 0; k < 10; ++k)
        bodies.push_back(make_box(Vec3(2.0 * i, 0.5 + k, 2.0 * j), kUnitHalf));
  bodies.push_back(make_plane(Vec3::Zero()));
  const auto pairs = broad_phase(bodies);
  CHECK(pairs == brute_force_pairs(bodies, 0.0));
  CHECK(pairs.size() == 1000);
  CHECK(broad_phase(bodies, 0.01) == brute_force_pairs(bodies, 0.01));

  const std::vector<Manifold> contacts = detect_contacts(bodies);
  REQUIRE(contacts.size() == 1000);
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    const Manifold& manifold = contacts[k];
    CHECK(manifold.a < manifold.b);
    if (k > 0)
      CHECK(std::pair{contacts[k - 1].a, contacts[k - 1].b} < std::pair{manifold.a, manifold.b});
    // Box on box (b above a) or box on the plane (the plane, index 1000, is b: n points down).
    const Vec3 up = manifold.b == 1000 ? Vec3(0, -1, 0) : Vec3(0, 1, 0);
    CHECK((manifold.n - up).norm() < kTol);
    CHECK(manifold.points.size() == 4);
    for (const ContactPoint& c : manifold.points) CHECK(c.depth == 0.0);
  }
}

TEST_CASE("collision: broad phase on a solid block of touching boxes equals the all-pairs test",
          "[collision]") {
  // Every box's AABB touches its 26 neighbours: 3 · 9·10·10 face neighbours, 6 · 9·9·10 edge
  // neighbours, 4 · 9·9·9 corner neighbours = 2700 + 4860 + 2916 = 10476 pairs.
  std::vector<Body> block;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      for (int k = 0; k < 10; ++k) block.push_back(make_box(Vec3(i, 0.5 + k, j), kUnitHalf));
  const auto block_pairs = broad_phase(block);
  CHECK(block_pairs.size() == 10476);
  CHECK(block_pairs == brute_force_pairs(block, 0.0));
}

TEST_CASE("collision: random box pairs: p lies in the overlap, depths ≥ 0, no missed overlap (4)",
          "[collision]") {
  // Boxes of random sizes and orientations near contact. Each p is halfway along n between a
  // point of one box's surface and a point of the other's, d apart: so p is within d/2 of each
  // box, and an edge–edge point (midway between two edge points, each inside the other box) is
  // inside both. Where no contact is reported, no vertex of either box is inside the other (a
  // necessary condition of separation).
  auto outside = [](const Body& box, const Vec3& p) {  // distance from p to the box, m
    const Vec3 local = box.q.conjugate() * (p - box.x);
    return (local.cwiseAbs() - box.shape.half_extents).cwiseMax(0.0).norm();
  };
  auto vertex = [](const Body& box, int v) {
    const Vec3 h = box.shape.half_extents;
    return box.world_point(
        Vec3((v & 1) ? h.x() : -h.x(), (v & 2) ? h.y() : -h.y(), (v & 4) ? h.z() : -h.z()));
  };
  auto strictly_inside = [](const Body& box, const Vec3& p) {
    const Vec3 local = box.q.conjugate() * (p - box.x);
    return (local.cwiseAbs() - box.shape.half_extents).maxCoeff() < -1e-12;
  };
  std::mt19937 rng(42);
  auto random_box = [&](const Vec3& x) {
    const Vec3 h(uniform(rng, 0.1, 1.0), uniform(rng, 0.1, 1.0), uniform(rng, 0.1, 1.0));
    const Vec3 axis(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
    return make_box(x, h, turn(uniform(rng, 0, kPi), axis));
  };
  int face = 0, edge = 0;
  for (int k = 0; k < 20000; ++k) {
    const Body a = random_box(Vec3::Zero());
    const Body b =
        random_box(Vec3(uniform(rng, -1.5, 1.5), uniform(rng, -1.5, 1.5), uniform(rng, -1.5, 1.5)));
    Manifold m;
    if (collide(a, b, 0, 1, m)) {
      CHECK(m.n.norm() == Approx(1.0).epsilon(1e-14));
      CHECK(features(m).size() == m.points.size());
      const bool is_edge = m.points[0].feature >> 24 == 2u;
      (is_edge ? edge : face) += 1;
      for (const ContactPoint& c : m.points) {
        CHECK(c.depth >= 0.0);
        CHECK(outside(a, c.p) <= 0.5 * c.depth + 1e-12);
        CHECK(outside(b, c.p) <= 0.5 * c.depth + 1e-12);
        if (is_edge && c.depth < 0.05) CHECK(outside(a, c.p) + outside(b, c.p) == 0.0);
      }
    } else {
      for (int v = 0; v < 8; ++v) {
        CHECK_FALSE(strictly_inside(a, vertex(b, v)));
        CHECK_FALSE(strictly_inside(b, vertex(a, v)));
      }
    }
  }
  INFO("face contacts " << face << ", edge contacts " << edge);
  CHECK(face > 1000);
  CHECK(edge > 100);
}

TEST_CASE("collision: jittered resting columns give 4-point face contacts within a margin (4)",
          "[collision]") {
  // Unit boxes in columns, each turned by up to 1e-4 rad and shifted by up to 1e-5 m from exact
  // stacking: every corner lies within 1e-4 m of the box below, so a margin of 1e-3 m keeps all
  // four corners of every face contact; no edge axis may win (face axes are preferred).
  std::mt19937 rng(7);
  std::vector<Body> bodies;
  bodies.push_back(make_plane(Vec3::Zero()));
  for (int i = 0; i < 5; ++i) {
    for (int k = 0; k < 10; ++k) {
      const Vec3 jitter(
          uniform(rng, -1e-5, 1e-5), uniform(rng, -1e-5, 1e-5), uniform(rng, -1e-5, 1e-5));
      const Vec3 axis(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
      bodies.push_back(make_box(
          Vec3(2.0 * i, 0.5 + k, 0) + jitter, kUnitHalf, turn(uniform(rng, 0, 1e-4), axis)));
    }
  }
  const std::vector<Manifold> contacts = detect_contacts(bodies, 1e-3);
  REQUIRE(contacts.size() == 50);
  for (const Manifold& manifold : contacts) {
    INFO("pair " << manifold.a << ", " << manifold.b);
    CHECK(manifold.n.dot(Vec3::UnitY()) > 1.0 - 1e-7);
    REQUIRE(manifold.points.size() == 4);
    for (const ContactPoint& c : manifold.points) {
      CHECK(std::abs(c.depth) < 2e-4);
      if (manifold.a != 0) CHECK((c.feature >> 24) == 1u);  // a face contact (box on box)
    }
  }
}
