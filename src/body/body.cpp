// Rigid bodies (paper 3.1) and the integrator (3.2, 12.4.1, 12.5.1).
#include "cbps/body/body.hpp"

#include <cmath>

#include "cbps/base/names.hpp"

namespace cbps {

double Shape::volume() const {
  if (kind == Kind::Sphere) return 4.0 / 3.0 * kPi * radius * radius * radius;
  if (kind == Kind::Plane) return kInf;
  return 8.0 * half_extents.x() * half_extents.y() * half_extents.z();
}

Mat3 Shape::inertia(double m) const {
  if (kind == Kind::Sphere) return Mat3::Identity() * (0.4 * m * radius * radius);
  if (kind == Kind::Plane) return Mat3::Constant(kInf);  // a half-space is only ever static
  // Solid box with edges 2h: I_xx = m (h_y² + h_z²) / 3, and cyclically.
  const Vec3 h2 = half_extents.cwiseProduct(half_extents);
  return Vec3(h2.y() + h2.z(), h2.x() + h2.z(), h2.x() + h2.y()).asDiagonal() * (m / 3.0);
}

void set_mass(Body& body, double m) {
  body.m = m;
  body.I_body = body.shape.inertia(m);
  body.I_body_inv = body.I_body.inverse();
}

Mat3 Body::I_world() const {
  if (is_static) return Mat3::Zero();
  const Mat3 r = R();
  return r * I_body * r.transpose();  // I = R I_body Rᵀ (3.1)
}

Mat3 Body::Iinv_world() const {
  if (is_static) return Mat3::Zero();
  const Mat3 r = R();
  return r * I_body_inv * r.transpose();  // I⁻¹ = R I_body⁻¹ Rᵀ (3.1)
}

void Body::set_velocity(const Vec3& v_new, const Vec3& omega_new) {
  if (is_static) {
    p.setZero();
    l.setZero();
    return;
  }
  p = m * v_new;              // p = m v (3.1)
  l = I_world() * omega_new;  // l = I omega (3.1)
}

double Body::kinetic_energy() const {
  if (is_static) return 0.0;
  return 0.5 * p.dot(v()) + 0.5 * l.dot(omega());  // ½ m v² + ½ omegaᵀ I omega
}

Quat axis_angle_quaternion(const Vec3& phi) {
  const double a = phi.norm();  // angle, rad
  if (a == 0.0) return Quat::Identity();
  const Vec3 axis = phi / a;
  const double s = std::sin(0.5 * a);
  return Quat(std::cos(0.5 * a), s * axis.x(), s * axis.y(), s * axis.z());  // (12.4.1)
}

Quat rotate_exact(const Quat& q, const Vec3& omega, double dt) {
  Quat r = axis_angle_quaternion(omega * dt) * q;  // (3.2, 12.4.1)
  r.normalize();
  return r;
}

Quat rotate_derivative(const Quat& q, const Vec3& omega, double dt) {
  const Quat w(0.0, omega.x(), omega.y(), omega.z());
  const Quat dq = w * q;  // [0, omega] ⊗ q
  Quat r(q.w() + 0.5 * dt * dq.w(),
         q.x() + 0.5 * dt * dq.x(),
         q.y() + 0.5 * dt * dq.y(),
         q.z() + 0.5 * dt * dq.z());  // q + ½ [0, omega] ⊗ q dt (12.5.1)
  r.normalize();
  return r;
}

void integrate_free(Body& body, double dt) {
  if (body.is_static) return;
  body.p += body.f * dt;    // p ← p + f dt (3.2)
  body.l += body.tau * dt;  // l ← l + tau dt (3.2)
  advance_position(body, body.v(), body.omega(), dt);
}

void advance_position(Body& body, const Vec3& v, const Vec3& omega, double dt) {
  if (body.is_static) return;
  body.x += v * dt;  // x ← x + v dt (3.2)
  body.q = rotate_exact(body.q, omega, dt);
}

namespace {

/// [a]×: the matrix of a × (·).
Mat3 cross_matrix(const Vec3& a) {
  Mat3 m;
  m << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return m;
}

}  // namespace

const std::vector<std::string>& integrator_names() {
  static const std::vector<std::string> names{"paper", "gyroscopic", "midpoint"};
  return names;
}

std::optional<Integrator> integrator_named(const std::string& name) {
  return enumerator_named<Integrator>(integrator_names(), name);
}

Vec3 gyroscopic_omega(const Body& body, double dt) {
  if (body.is_static) return Vec3::Zero();
  const Mat3 R = body.R();
  const Mat3& I = body.I_body;
  const Vec3 omega = R.transpose() * body.omega();  // body frame, rad/s
  const Vec3 f = dt * omega.cross(I * omega);       // f(ω) = dt ω × I ω, kg m²/s
  const Mat3 jacobian = I + dt * (cross_matrix(omega) * I - cross_matrix(I * omega));
  return R * (omega - jacobian.partialPivLu().solve(f));
}

Quat midpoint_turn(const Body& body, const Vec3& omega, double dt) {
  if (body.is_static) return body.q;
  const Mat3 R = body.R();
  const Vec3 l = R.transpose() * (body.I_world() * omega);  // l_b, kg m²/s
  Vec3 next = l;
  Vec3 mid = l;
  // Newton on F(l') = l' − l − dt l_m × ω_m, ω_m = I_b⁻¹ l_m, whose derivative is
  // dF/dl' = E − (dt/2)([l_m]× I_b⁻¹ − [ω_m]×).
  for (int k = 0; k < 50; ++k) {
    mid = 0.5 * (l + next);
    const Vec3 w = body.I_body_inv * mid;
    const Vec3 F = next - l - dt * mid.cross(w);
    if (F.norm() <= 1e-15 * l.norm()) break;
    const Mat3 dF =
        Mat3::Identity() - 0.5 * dt * (cross_matrix(mid) * body.I_body_inv - cross_matrix(w));
    next -= dF.partialPivLu().solve(F);
  }
  mid = 0.5 * (l + next);
  const Vec3 half = 0.5 * dt * (body.I_body_inv * mid);  // dt ω_m / 2, body frame
  Quat turn(1.0, half.x(), half.y(), half.z());
  turn.normalize();
  Quat q = body.q * turn;  // the body-frame turn acts on the right
  q.normalize();
  return q;
}

}  // namespace cbps
