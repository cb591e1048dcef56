// Contacts (4), contact rows (5.3), friction (5.4), restitution (8.2.1) and the improved push
// factor (8.1) on the built-in contact scenes. Every expected value is worked out in the comment
// beside it from a force balance or from kinematics, or comes from another solver; none is a
// number printed by the code under test.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "cbps/cbps.hpp"
#include "cbps/rows/contact.hpp"
#include "cbps/scene/builtin.hpp"
#include "cbps/step/simulation.hpp"
#include "fixture.hpp"

using namespace cbps;

namespace {

constexpr double kG = 9.81;  // |g| of every built-in scene, m/s²

/// A built-in contact scene with NAME=VALUE overrides and the given solver.
Scene contact_scene(const std::string& name,
                    const std::map<std::string, std::string>& values,
                    const std::string& method = "pgs") {
  Scene scene = make_builtin_scene(name, values);
  scene.solver.method = method_of(method);
  return scene;
}

/// The solver settings of the scene with another method (e.g. the direct path, 6.2).
SolverSettings with_method(const Scene& scene, const std::string& method) {
  SolverSettings s = scene.solver;
  s.method = method_of(method);
  return s;
}

bool has_stage(const std::vector<std::string>& stages, const std::string& stage) {
  return std::find(stages.begin(), stages.end(), stage) != stages.end();
}

/// The number after `"key": ` in a JSON text (the first occurrence); NaN if there is none.
double json_number(const std::string& json, const std::string& key) {
  const std::string pattern = "\"" + key + "\": ";
  const std::size_t at = json.find(pattern);
  if (at == std::string::npos) return std::nan("");
  return std::strtod(json.c_str() + at + pattern.size(), nullptr);
}

double kinetic_energy(const std::vector<Body>& bodies) {
  double e = 0.0;
  for (const Body& body : bodies) e += body.is_static ? 0.0 : body.kinetic_energy();
  return e;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// 12.2: the sphere in the V. Normals a = (sin φ_l, cos φ_l, 0) and b = (−sin φ_r, cos φ_r, 0)
// point from each static plane (body a of the manifold) to the ball (body b). At rest
// a λ₁ + b λ₂ = m g ŷ: the x row gives λ₁ sin φ_l = λ₂ sin φ_r, the y row
// λ₁ cos φ_l + λ₂ cos φ_r = m g, so λ₁ = m g sin φ_r / sin(φ_l + φ_r), λ₂ = m g sin φ_l /
// sin(φ_l + φ_r); for φ_l = φ_r = 45° both are m g / (2 cos 45°). A = J M⁻¹ Jᵀ is 2×2 and
// positive definite (a and b are independent), so λ is unique and any exact solver must give it.

TEST_CASE(
    "v-corner: the contact forces balance the weight, lambda = m g sin(phi)/sin(phi_l + "
    "phi_r) (12.2, 5.3)",
    "[contact][eq12.2][eq12.2.1][eq12.2.2][eq5.3]") {
  const auto [left_deg, right_deg] =
      GENERATE(std::pair{45.0, 30.0}, std::pair{45.0, 45.0}, std::pair{30.0, 60.0});
  CAPTURE(left_deg, right_deg);
  const double m = 1.0;  // the scene's default ball mass, kg
  const double phi_l = left_deg * kPi / 180.0;
  const double phi_r = right_deg * kPi / 180.0;
  const Vec3 a(std::sin(phi_l), std::cos(phi_l), 0.0);
  const Vec3 b(-std::sin(phi_r), std::cos(phi_r), 0.0);
  const double lambda1 = m * kG * std::sin(phi_r) / std::sin(phi_l + phi_r);
  const double lambda2 = m * kG * std::sin(phi_l) / std::sin(phi_l + phi_r);
  if (left_deg == right_deg) {
    CHECK(lambda1 == Approx(m * kG / (2.0 * std::cos(kPi / 4.0))).epsilon(1e-14));
  }
  const std::map<std::string, std::string> values = {
      {"angle_left_deg", std::to_string(left_deg)}, {"angle_right_deg", std::to_string(right_deg)}};

  SECTION("J's rows are [n^T, (r x n)^T] in the ball's columns only (12.2.1, 5.3)") {
    Simulation sim(contact_scene("v-corner", values, "direct"));
    const System sys = sim.build_system();
    REQUIRE(sys.rows() == 2);
    CHECK(sys.blocks() == 1);  // the two planes are static: no columns (5.3)
    CHECK(sys.J.cols() == 6);
    const MatX J = MatX(sys.J);
    // The contact point lies on the line through the centre along n, so r_b ∥ n and
    // r_b × n = 0: the sphere's rows have no angular part (12.2: "no rotation").
    Eigen::Matrix<double, 2, 6> expected;
    expected << a.transpose(), 0, 0, 0, b.transpose(), 0, 0, 0;
    INFO("J =\n" << J);
    CHECK((J - expected).lpNorm<Eigen::Infinity>() < 1e-15);  // a few roundings of unit values
    // (12.2.2): Jᵀ λ = a λ₁ + b λ₂, and at the force balance it is the weight m g ŷ.
    const VecX lambda = Eigen::Vector2d(lambda1, lambda2);
    const VecX f = sys.J.transpose() * lambda;
    CHECK((f.head<3>() - m * kG * Vec3::UnitY()).norm() < 1e-13 * m * kG);
  }

  SECTION("the direct path at step 0 and after 60 steps, PGS to its tolerance (6.2, 7.1.1)") {
    // The ball starts touching both planes (depth 0) at rest, so the first system already has
    // the static answer. Direct: exact up to rounding, 1e-9 relative leaves ~10⁶ u of room.
    Simulation sim(contact_scene("v-corner", values, "direct"));
    const System sys = sim.build_system();
    REQUIRE(sys.rows() == 2);
    VecX lambda = VecX::Zero(2);
    const SolverSummary direct = sim.solve_system(sys, lambda);
    INFO(direct.message);
    CHECK(direct.termination == Termination::Direct);
    CHECK(lambda(0) == Approx(lambda1).epsilon(1e-9));
    CHECK(lambda(1) == Approx(lambda2).epsilon(1e-9));
    // PGS stops at natural-map residual 1e-10 (the scene's tolerance); with A⁻¹'s norm at most
    // m / (1 − |cos(φ_l + φ_r)|) ≤ 1.4 kg here, λ is within ~1e-10 N: 1e-8 relative is loose.
    VecX lambda_pgs = VecX::Zero(2);
    const SolverSummary pgs =
        sim.solve_system(sys, sys.b, lambda_pgs, with_method(sim.scene(), "pgs"));
    INFO(pgs.message);
    CHECK(pgs.termination == Termination::ResidualTolerance);
    CHECK(lambda_pgs(0) == Approx(lambda1).epsilon(1e-8));
    CHECK(lambda_pgs(1) == Approx(lambda2).epsilon(1e-8));

    // 60 steps of 1/60 s (1 s): the ball must stay where it is, with the same forces. Both
    // runs get a 1 mm contact margin (the scene's default, made explicit): PGS's 1e-10 N error
    // separates the ball by ~1e-14 m, which at margin 0 loses a contact for a step (measured:
    // the ball then sinks 1.45 mm and λ₂ jumps to 13.96 N).
    for (const std::string method : {"direct", "pgs"}) {
      CAPTURE(method);
      std::map<std::string, std::string> run_values = values;
      run_values["margin"] = "0.001";
      Simulation run(contact_scene("v-corner", run_values, method));
      const Vec3 x0 = run.bodies()[2].x;
      VecX last;
      int rows = 0;
      run.set_observer([&](const System& s, const VecX& l, const VecX&) {
        rows = s.rows();
        last = l;
      });
      double max_penetration = 0.0;
      for (int s = 0; s < 60; ++s)
        max_penetration = std::max(max_penetration, run.step().max_penetration);
      REQUIRE(rows == 2);
      const double rel = method == "direct" ? 1e-9 : 1e-8;
      CHECK(last(0) == Approx(lambda1).epsilon(rel));
      CHECK(last(1) == Approx(lambda2).epsilon(rel));
      CHECK(max_penetration < 1e-9);
      CHECK((run.bodies()[2].x - x0).norm() < 1e-9);
    }
  }
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
      for (const Manifold& m : contacts) {
        touching = touching && m.points.size() == 1 && std::abs(m.points[0].depth) < 1e-12;
      }
      if (!touching) ++missing;
    }
  }
  INFO(missing << " of " << pairs << " angle pairs do not start with two contacts of depth 0");
  CHECK(missing == 0);
}

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
    for (const Manifold& m : manifolds) CHECK(m.points.size() == 4);
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

TEST_CASE(
    "Coulomb friction rows point to their contact row; the direct solve keeps |lambda_t| "
    "<= mu lambda_n and slows a sliding box by mu g (5.4)",
    "[contact][eq5.4][eq6.2]") {
  // The slide scene at step 0: a 1 kg box at v0 = 2 m/s along x on the ground, mu = 0.3.
  const double mu = 0.3;
  const double v0 = 2.0;
  Simulation sim(contact_scene("slide", {{"friction", "coulomb"}}, "direct"));
  const System sys = sim.build_system();
  REQUIRE(sys.rows() == 12);
  for (int k = 0; k < sys.rows(); ++k) {
    CAPTURE(k, sys.labels[std::size_t(k)]);
    const int n = sys.normal_row[std::size_t(k)];
    if (k % 3 == 0) {
      CHECK(n == -1);  // a contact row
      continue;
    }
    REQUIRE(n == k - k % 3);  // the contact row of the same point, just before its tangents
    CHECK(sys.labels[std::size_t(n)].rfind("contact ", 0) == 0);
    // "friction ground-box #f t1" belongs to "contact ground-box #f".
    const std::string& label = sys.labels[std::size_t(k)];
    CHECK(label.substr(9, label.size() - 12) == sys.labels[std::size_t(n)].substr(8));
    CHECK(sys.mu(k) == mu);
  }
  VecX lambda = VecX::Zero(sys.rows());
  const SolverSummary s = sim.solve_system(sys, lambda);
  INFO(s.message);
  CHECK(s.termination == Termination::Direct);
  // The bounds ±mu lambda_n are iterated to a fixed point, so the cone holds up to the last
  // bound change: 1e-9 N, 1e-10 of the weight, allows for it.
  const double cone_slack = 1e-9;
  double normal_total = 0.0;
  for (int k = 0; k < sys.rows(); k += 3) {
    normal_total += lambda(k);
    for (int t = k + 1; t <= k + 2; ++t) {
      CAPTURE(t);
      CHECK(std::abs(lambda(t)) <= mu * lambda(k) + cone_slack);
    }
  }
  // The box neither rises nor sinks: the normal forces carry the weight, Σλ_n = m g (v2_y = 0).
  CHECK(normal_total == Approx(1.0 * kG).epsilon(1e-9));
  // It slides: kinetic friction μ Σλ_n = μ m g decelerates it, v2_x = v0 − μ g dt, and it does
  // not tip (μ = 0.3 < half width / half height = 1), so ω2 = 0.
  const VecX v2 = compute_v2(sys.v1, sys.Minv, sys.J, lambda, sys.fext, sys.dt);
  CHECK(v2(0) == Approx(v0 - mu * kG * sys.dt).epsilon(1e-9));
  CHECK(std::abs(v2(1)) < 1e-9);
  CHECK(v2.tail<3>().norm() < 1e-9);
}

// ---------------------------------------------------------------------------------------------
// 8.2: restitution.

TEST_CASE("restitution: upsilon = -eps j_c v1 above the threshold, none below (8.2.1, 5.3)",
          "[contact][eq8.2.1][eq5.3]") {
  const double beta = 0.2;
  const double dt = 1.0 / 60.0;
  const double eps = 0.5;
  const double threshold = 0.1;
  // The bias of a system with the push (5.3; the position system of 8.1) or without it (the
  // velocity system of 8.1).
  const auto bias = [&](double depth, double approach, bool push) {
    const double upsilon = contact_bias(depth, approach, dt, eps, threshold);
    return push ? with_push(upsilon, contact_push(depth, beta, dt)) : upsilon;
  };
  // Approaching at 2 m/s (j_c v1 = −2): the row asks to separate at ε · 2 = +1 m/s.
  CHECK(bias(0.0, -2.0, false) == 1.0);
  CHECK(bias(0.0, -2.0, true) == 1.0);  // d = 0: no push
  // With a depth of 1 cm the push β d / dt = 0.2 · 0.01 · 60 = 0.12 m/s adds to it (5.3)...
  CHECK(bias(0.01, -2.0, true) == Approx(1.12).epsilon(1e-14));
  // ...but not in the velocity system of the improved push (8.1).
  CHECK(bias(0.01, -2.0, false) == 1.0);
  // Below the threshold (a resting contact) and for separating bodies: no bounce.
  CHECK(bias(0.0, -0.05, false) == 0.0);
  CHECK(bias(0.0, 2.0, false) == 0.0);
  CHECK(bias(0.01, -0.05, true) == Approx(0.12).epsilon(1e-14));
  // A gap of 1 mm (a margin point, d = −0.001): closing at 2 m/s covers 3.3 cm in the step, so
  // the impact is now and the target is the rebound alone, ε · 2 = 1 m/s (adding d / dt =
  // −0.06 m/s would take 6 % off it). At 0.05 m/s the gap stays open: d / dt, a bound on the
  // approach, and no rebound.
  CHECK(bias(-0.001, -2.0, true) == 1.0);
  CHECK(bias(-0.001, -2.0, false) == 1.0);
  CHECK(bias(-0.001, -0.05, true) == Approx(-0.06).epsilon(1e-14));
  // Fast (0.5 m/s, above the threshold) but not fast enough to close 1 cm in 1/60 s (0.6 m/s).
  CHECK(bias(-0.01, -0.5, true) == Approx(-0.6).epsilon(1e-14));
}

TEST_CASE("bounce: each rebound apex is eps^2 times the one before (8.2.1, 8.1)",
          "[contact][eq8.2.1][eq8.1]") {
  // A ball dropped from h0 = 1 m with ε = 0.8 (the scene's defaults, dt 1/240, improved push)
  // leaves the ground at ε times its impact speed, so apex heights go as ε² = 0.64.
  // Tolerance 5 %: the impact is seen up to one step late, so the speed read is off by up to
  // g dt = 0.04 m/s of ≥ 2.8 m/s (h ≥ 0.41 m) and the ball is up to v dt ≈ 1.2 cm deep; the
  // height (∝ v²) is then off by up to 2 g dt / v + v dt / h ≈ 3 % + 3 % per bounce.
  const double eps = 0.8;
  const double h0 = 1.0;
  const double r = 0.1;
  Simulation sim(contact_scene("bounce", {}));
  REQUIRE(sim.scene().world.restitution == eps);
  std::vector<double> apex;  // heights of the ball's lowest point at each local maximum of y
  double y_prev2 = sim.bodies()[1].x.y();
  double y_prev = y_prev2;
  for (int s = 0; s < 500 && apex.size() < 3; ++s) {  // apexes near 0.8, 1.47, 1.99 s
    sim.step();
    const double y = sim.bodies()[1].x.y();
    if (y_prev > y_prev2 && y_prev >= y) apex.push_back(y_prev - r);
    y_prev2 = y_prev;
    y_prev = y;
  }
  INFO("apex heights " << (apex.size() > 0 ? apex[0] : 0) << ", " << (apex.size() > 1 ? apex[1] : 0)
                       << ", " << (apex.size() > 2 ? apex[2] : 0) << " m");
  REQUIRE(apex.size() == 3);
  CHECK(apex[0] / h0 == Approx(eps * eps).epsilon(0.05));
  CHECK(apex[1] / apex[0] == Approx(eps * eps).epsilon(0.05));
  CHECK(apex[2] / apex[1] == Approx(eps * eps).epsilon(0.05));
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

// ---------------------------------------------------------------------------------------------
// What a scene does not need is left out (4, 5.3, 5.4).

TEST_CASE("a scene runs only the stages and has only the columns it needs (4, 5.3, 5.4)",
          "[contact][eq4][eq5.3][eq5.4]") {
  SECTION("no contact pairs, no collision stage") {
    for (const char* name : {"pendulum-wave", "chain"}) {
      CAPTURE(name);
      Simulation sim(make_builtin_scene(name, {{"n", "5"}}));
      sim.step();
      CHECK(sim.stages().size() > 2);
      CHECK_FALSE(has_stage(sim.stages(), "collision (4)"));
      CHECK_FALSE(has_stage(sim.stages(), "contact_rows (5.3)"));
      CHECK(sim.manifolds().empty());
    }
  }
  SECTION("v-corner with mu = 0: contacts but no friction rows, 2 rows") {
    Simulation sim(contact_scene("v-corner", {{"mu", "0"}}));
    const StepReport r = sim.step();
    CHECK(has_stage(sim.stages(), "collision (4)"));
    CHECK(has_stage(sim.stages(), "contact_rows (5.3)"));
    CHECK_FALSE(has_stage(sim.stages(), "friction_rows (5.4)"));
    CHECK(r.rows == 2);
    CHECK(r.contacts == 2);
  }
  SECTION("static bodies get no columns") {
    // 3 boxes on a static ground plane: 3 movable bodies, 6 columns each.
    Simulation sim(contact_scene("stack", {{"n", "3"}}));
    const System& sys = sim.assemble();
    CHECK(sys.blocks() == 3);
    CHECK(sys.J.cols() == 18);
    CHECK(sys.block_of_body[0] == -1);
    CHECK(sys.Minv.rows() == 18);
  }
}

TEST_CASE("separate columns of boxes are separate islands of A (6.2.9)", "[contact][eq6.2.9]") {
  // 3 columns of 3 boxes, 0.5 m apart: no contact joins two columns, and the ground has no
  // columns of its own, so A splits into one block per column.
  Simulation sim(contact_scene("stack", {{"n", "3"}, {"columns", "3"}}, "direct"));
  const System& sys = sim.assemble();
  const std::vector<std::vector<int>> islands = find_islands(sys.A);
  CHECK(islands.size() == 3);
  for (const std::vector<int>& island : islands) CHECK(island.size() == 3 * 4 * 3);
  VecX lambda = VecX::Zero(sys.rows());
  const SolverSummary s = sim.solve_system(sys, lambda);
  INFO(s.message);
  CHECK(s.islands == 3);
  CHECK(s.termination == Termination::Direct);
}

// ---------------------------------------------------------------------------------------------
// 8.1 and 6.2 together: a tall stack, the test.

TEST_CASE(
    "a 10-box stack at dt 1/60 with the improved push stands for 10 s: block PGS with 20 "
    "sweeps, and the direct path (8.1, 7.1.1, 6.2)",
    "[contact][eq8.1][eq7.1.1][eq6.2]") {
  // Row-by-row PGS with 20 sweeps does not hold this stack (the top box walks 4–15 cm in 10 s,
  // docs/contacts.md, "Stacks"); block PGS, each manifold's 12 rows solved together, does.
  const std::string method = GENERATE(as<std::string>{}, "block-pgs", "direct");
  CAPTURE(method);
  Scene scene = contact_scene("stack", {{"n", "10"}, {"dt", "1/60"}, {"push", "improved"}}, method);
  scene.solver.iterations = 20;
  Simulation sim(scene);
  REQUIRE(sim.bodies().size() == 11);
  const Vec3 top0 = sim.bodies().back().x;
  double max_penetration = 0.0;
  for (int s = 0; s < 600; ++s) {  // 10 s at 1/60 s
    const StepReport r = sim.step();
    max_penetration = std::max(max_penetration, r.max_penetration);
    if (method == "block-pgs") REQUIRE(r.solver.iterations <= 20);
  }
  const Vec3 drift = sim.bodies().back().x - top0;
  INFO("max penetration " << max_penetration << " m, top drift " << drift.transpose() << " m");
  CHECK(max_penetration < 0.01);
  CHECK(std::hypot(drift.x(), drift.z()) < 0.01);
  CHECK(std::abs(drift.y()) < 0.01);
}

// ---------------------------------------------------------------------------------------------
// 8.1: the push-factor figure.

TEST_CASE("the improved push separates overlapping boxes without giving them speed (8.1)",
          "[contact][eq8.1]") {
  // 3 unit boxes, each sunk 0.25 m into the one below (the scene's defaults), 1 s at 1/60 s.
  // Original Baumgarte asks the first step for β d / dt = 0.2 · 0.25 · 60 = 3 m/s apart, and
  // keeps it: about ½ m v² = 4.5 J per box. The improved technique moves the bodies apart with
  // the position system only; the kept velocities see no push and stay at rest.
  const auto run = [](const std::string& push, StepReport& last) {
    Simulation sim(contact_scene("overlap", {{"push", push}}));
    for (int s = 0; s < 60; ++s) last = sim.step();
    return sim;
  };
  StepReport original_last, improved_last;
  const Simulation original = run("original", original_last);
  const Simulation improved = run("improved", improved_last);
  const double e_original = kinetic_energy(original.scene().bodies);
  const double e_improved = kinetic_energy(improved.scene().bodies);
  INFO("kinetic energy after 1 s: original " << e_original << " J, improved " << e_improved
                                             << " J");
  CHECK(e_original > 1.0);  // the injected separation velocity
  CHECK(e_improved < 1e-6 * e_original);
  // Separated: resting on each other, centres 1 m apart, the lowest at 0.5 m.
  CHECK(improved_last.max_penetration < 1e-3);
  for (std::size_t k = 1; k < improved.scene().bodies.size(); ++k) {
    CAPTURE(k);
    CHECK(std::abs(improved.scene().bodies[k].x.y() - (0.5 + double(k - 1))) < 1e-3);
  }
}

// ---------------------------------------------------------------------------------------------
// The command line's --check: every step solved again by the direct path (6.2).

namespace {

struct CheckedRun {
  std::string args;
  double weight;  ///< the scene's total weight m g, N: the force scale of its lambdas
};

void check_cross_check(const CheckedRun& c, long steps) {
  CAPTURE(c.args);
  const test::CliResult r =
      test::run_cli("run " + c.args + " --check --json --quiet --steps " + std::to_string(steps));
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(json_number(r.out, "steps_checked") == double(steps));
  // Every step's direct answer verified as `cbps lcp` verifies a solution: natural-map residual
  // ≤ 1e-9 · max(1, ‖b‖∞, max |A_ij|). (Its own stopping rule, 64 u of the force scale, about
  // 1e-11 N here, is stricter than the proximal steps reach on some singular systems with
  // friction: `direct_stopped_short` counts those steps and is reported, not asserted.)
  CHECK(json_number(r.out, "direct_unverified") == 0.0);
  const double residual = json_number(r.out, "max_direct_residual");
  CAPTURE(residual);
  CHECK(residual <= 1e-9 * c.weight);
  CHECK(r.out.find("\"collision (4)\"") != std::string::npos);
}

}  // namespace

TEST_CASE("contact scenes pass the --check cross-check against the direct path (6.2, 4)",
          "[contact][cli][eq6.2][eq4]") {
  // Every contact scene, run by PGS, block PGS or the direct path itself, each step solved
  // again by the direct path started from the run's lambda (from lambda = 0 if that stalls).
  const CheckedRun run = GENERATE(values<CheckedRun>({
      {"v-corner", 1.0 * kG},
      {"v-corner --param mu=0.5", 1.0 * kG},
      {"v-corner --param mu=0.5 --param friction=coulomb", 1.0 * kG},
      {"v-corner --param mu=0.5 --param friction=coulomb --solver direct", 1.0 * kG},
      {"newtons-cradle", 5 * 0.2 * kG},
      {"slide", 1.0 * kG},
      {"slide --param friction=coulomb", 1.0 * kG},
      {"slide --solver direct", 1.0 * kG},
      {"slide --param friction=coulomb --solver direct", 1.0 * kG},
      {"bounce", 1.0 * kG},  // 240 steps (1 s): the ball lands at about 0.45 s
      {"overlap --push original", 3.0 * kG},
      {"overlap --push improved", 3.0 * kG},
      {"overlap --push improved --solver direct", 3.0 * kG},
      {"overlap --push original --solver direct", 3.0 * kG},
      {"stack", 10.0 * kG},
      {"stack --solver block-pgs", 10.0 * kG},
      {"stack --solver direct", 10.0 * kG},
      {"pyramid --param base=4", 10.0 * kG},
      {"pyramid --param base=4 --solver block-pgs", 10.0 * kG},
      {"pyramid --param base=4 --solver direct", 10.0 * kG},
  }));
  check_cross_check(run, run.args == "bounce" ? 240 : 60);
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
