// Step schemes beside the paper's (step/scheme.hpp, docs/schemes.md): tgs against the paper's
// step at dt/N, the soft step's contact and XPBD's compliant row against their closed forms,
// Catto's soft coefficients against Box2D v3's update, and contact points carried with bodies.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <vector>

#include "cbps/collision/persistence.hpp"
#include "cbps/scene/builtin.hpp"
#include "cbps/step/scheme.hpp"
#include "cbps/step/simulation.hpp"
#include "fixture.hpp"

using namespace cbps;
using test::contact_scene;

namespace {

/// Every body's position, orientation and momenta, exactly equal.
void check_same_bodies(const std::vector<Body>& got, const std::vector<Body>& want) {
  REQUIRE(got.size() == want.size());
  for (std::size_t k = 0; k < got.size(); ++k) {
    CAPTURE(k);
    CHECK(got[k].x == want[k].x);
    CHECK(got[k].q.coeffs() == want[k].q.coeffs());
    CHECK(got[k].p == want[k].p);
    CHECK(got[k].l == want[k].l);
  }
}

/// A sphere of 1 kg and radius 0.1 m resting on a static ground plane (y = 0), no friction.
Scene sphere_on_plane() {
  Scene scene;
  scene.name = "sphere-on-plane";
  scene.world.dt = 1.0 / 60.0;
  scene.world.contact_margin = kSceneContactMargin;
  scene.bodies.push_back(ground_body("ground", Vec3::Zero(), Vec3::UnitY()));
  scene.bodies.push_back(sphere_body("ball", 0.1, 1.0, Vec3(0.0, 0.1, 0.0)));
  return scene;
}

}  // namespace

TEST_CASE("tgs with one substep is the paper's step, bit for bit", "[scheme][tgs]") {
  Scene paper = contact_scene("stack", {{"n", "4"}, {"dt", "1/60"}}, "pgs");
  paper.solver.max_iterations = 10;
  Scene tgs = paper;
  tgs.world.scheme.kind = Scheme::Tgs;
  tgs.world.scheme.substeps = 1;
  tgs.world.scheme.speculative_distance = 0.0;  // contacts found within the paper's margin
  Simulation a(paper), b(tgs);
  for (int s = 0; s < 120; ++s) {
    a.step();
    b.step();
  }
  check_same_bodies(b.bodies(), a.bodies());
}

TEST_CASE("tgs with N substeps is the paper's step at dt/N where nothing collides",
          "[scheme][tgs]") {
  // A chain has no contacts: found once a step or every substep makes no difference, so tgs's
  // N substeps of dt/N are N paper steps of dt/N exactly.
  Scene paper = contact_scene("chain", {{"n", "5"}, {"dt", "1/240"}}, "pgs");
  paper.solver.max_iterations = 5;
  Scene tgs = paper;
  tgs.world.dt = 4.0 * paper.world.dt;  // h = dt/4 exactly the paper's dt
  tgs.world.scheme.kind = Scheme::Tgs;
  tgs.world.scheme.substeps = 4;
  Simulation a(paper), b(tgs);
  for (int s = 0; s < 60; ++s) {
    b.step();
    for (int k = 0; k < 4; ++k) a.step();
  }
  check_same_bodies(b.bodies(), a.bodies());
}

TEST_CASE("Catto's soft row is Box2D v3's soft update of PGS", "[scheme][soft-step]") {
  // Box2D v3 (b2MakeSoft, solver.h) updates a soft row by
  //   Δλ = −massScale (Jv + biasRate C... ) / A_kk − impulseScale λ,
  // with a1 = 2ζ + hω, a2 = hω a1, a3 = 1/(1 + a2), biasRate = ω/a1, massScale = a2 a3,
  // impulseScale = a3. Gauss-Seidel on (A + γ) λ = b gives Δλ = −(r + γ λ)/(A_kk + γ): the two
  // agree when 1/(A_kk + γ) = massScale / A_kk and γ/(A_kk + γ) = impulseScale.
  const double hertz = GENERATE(5.0, 30.0, 60.0, 240.0);
  const double zeta = GENERATE(0.0, 1.0, 10.0);
  const double h = 1.0 / 240.0, A_kk = 3.7;  // kg⁻¹
  CAPTURE(hertz, zeta);
  const double omega = 2.0 * std::numbers::pi * hertz;
  const double a1 = 2.0 * zeta + h * omega, a2 = h * omega * a1, a3 = 1.0 / (1.0 + a2);
  const SoftRow soft = soft_row(hertz, zeta, h);
  const double gamma = soft.gamma_per_A_kk * A_kk;
  CHECK(soft.beta == Approx(h * omega / a1).epsilon(1e-14));  // biasRate h
  CHECK(1.0 / (A_kk + gamma) == Approx(a2 * a3 / A_kk).epsilon(1e-14));
  CHECK(gamma / (A_kk + gamma) == Approx(a3).epsilon(1e-14));
  // Rigid: no stiffness, no push and no softness.
  CHECK(soft_row(0.0, zeta, h).beta == 0.0);
  CHECK(soft_row(0.0, zeta, h).gamma_per_A_kk == 0.0);
}

TEST_CASE("soft-step: a sphere on a plane rests at its soft contact's depth g / omega^2",
          "[scheme][soft-step]") {
  // At rest the relax leaves v2 = 0 and the push system moves nothing: J v = beta d/h − h γ λ
  // = 0 with λ = m g, so d = h² γ m g / beta = A_kk m g / ω² = g / ω² (A_kk = 1/m for a
  // sphere: r × n = 0). The contact is against a static body: twice the contact hertz, itself
  // at most a quarter of the substep rate.
  Scene scene = sphere_on_plane();
  scene.world.scheme.kind = Scheme::SoftStep;
  const int substeps = GENERATE(2, 4, 8);
  scene.world.scheme.substeps = substeps;
  scene.solver.max_iterations = 1;
  CAPTURE(substeps);
  const double hertz = 2.0 * std::min(30.0, 0.25 * substeps / scene.world.dt);
  const double omega = 2.0 * std::numbers::pi * hertz;
  const double want = 9.81 / (omega * omega);  // m
  Simulation sim(scene);
  for (int s = 0; s < 180; ++s) sim.step();  // 3 s
  const double depth = 0.1 - sim.bodies()[1].x.y();
  CHECK(depth == Approx(want).epsilon(1e-6));
  CHECK(std::abs(sim.bodies()[1].v().y()) < 1e-9);
}

TEST_CASE("xpbd: a ball on a row of compliance alpha hangs alpha m g below its rest length",
          "[scheme][xpbd]") {
  // XPBD's compliant row is a spring of stiffness 1/alpha: C = −alpha λ at rest, λ = −m g (the
  // row pulls), so the link stretches by alpha m g. Backward Euler in XPBD damps the spring's
  // swing: ω = (alpha m)^-1/2 = 22 rad/s, ω h = 0.093, a factor (1 + (ω h)²)^-1/2 a substep,
  // e^-21 in 20 s.
  Scene scene;
  scene.name = "hanging-ball";
  scene.world.dt = 1.0 / 60.0;
  scene.world.scheme.kind = Scheme::Xpbd;
  scene.world.scheme.substeps = 4;
  const double alpha = 1e-3, m = 2.0, length = 0.5;  // m/N, kg, m
  scene.world.scheme.compliance = alpha;
  scene.solver.max_iterations = 1;
  scene.bodies.push_back(sphere_body("ball", 0.05, m, Vec3(0.0, -length, 0.0)));
  DistanceConstraint link;
  link.name = "link";
  link.a = -1;
  link.b = 0;
  link.length = length;
  scene.distances.push_back(link);
  Simulation sim(scene);
  for (int s = 0; s < 1200; ++s) sim.step();
  const double stretch = -sim.bodies()[0].x.y() - length;
  CHECK(stretch == Approx(alpha * m * 9.81).epsilon(1e-6));
  // Rigid (compliance 0): the link keeps its length to the solve's accuracy.
  scene.world.scheme.compliance = 0.0;
  Simulation rigid(scene);
  for (int s = 0; s < 600; ++s) rigid.step();
  CHECK(std::abs(-rigid.bodies()[0].x.y() - length) < 1e-9);
}

TEST_CASE("contact points carried with their bodies: the depth falls by the separation along n",
          "[scheme][persistence]") {
  // A box resting on the ground: lift it 1 mm and turn it about the vertical; each point keeps
  // its place on the box, so every depth falls by exactly 1 mm and the points turn with it.
  Scene scene = contact_scene("stack", {{"n", "1"}}, "pgs");
  Simulation sim(scene);
  std::vector<Manifold> found;
  std::vector<Row> rows;
  sim.build_rows(rows, found);
  REQUIRE(found.size() == 1);
  const ContactMemory kept = keep_contacts(sim.bodies(), found, 0);
  std::vector<Body> moved_bodies = sim.bodies();
  Body& box = moved_bodies[static_cast<std::size_t>(found[0].b)];
  const Vec3 x0 = box.x;
  box.x += Vec3(0.0, 1e-3, 0.0);
  box.q = axis_angle_quaternion(Vec3(0.0, 0.3, 0.0)) * box.q;
  std::vector<Manifold> moved;
  carry_contacts(found, kept, moved_bodies, moved);
  REQUIRE(moved.size() == 1);
  REQUIRE(moved[0].points.size() == found[0].points.size());
  const Mat3 turn = axis_angle_quaternion(Vec3(0.0, 0.3, 0.0)).toRotationMatrix();
  for (std::size_t k = 0; k < found[0].points.size(); ++k) {
    const ContactPoint &before = found[0].points[k], &after = moved[0].points[k];
    CHECK(after.depth == Approx(before.depth - 1e-3).margin(1e-15));
    CHECK(after.id == before.id);
    // The point on the ground stays; the one on the box turns and lifts: the midpoint.
    const Vec3 on_box = x0 + Vec3(0.0, 1e-3, 0.0) + turn * (before.p - x0);
    CHECK((after.p - 0.5 * (before.p + on_box)).norm() < 1e-14);
  }
}
