// Built-in scenes: the pendulum-wave length rule, the chain, the v-corner's starting contacts, the
// pyramid's parts, and parameter errors.
#include <Eigen/Eigenvalues>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "cbps/base/error.hpp"
#include "cbps/base/numbers.hpp"
#include "cbps/collision/collision.hpp"
#include "cbps/scene/builtin.hpp"
#include "cbps/step/simulation.hpp"

using namespace cbps;

TEST_CASE("elliptic_K by the AGM matches tabulated values", "[scenes]") {
  CHECK(elliptic_K(0.0) == Approx(kPi / 2).epsilon(1e-15));
  // K(1/√2) = Γ(1/4)² / (4 √π) = 1.8540746773013719 (Abramowitz & Stegun 17.3).
  CHECK(elliptic_K(std::sqrt(0.5)) == Approx(1.8540746773013719).epsilon(1e-15));
  // K(sin 15°): A&S table 17.1, modular angle 15°: 1.5981420021.
  CHECK(elliptic_K(std::sin(15.0 * kPi / 180)) == Approx(1.5981420021).epsilon(1e-10));
}

TEST_CASE("pendulum-wave lengths give ball k exactly n0+k swings per cycle (10)", "[scenes]") {
  const Scene s = make_builtin_scene(
      "pendulum-wave", {{"n", "5"}, {"n0", "10"}, {"cycle", "30"}, {"attach", "center"}});
  REQUIRE(s.bodies.size() == 5);
  REQUIRE(s.distances.size() == 5);
  const double theta0 = 15.0 * kPi / 180.0;
  for (int k = 0; k < 5; ++k) {
    const DistanceConstraint& dc = s.distances[static_cast<std::size_t>(k)];
    const double T = pendulum_period(dc.length, 9.81, theta0);
    CHECK(T * (10 + k) == Approx(30.0).epsilon(1e-14));
    CHECK(dc.a == -1);
    CHECK(dc.b == k);
    // Released at theta0 from the vertical below the pivot, at rest, with the string taut.
    const Vec3 d = s.bodies[static_cast<std::size_t>(k)].x - dc.anchor_a;
    CHECK(std::atan2(d.x(), -d.y()) == Approx(theta0).epsilon(1e-14));
    CHECK(distance_violation(dc, s.bodies) == Approx(0.0).margin(1e-15));
  }
}

TEST_CASE("pendulum-wave attach=top: the string's slow mode has the designed period (10)",
          "[scenes]") {
  const double r = 0.03;
  const double m = 0.1;
  const double g = 9.81;
  const Scene s = make_builtin_scene("pendulum-wave", {{"n", "3"}, {"radius", "0.03"}});
  const double K = elliptic_K(std::sin(15.0 * kPi / 360.0));
  for (std::size_t k = 0; k < 3; ++k) {
    const DistanceConstraint& dc = s.distances[k];
    const Body& ball = s.bodies[k];
    // The string is taut and ends at the ball's top point.
    CHECK(distance_violation(dc, s.bodies) == Approx(0.0).margin(1e-15));
    CHECK((ball.world_point(dc.anchor_b) - ball.x).norm() == Approx(r).epsilon(1e-14));
    // Independent check: the generalized eigenproblem K u = ω² M u of the linearised string +
    // ball (angles φ, ψ; I = 2/5 m r²), solved numerically; its slow mode must have
    // ω² = g / L_k, L_k = g (T_k / 4K)², T_k = cycle / (n0 + k).
    const double l = dc.length;
    Eigen::Matrix2d M;
    M << m * l * l, m * l * r, m * l * r, m * r * r + 0.4 * m * r * r;
    Eigen::Matrix2d Kmat;
    Kmat << m * g * l, 0.0, 0.0, m * g * r;
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix2d> eig(Kmat, M);
    const double T_k = 60.0 / (51.0 + static_cast<double>(k));
    const double L_k = g * std::pow(T_k / (4.0 * K), 2);
    CHECK(eig.eigenvalues()(0) == Approx(g / L_k).epsilon(1e-12));
    // Released in the slow mode's shape: ψ0/φ0 equals the eigenvector's ratio.
    const Vec3 string_dir = ball.world_point(dc.anchor_b) - dc.anchor_a;
    const double phi0 = std::atan2(string_dir.x(), -string_dir.y());
    const double psi0 = Eigen::AngleAxisd(ball.q).angle();
    const Eigen::Vector2d u = eig.eigenvectors().col(0);
    CHECK(psi0 / phi0 == Approx(u(1) / u(0)).epsilon(1e-12));
  }
  CHECK(s.duration == 60.0);
}

TEST_CASE("chain: n links, heavy last link, released horizontally", "[scenes]") {
  const Scene s =
      make_builtin_scene("chain", {{"n", "4"}, {"mass_ratio", "100"}, {"link_mass", "0.2"}});
  REQUIRE(s.bodies.size() == 4);
  CHECK(s.bodies[3].m == Approx(20.0));
  CHECK(s.bodies[0].m == Approx(0.2));
  for (const Body& b : s.bodies) CHECK(b.x.y() == 0.0);
  for (const DistanceConstraint& dc : s.distances) {
    CHECK(distance_violation(dc, s.bodies) == Approx(0.0).margin(1e-15));
  }
  CHECK(s.distances[0].a == -1);
}

TEST_CASE("unknown scenes, unknown parameters and bad values are input errors", "[scenes]") {
  CHECK_THROWS_WITH(make_builtin_scene("pendulum-wav", {}), Catch::Contains("pendulum-wave"));
  CHECK_THROWS_WITH(make_builtin_scene("chain", {{"links", "3"}}),
                    Catch::Contains("unknown parameter 'links'") && Catch::Contains("valid: n"));
  CHECK_THROWS_AS(make_builtin_scene("chain", {{"n", "0"}}), InputError);
  CHECK_THROWS_AS(make_builtin_scene("chain", {{"n", "2.5"}}), InputError);
  CHECK_THROWS_AS(make_builtin_scene("chain", {{"link_mass", "-1"}}), InputError);
  CHECK_THROWS_AS(make_builtin_scene("chain", {{"dt", "0"}}), InputError);
  CHECK_THROWS_AS(make_builtin_scene("chain", {{"dt", "nan"}}), InputError);
  CHECK_THROWS_AS(make_builtin_scene("chain", {{"dt", "inf"}}), InputError);
  CHECK_THROWS_AS(make_builtin_scene("chain", {{"dt", "1/0"}}), InputError);
  CHECK_THROWS_WITH(make_builtin_scene("pendulum-wave", {{"attach", "side"}}),
                    Catch::Contains("top|center"));
  double dt = 0.0;
  CHECK(parse_number("1/240", dt));
  CHECK(dt == 1.0 / 240.0);
}

TEST_CASE("a simple pendulum keeps its length and energy over one period (5.2, 3.2)",
          "[scenes][simulation]") {
  Simulation sim(make_builtin_scene("pendulum-wave", {{"n", "1"}, {"attach", "center"}}));
  const double e0 = sim.energy();
  const long steps = std::lround(sim.scene().duration / 51.0 / sim.scene().world.dt);
  double worst = 0.0;
  for (long s = 0; s < steps; ++s) worst = std::max(worst, sim.step().max_constraint_error);
  INFO("max |c| " << worst << " m, energy " << e0 << " -> " << sim.energy() << " J");
  CHECK(worst < 1e-4);
  CHECK(std::abs(sim.energy() - e0) < 0.02 * std::abs(e0));
}

TEST_CASE("v-corner: the ball starts touching both planes for any pair of angles (12.2, 4)",
          "[contact][eq12.2][eq4]") {
  // The scene solves a·c = r and b·c = r for the centre, so both depths are 0 up to rounding
  // (about ±1e-17 m). The scene's contact margin (1 mm) keeps a depth of −1e-17 m a contact; at
  // margin 0 it is none (41 of these 64 pairs then start with one contact and the ball falls
  // for a step), so the margin is read from the scene and must be positive.
  int missing = 0;
  int pairs = 0;
  for (int left = 10; left <= 80; left += 10) {
    for (int right = 10; right <= 80; right += 10) {
      const Scene scene = make_builtin_scene(
          "v-corner",
          {{"angle_left_deg", std::to_string(left)}, {"angle_right_deg", std::to_string(right)}});
      REQUIRE(scene.world.contact_margin > 0.0);
      ++pairs;
      const std::vector<Manifold> contacts =
          detect_contacts(scene.bodies, scene.world.contact_margin);
      bool touching = contacts.size() == 2;
      for (const Manifold& manifold : contacts) {
        touching =
            touching && manifold.points.size() == 1 && std::abs(manifold.points[0].depth) < 1e-12;
      }
      if (!touching) ++missing;
    }
  }
  INFO(missing << " of " << pairs << " angle pairs do not start with two contacts of depth 0");
  CHECK(missing == 0);
}

TEST_CASE("pyramid: any run of its boxes is built as the whole scene builds them", "[scenes]") {
  // The distributed generator (distributed/generate.hpp) builds a rank's boxes and its halo by
  // build_pyramid_range; the serial scene is the run of every box. Base 5: 15 boxes, rows of
  // 5, 4, 3, 2, 1 from the bottom.
  const std::map<std::string, std::string> values{{"base", "5"}, {"gap", "0.2"}};
  CHECK(pyramid_base(values) == 5);
  const Scene whole = make_builtin_scene("pyramid", values);
  REQUIRE(whole.bodies.size() == 16);  // the ground and 15 boxes
  for (const auto& [first, last] : std::vector<std::pair<long, long>>{
           {0, 15}, {0, 5}, {3, 9}, {5, 6}, {7, 15}, {14, 15}, {4, 4}}) {
    const Scene part = build_pyramid_range(values, first, last);
    REQUIRE(part.bodies.size() == std::size_t(1 + last - first));
    CHECK(part.bodies[0].name == "ground");
    CHECK(part.bodies[0].is_static);
    for (long k = first; k < last; ++k) {
      const Body& mine = part.bodies[std::size_t(1 + k - first)];
      const Body& theirs = whole.bodies[std::size_t(1 + k)];
      CHECK(mine.name == theirs.name);
      CHECK(mine.x == theirs.x);
      CHECK(mine.m == theirs.m);
    }
    CHECK(part.world.dt == whole.world.dt);
    CHECK(part.world.mu == whole.world.mu);
  }
  // Box 5 is the first of the second row: centred half a pitch (1 m + gap 0.2 m) in, one box up.
  const Scene second_row = build_pyramid_range(values, 5, 6);
  const Body& first_of_row_1 = second_row.bodies[1];
  CHECK(first_of_row_1.name == "box1_0");
  CHECK(first_of_row_1.x.x() == Approx(0.6).epsilon(1e-15));
  CHECK(first_of_row_1.x.y() == Approx(1.5).epsilon(1e-15));
  CHECK_THROWS_AS(build_pyramid_range(values, 3, 16), InputError);
  CHECK_THROWS_AS(build_pyramid_range(values, -1, 2), InputError);
  CHECK_THROWS_AS(build_pyramid_range(values, 4, 3), InputError);
  CHECK_THROWS_AS(pyramid_base({{"base", "0"}}), InputError);
}

TEST_CASE("card-house: every card starts touching what holds it, nothing overlaps (4)",
          "[scenes][contact][eq4]") {
  // Levels of 3, 2, 1 Λs and 2, 1 flat cards: 15 cards. Each leaning card touches the floor (or
  // the flat card below) and its partner at the apex; each flat card rests on two apexes. All
  // depths are 0 up to rounding; the leaning pairs meet edge to edge.
  const Scene scene = make_builtin_scene("card-house", {});
  REQUIRE(scene.bodies.size() == 16);
  const std::vector<Manifold> contacts = detect_contacts(scene.bodies, 1e-9);
  double deepest = 0.0;
  std::vector<int> touching(scene.bodies.size(), 0);
  for (const Manifold& manifold : contacts) {
    ++touching[static_cast<std::size_t>(manifold.a)];
    ++touching[static_cast<std::size_t>(manifold.b)];
    for (const ContactPoint& point : manifold.points)
      deepest = std::max(deepest, std::abs(point.depth));
  }
  CHECK(deepest < 1e-12);
  for (std::size_t k = 1; k < scene.bodies.size(); ++k) {
    CAPTURE(scene.bodies[k].name);
    CHECK(touching[k] >= 2);  // a leaning card: its support and its partner; a flat one: 2 apexes
  }
  // A flat card that cannot reach across two Λs, and Λs whose feet overlap, are refused.
  CHECK_THROWS_AS(make_builtin_scene("card-house", {{"gap", "0.05"}}), InputError);
  CHECK_THROWS_AS(make_builtin_scene("card-house", {{"angle_deg", "40"}}), InputError);
}
