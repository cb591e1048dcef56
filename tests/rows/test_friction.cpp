// Friction rows (5.4): the paper's bounds ±mu m |g·n| over the points of a pair, the sliding box
// they stop, and the tangent basis. Every expected value is worked out in the comment beside it.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "cbps/body/body.hpp"
#include "cbps/collision/collision.hpp"
#include "cbps/rows/friction.hpp"
#include "cbps/rows/row.hpp"
#include "cbps/step/simulation.hpp"
#include "cbps/system/system.hpp"
#include "fixture.hpp"

using namespace cbps;
using test::contact_scene;
using test::kG;

// ---------------------------------------------------------------------------------------------
// 5.4: the paper's friction bound ±mu m |g·n|, m the pair's movable mass over its points.

TEST_CASE("paper friction rows are bounded by mu m |g.n| / points of the pair (5.4)",
          "[contact][eq5.4]") {
  SECTION("box on the ground and box on box: 4 points each") {
    // A 1 kg box on the ground and a 3 kg box on it, both lying flat: 4 points per pair.
    Scene scene = contact_scene("stack", {{"n", "2"}, {"mu", "0.5"}});
    REQUIRE(scene.bodies.size() == 3);
    set_mass(scene.bodies[2], 3.0);
    Simulation sim(scene);
    std::vector<Row> rows;
    std::vector<Manifold> manifolds;
    sim.build_rows(rows, manifolds);
    REQUIRE(manifolds.size() == 2);
    for (const Manifold& manifold : manifolds) CHECK(manifold.points.size() == 4);
    REQUIRE(rows.size() == 2 * 4 * 3);  // each point: a contact row and two friction rows
    // ground–box: only the box moves, 0.5 · 1 kg · 9.81 m/s² / 4; box–box: (1 + 3) kg.
    const double ground_bound = 0.5 * 1.0 * kG / 4.0;
    const double box_bound = 0.5 * (1.0 + 3.0) * kG / 4.0;
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const Row& row = rows[k];
      CAPTURE(k, row.label);
      if (k % 3 == 0) {  // the contact row (5.3): push only
        CHECK(row.cmin == 0.0);
        CHECK(row.cmax == kInf);
        continue;
      }
      const double expected = row.body_a == -1 ? ground_bound : box_bound;
      CHECK(row.body_b == (row.body_a == -1 ? 1 : 2));
      CHECK(row.cmax == Approx(expected).epsilon(1e-14));
      CHECK(row.cmin == -row.cmax);
      CHECK(row.upsilon == 0.0);
    }
  }

  SECTION("v-corner: one point per plane, |g.n| = g cos(phi)") {
    // Tilted planes: |g·n| = g cos φ, so the bounds are mu m g cos φ_l and mu m g cos φ_r.
    Simulation sim(contact_scene("v-corner", {{"mu", "0.5"}}));
    const std::vector<Row> rows = sim.build_rows();
    REQUIRE(rows.size() == 6);
    CHECK(rows[1].cmax == Approx(0.5 * kG * std::cos(kPi / 4.0)).epsilon(1e-14));  // 45°
    CHECK(rows[2].cmax == Approx(0.5 * kG * std::cos(kPi / 4.0)).epsilon(1e-14));
    CHECK(rows[4].cmax == Approx(0.5 * kG * std::cos(kPi / 6.0)).epsilon(1e-14));  // 30°
    CHECK(rows[5].cmax == Approx(0.5 * kG * std::cos(kPi / 6.0)).epsilon(1e-14));
  }

  SECTION("mu = 0: no friction rows, one row per contact point") {
    Simulation sim(contact_scene("stack", {{"n", "2"}, {"mu", "0"}}));
    const System& sys = sim.assemble();
    CHECK(sys.rows() == 8);  // 2 pairs × 4 points
    for (int k = 0; k < sys.rows(); ++k) CHECK(sys.cmin(k) == 0.0);
  }
}

// ---------------------------------------------------------------------------------------------
// 5.4: the sliding box. On 4 points the paper's bounds add up to mu m g, the Coulomb friction
// of the whole box, so it decelerates at mu g: it stops at t = v0 / (mu g) after v0² / (2 mu g).

TEST_CASE("slide: the box stops after v0^2/(2 mu g) at t = v0/(mu g) (5.4)", "[contact][eq5.4]") {
  const std::string method = GENERATE(as<std::string>{}, "pgs", "direct");
  CAPTURE(method);
  const double v0 = 2.0;  // the scene's defaults
  const double mu = 0.3;
  const double dt = 1.0 / 240.0;
  Simulation sim(contact_scene("slide", {}, method));
  double t_stop = -1.0;
  double x_stop = 0.0;
  for (int s = 0; s < 240; ++s) {  // 1 s; it stops at about 0.68 s
    sim.step();
    const Body& box = sim.bodies()[1];
    if (t_stop < 0.0 && std::abs(box.v().x()) < 1e-9) {
      t_stop = sim.time();
      x_stop = box.x.x();
    }
  }
  const Body& box = sim.bodies()[1];
  INFO("stopped at t = " << t_stop << " s, x = " << x_stop << " m");
  REQUIRE(t_stop > 0.0);
  // Semi-implicit Euler moves by v_k dt with v_k = v0 − k μ g dt already reduced, so the
  // distance is v0²/(2 μ g) − v0 dt / 2 + O(dt²): the error is below v0 dt = 8.3 mm.
  CHECK(std::abs(x_stop - v0 * v0 / (2.0 * mu * kG)) < v0 * dt);
  // The speed reaches 0 within the step containing v0 / (μ g) (it is checked after each step).
  CHECK(t_stop >= v0 / (mu * kG) - 1e-12);
  CHECK(t_stop < v0 / (mu * kG) + dt + 1e-12);
  // Static friction then holds it: still at x_stop, on the ground.
  CHECK(std::abs(box.x.x() - x_stop) < 1e-6);
  CHECK(std::abs(box.x.y() - 0.1) < 1e-6);
}

TEST_CASE("the friction tangents turn continuously with the normal (5.4)", "[contact][eq5.4]") {
  // Two normals a milliradian apart near +y, on either side of |n_x| = |n_z|: the least aligned
  // world axis switches between them (x, then z); the tangents must not turn by 90°, or last
  // step's friction lambda (warm start, 7) would push across the motion.
  Vec3 t1a, t2a, t1b, t2b;
  tangent_basis(Vec3(1e-3, 1.0, 2e-3).normalized(), t1a, t2a);
  tangent_basis(Vec3(2e-3, 1.0, 1e-3).normalized(), t1b, t2b);
  CHECK((t1a - t1b).norm() < 1e-2);
  CHECK((t2a - t2b).norm() < 1e-2);
  for (const Vec3& n : std::vector<Vec3>{Vec3::UnitX(),
                                         Vec3::UnitY(),
                                         Vec3::UnitZ(),
                                         Vec3(1, 1, 1).normalized(),
                                         Vec3(-0.3, 0.2, -0.9).normalized()}) {
    Vec3 t1, t2;
    tangent_basis(n, t1, t2);
    CHECK(std::abs(t1.norm() - 1.0) < 1e-15);
    CHECK(std::abs(t1.dot(n)) < 1e-15);
    CHECK((n.cross(t1) - t2).norm() < 1e-15);  // right-handed (n, t1, t2)
  }
}

// ---------------------------------------------------------------------------------------------
// The friction law as one value (base/friction_law.hpp): the scene's, on the rows, in the system.

TEST_CASE("a contact's friction law is one value from the scene through the rows to the system",
          "[contact][eq5.4][cones]") {
  struct Case {
    const char* friction;
    const char* cone;
    FrictionLaw law;
  };
  for (const Case& c : {Case{"paper", "coulomb", FrictionLaw::PaperBox},
                        Case{"coulomb", "coulomb", FrictionLaw::CoulombBox},
                        Case{"cone", "coulomb", FrictionLaw::CoulombCone},
                        Case{"cone", "ccp", FrictionLaw::Relaxation}}) {
    CAPTURE(c.friction, c.cone);
    // Two boxes stacked on the ground, mu = 0.5: two pairs of four points each.
    const Scene scene = contact_scene(
        "stack", {{"n", "2"}, {"mu", "0.5"}, {"friction", c.friction}, {"cone", c.cone}});
    CHECK(scene.world.friction == c.law);
    CHECK(friction_name(c.law) == std::string(c.friction));
    CHECK(cone_law_name(c.law) == std::string(is_cone(c.law) ? c.cone : ""));
    const System sys = Simulation(scene).build_system();
    // Every contact row is one contact, its two friction rows right after it, of the scene's mu
    // and law.
    REQUIRE(sys.contacts.contacts() == 8);
    CHECK(sys.contacts.law == c.law);
    long contact_rows = 0;
    for (const RowKind kind : sys.kind) contact_rows += kind == RowKind::Contact ? 1 : 0;
    CHECK(contact_rows == 8);
    for (long i = 0; i < 8; ++i) {
      const auto n = static_cast<std::size_t>(sys.contacts.normal[std::size_t(i)]);
      CHECK(sys.kind[n] == RowKind::Contact);
      CHECK(sys.kind[n + 1] == RowKind::Friction);
      CHECK(sys.kind[n + 2] == RowKind::Friction);
      CHECK(sys.contacts.mu(i) == 0.5);
      // The box lives in the friction rows' bounds (the paper's: mu m g / 4 for the top box's
      // pair, 1 kg and 9.81 m/s²; Coulomb's: 0 until the solve sets them); a cone has none.
      const double bound = sys.cmax(Eigen::Index(n + 1));
      if (c.law == FrictionLaw::PaperBox) CHECK(bound > 0.0);
      if (c.law == FrictionLaw::CoulombBox) CHECK(bound == 0.0);
      if (is_cone(c.law)) CHECK(bound == kInf);
    }
    // The solvers see the law as it is: the problem's cones, or Coulomb's box.
    CHECK((sys.cones() != nullptr) == is_cone(c.law));
    CHECK((sys.problem().cones != nullptr) == is_cone(c.law));
    CHECK(sys.coulomb().any() == (c.law == FrictionLaw::CoulombBox));
    // Posed on a cone, the contacts keep their mu.
    const FrictionContacts posed = contacts_in_cones(sys, FrictionLaw::Relaxation);
    CHECK(posed.normal == sys.contacts.normal);
    CHECK(posed.mu == sys.contacts.mu);
    CHECK(posed.law == FrictionLaw::Relaxation);
  }
  SECTION("mu = 0: no friction rows, no contacts with a law, and none to put in a cone") {
    const System sys =
        Simulation(contact_scene("stack", {{"n", "2"}, {"mu", "0"}, {"friction", "cone"}}))
            .build_system();
    CHECK(sys.rows() == 8);
    CHECK(sys.contacts.empty());
    CHECK(sys.cones() == nullptr);
    CHECK_THROWS_WITH(contacts_in_cones(sys, FrictionLaw::CoulombCone),
                      Catch::Contains("is a contact without two friction rows after it"));
  }
}

TEST_CASE(
    "the cone laws' names read back and Coulomb's box bound is mu times lambda_n's positive part",
    "[contact][eq5.4][cones]") {
  FrictionLaw law = FrictionLaw::PaperBox;
  CHECK(cone_law_from_string("ccp", law));
  CHECK(law == FrictionLaw::Relaxation);
  CHECK(cone_law_from_string("coulomb", law));
  CHECK(law == FrictionLaw::CoulombCone);
  CHECK_FALSE(cone_law_from_string("elliptic", law));
  CHECK(law == FrictionLaw::CoulombCone);  // untouched
  CHECK_FALSE(is_cone(FrictionLaw::PaperBox));
  CHECK_FALSE(is_cone(FrictionLaw::CoulombBox));
  CHECK(coulomb_bound(0.5, 10.0) == 5.0);  // N
  CHECK(coulomb_bound(0.5, -3.0) == 0.0);  // a pulling normal force bounds nothing
}
