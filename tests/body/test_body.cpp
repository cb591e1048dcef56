// Rigid bodies and the integrator (3.1, 3.2, 12.4.1, 12.5.1).
#include <catch2/catch.hpp>
#include <cmath>

#include "cbps/body/body.hpp"

using namespace cbps;

TEST_CASE("solid sphere and box inertia follow the textbook formulas (3.1)", "[body]") {
  Shape sphere;
  sphere.radius = 0.3;
  CHECK(sphere.inertia(2.0)(0, 0) == Approx(0.4 * 2.0 * 0.09).epsilon(1e-15));
  CHECK(sphere.volume() == Approx(4.0 / 3.0 * kPi * 0.027).epsilon(1e-15));
  Shape box;
  box.kind = Shape::Kind::Box;
  box.half_extents = Vec3(0.5, 1.0, 1.5);  // edges 1, 2, 3 m
  const Mat3 I = box.inertia(12.0);        // m (b² + c²) / 12 with full edges
  CHECK(I(0, 0) == Approx(12.0 * (4.0 + 9.0) / 12.0).epsilon(1e-15));
  CHECK(I(1, 1) == Approx(12.0 * (1.0 + 9.0) / 12.0).epsilon(1e-15));
  CHECK(I(2, 2) == Approx(12.0 * (1.0 + 4.0) / 12.0).epsilon(1e-15));
  CHECK(box.volume() == Approx(6.0).epsilon(1e-15));
}

TEST_CASE("world inertia is R I_body R^T and its inverse R I_body^-1 R^T (3.1)", "[body]") {
  Body body;
  body.shape.kind = Shape::Kind::Box;
  body.shape.half_extents = Vec3(0.1, 0.4, 0.9);
  set_mass(body, 3.0);
  body.q = Quat(Eigen::AngleAxisd(0.8, Vec3(1, -2, 0.5).normalized()));
  const Mat3 product = body.I_world() * body.Iinv_world();
  CHECK((product - Mat3::Identity()).cwiseAbs().maxCoeff() < 1e-14);
  // A rotation by 90° about z swaps the x and y moments.
  body.q = Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitZ()));
  CHECK(body.I_world()(0, 0) == Approx(body.I_body(1, 1)).epsilon(1e-14));
  CHECK(body.I_world()(1, 1) == Approx(body.I_body(0, 0)).epsilon(1e-14));
}

TEST_CASE("static bodies have zero inverse mass and inverse inertia (3.1)", "[body]") {
  Body body;
  body.is_static = true;
  CHECK(body.minv() == 0.0);
  CHECK(body.Iinv_world().isZero(0.0));
}

TEST_CASE("semi-implicit Euler on momenta matches its closed form in free fall (3.2)",
          "[body][eq3.2]") {
  // p_n = p_0 + n m g dt, x_n = x_0 + dt Σ_{k=1..n} v_k = x_0 + n dt v_0 + g dt² n(n+1)/2.
  Body body;
  set_mass(body, 2.0);
  const Vec3 g(0.0, -9.81, 0.0);
  const Vec3 v0(1.0, 2.0, 0.5);
  body.set_velocity(v0, Vec3::Zero());
  const double dt = 0.01;
  const int n = 200;
  for (int k = 0; k < n; ++k) {
    body.f = body.m * g;
    integrate_free(body, dt);
  }
  const Vec3 expected = n * dt * v0 + g * dt * dt * n * (n + 1) / 2.0;
  CHECK((body.x - expected).norm() < 1e-12);
  CHECK((body.v() - (v0 + n * dt * g)).norm() < 1e-12);
}

TEST_CASE("the exact rotation turns a body by |omega| dt per step (12.4.1)", "[body][eq12.4.1]") {
  const Vec3 axis = Vec3(1, 1, 0).normalized();
  const Vec3 omega = 2.5 * axis;  // rad/s
  Quat q = Quat::Identity();
  for (int k = 0; k < 1000; ++k) q = rotate_exact(q, omega, 1e-3);
  const Eigen::AngleAxisd aa(q);
  CHECK(aa.angle() == Approx(2.5).epsilon(1e-12));
  CHECK((aa.axis() - axis).norm() < 1e-12);
}

TEST_CASE("the normalised derivative update 12.5.1 is second order at constant omega",
          "[body][eq12.5.1]") {
  // q + ½ [0, ω] ⊗ q Δt, normalised, is a rotation about ω by 2 atan(|ω|Δt/2)
  // = |ω|Δt − (|ω|Δt)³/12 + …: a local error O(Δt³), so a global error O(Δt²).
  const Vec3 omega(0.3, -1.2, 2.0);
  const Quat exact = axis_angle_quaternion(omega * 1.0);
  double previous = 0.0;
  for (int steps : {100, 200, 400}) {
    Quat q = Quat::Identity();
    for (int k = 0; k < steps; ++k) q = rotate_derivative(q, omega, 1.0 / steps);
    const double error = q.angularDistance(exact);
    if (previous > 0.0) {
      INFO("error ratio when dt halves: " << previous / error);
      CHECK(previous / error == Approx(4.0).epsilon(0.01));
    }
    previous = error;
  }
}

TEST_CASE("torque-free rotation keeps angular momentum l exactly (3.1)", "[body]") {
  Body body;
  body.shape.kind = Shape::Kind::Box;
  body.shape.half_extents = Vec3(0.1, 0.3, 0.6);
  set_mass(body, 1.0);
  body.set_velocity(Vec3::Zero(), Vec3(0.1, 5.0, 0.2));
  const Vec3 l0 = body.l;
  for (int k = 0; k < 1000; ++k) integrate_free(body, 1e-3);
  CHECK(body.l == l0);
  CHECK(std::abs(body.q.norm() - 1.0) < 1e-14);
}

namespace {

/// A free box 1 × 0.5 × 0.2 m of 1 kg turned by `angle` about `axis`, spinning at `omega`
/// (world frame, rad/s).
Body tumbling_box(const Vec3& omega, double angle = 0.0, const Vec3& axis = Vec3::UnitX()) {
  Body body;
  body.shape.kind = Shape::Kind::Box;
  body.shape.half_extents = Vec3(0.5, 0.25, 0.1);
  set_mass(body, 1.0);
  body.q = Quat(Eigen::AngleAxisd(angle, axis.normalized()));
  body.set_velocity(Vec3::Zero(), omega);
  return body;
}

Mat3 cross_of(const Vec3& a) {
  Mat3 m;
  m << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return m;
}

}  // namespace

TEST_CASE("the gyroscopic step is one Newton step on I (w' - w) + dt w' x I w' = 0",
          "[body][integrator]") {
  const double dt = 1.0 / 60.0;
  // About a principal axis ω × I ω = 0: nothing to correct.
  const Body principal = tumbling_box(Vec3(0.0, 7.0, 0.0));
  CHECK((gyroscopic_omega(principal, dt) - principal.omega()).norm() <= 1e-14);
  // In the body frame, from ω: the residual f(ω') of backward Euler falls from O(dt) to
  // O(dt²) after the one Newton step (Newton's quadratic convergence), here by over 100×.
  const Body upright = tumbling_box(Vec3(2.0, 9.0, -3.0));
  const Mat3& I = upright.I_body;
  const auto residual = [&](const Vec3& w_new, const Vec3& w) {
    return (I * (w_new - w) + dt * w_new.cross(I * w_new)).norm();
  };
  const Vec3 w = upright.omega();
  const Vec3 w_new = gyroscopic_omega(upright, dt);
  CAPTURE(residual(w, w), residual(w_new, w));
  CHECK(residual(w_new, w) < 1e-2 * residual(w, w));
  // The step itself, written out: ω − J⁻¹ f(ω), J = I + dt ([ω]× I − [I ω]×).
  const Mat3 J = I + dt * (cross_of(w) * I - cross_of(I * w));
  const Vec3 expected = w - J.inverse() * (dt * w.cross(I * w));
  CHECK((w_new - expected).norm() <= 1e-13 * w.norm());
  // The same body turned: the step turns with it (it is taken in the body frame).
  const Vec3 axis = Vec3(1.0, -2.0, 0.5).normalized();
  const Quat turn(Eigen::AngleAxisd(0.9, axis));
  const Body turned = tumbling_box(turn * Vec3(2.0, 9.0, -3.0), 0.9, axis);
  const Vec3 turned_new = gyroscopic_omega(turned, dt);
  CHECK((turned_new - turn * w_new).norm() <= 1e-12 * w.norm());
}

TEST_CASE("the midpoint turn keeps the world angular momentum and the kinetic energy",
          "[body][integrator]") {
  const double dt = 1.0 / 60.0;
  const Vec3 axis = Vec3(0.3, 1.0, -0.7).normalized();
  const Body body = tumbling_box(Vec3(1.0, 10.0, -4.0), 1.1, axis);
  const Vec3 l = body.l;  // world, kg m²/s
  const Vec3 l_b = body.R().transpose() * l;
  Body after = body;
  after.q = midpoint_turn(body, body.omega(), dt);
  const Vec3 l_b_new = after.R().transpose() * l;  // l is kept: the body-frame l moves
  // Its new body-frame momentum solves the midpoint rule on Euler's equations.
  const Vec3 mid = 0.5 * (l_b + l_b_new);
  CHECK((l_b_new - l_b - dt * mid.cross(body.I_body_inv * mid)).norm() <= 1e-13 * l.norm());
  // Quadratic invariants: |l_b| (a rotation's) and ½ l_bᵀ I_b⁻¹ l_b.
  CHECK(l_b_new.norm() == Approx(l_b.norm()).epsilon(1e-14));
  CHECK(0.5 * l_b_new.dot(body.I_body_inv * l_b_new) ==
        Approx(0.5 * l_b.dot(body.I_body_inv * l_b)).epsilon(1e-13));
  // And the turn is about the midpoint spin by 2 atan(dt |ω_m| / 2) (the Cayley rotation).
  const Eigen::AngleAxisd turn(body.q.conjugate() * after.q);
  const Vec3 w_mid = body.I_body_inv * mid;
  CHECK(turn.angle() == Approx(2.0 * std::atan(0.5 * dt * w_mid.norm())).epsilon(1e-12));
  CHECK((turn.axis() - w_mid.normalized()).norm() <= 1e-10);
}
