// Rigid bodies (paper 3.1) and the integrator (3.2, 12.4, 12.5).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cbps/base/types.hpp"

namespace cbps {

/// The shape a body is drawn and collided with (4). Sizes in m.
/// A Plane is the half-space below a static body's plane: its outward normal is the body's
/// local +y axis, R (0, 1, 0), and its surface passes through the body's x. Only static bodies
/// may be planes (a half-space has no finite mass).
struct Shape {
  enum class Kind { Sphere, Box, Plane };
  Kind kind = Kind::Sphere;
  double radius = 0.5;               ///< sphere radius, m
  Vec3 half_extents{0.5, 0.5, 0.5};  ///< box half extents, m

  double volume() const;  ///< m³
  /// Body-frame inertia tensor of a solid of uniform density with mass m (kg m²).
  Mat3 inertia(double m) const;
};

/// A rigid body (3.1). A static body is fixed in the world: m⁻¹ = 0, I⁻¹ = 0, and it gets no
/// columns in J (5.3). A movable body keeps momenta, not velocities (3.1): p = m v, l = I omega.
struct Body {
  std::string name;
  Shape shape;
  bool is_static = false;
  bool collides = true;                ///< takes part in collision detection (4)
  double m = 1.0;                      ///< mass, kg (ignored when static)
  Mat3 I_body = Mat3::Identity();      ///< body-frame inertia tensor, kg m² (SPD)
  Mat3 I_body_inv = Mat3::Identity();  ///< its inverse, kg⁻¹ m⁻²

  Vec3 x = Vec3::Zero();      ///< centre of mass, m
  Quat q = Quat::Identity();  ///< orientation, unit quaternion
  Vec3 p = Vec3::Zero();      ///< linear momentum, N s
  Vec3 l = Vec3::Zero();      ///< angular momentum, N m s

  Vec3 f = Vec3::Zero();    ///< accumulated force this step, N
  Vec3 tau = Vec3::Zero();  ///< accumulated torque this step, N m

  double minv() const { return is_static ? 0.0 : 1.0 / m; }  ///< kg⁻¹
  Mat3 R() const { return q.toRotationMatrix(); }
  /// World inertia I = R I_body Rᵀ (3.1), kg m²; zero for a static body.
  Mat3 I_world() const;
  /// World inverse inertia I⁻¹ = R I_body⁻¹ Rᵀ (3.1), kg⁻¹ m⁻²; zero for a static body.
  Mat3 Iinv_world() const;
  Vec3 v() const { return minv() * p; }            ///< v = p / m (3.2), m/s
  Vec3 omega() const { return Iinv_world() * l; }  ///< omega = I⁻¹ l (3.2), rad/s
  /// Sets the momenta from velocities: p = m v, l = I omega (3.2).
  void set_velocity(const Vec3& v_new, const Vec3& omega_new);
  /// World position of a body-frame point, m.
  Vec3 world_point(const Vec3& local) const { return x + q * local; }
  /// Kinetic energy ½ m v² + ½ omegaᵀ I omega, J.
  double kinetic_energy() const;
};

/// Sets m, I_body and I_body_inv of a movable body from its shape and mass (kg).
void set_mass(Body& body, double m);

/// Axis-angle quaternion (12.4.1): rotation by |phi| about phi/|phi|, i.e.
/// q = [cos(|phi|/2), sin(|phi|/2) phi/|phi|]; phi in rad.
Quat axis_angle_quaternion(const Vec3& phi);

/// Orientation update by the exact rotation (3.2, 12.4.1): q ← [cos(½|omega|dt),
/// sin(½|omega|dt) omega/|omega|] ⊗ q, then renormalised against round-off.
Quat rotate_exact(const Quat& q, const Vec3& omega, double dt);

/// Orientation update by the derivative (3.2, 12.5.1): q ← q + ½ [0, omega] ⊗ q dt, normalised.
Quat rotate_derivative(const Quat& q, const Vec3& omega, double dt);

/// Semi-implicit Euler on momenta without constraints (3.2): p ← p + f dt, l ← l + tau dt,
/// then x ← x + v dt with v = p/m and q by rotate_exact with omega = I⁻¹ l.
void integrate_free(Body& body, double dt);

/// Position update with given velocities (3.2, after the solve of 6.2): x ← x + v dt,
/// q ← rotate_exact(q, omega, dt).
void advance_position(Body& body, const Vec3& v, const Vec3& omega, double dt);

/// How a step turns a body (World::integrator, docs/integrators.md). Translation is the same
/// under each: x ← x + v dt (3.2).
enum class Integrator {
  /// The paper's (3.2): l = I ω2 kept in the world frame, q turned by ω2 dt with the exact
  /// rotation (12.4.1). Explicit in the turn: a free body spun near its intermediate axis gains
  /// energy (the stress catalogue's Dzhanibekov case).
  Paper,
  /// Bullet's implicit gyroscopic step (btRigidBody::computeGyroscopicImpulseImplicit_Body):
  /// before the solve, one Newton step in the body frame on I (ω' − ω) + dt ω' × I ω' = 0
  /// (gyroscopic_omega) gives the step's v1; ω, not l, is kept through the turn. Backward
  /// Euler in the gyroscopic term: stable, and it loses energy.
  Gyroscopic,
  /// The implicit midpoint rule on Euler's equations in the body frame (midpoint_turn) with
  /// the Cayley rotation: keeps l in the world frame and the kinetic energy of a free body to
  /// round-off (both are quadratic invariants the midpoint rule keeps).
  Midpoint,
};

/// The integrators' names in Integrator order (scene files' "integrator", --integrator).
const std::vector<std::string>& integrator_names();
/// The integrator of that name (integrator_names()); nullopt for any other.
std::optional<Integrator> integrator_named(const std::string& name);

/// Bullet's implicit gyroscopic step for a body with angular velocity ω = I⁻¹ l (world, rad/s):
/// in the body frame (ω_b = Rᵀ ω, I_b), one Newton step from ω_b on
/// f(ω') = I_b (ω' − ω_b) + dt ω' × I_b ω' = 0, whose Jacobian is
/// I_b + dt ([ω']× I_b − [I_b ω']×); returned in the world frame, rad/s.
Vec3 gyroscopic_omega(const Body& body, double dt);

/// The turn of one step by the implicit midpoint rule: the body-frame momentum l_b = Rᵀ l
/// (l = I ω, world) moves to l_b' = l_b + dt l_m × I_b⁻¹ l_m with l_m = (l_b + l_b')/2 (Euler's
/// equations, solved by Newton to round-off), and q ← q ⊗ cay(dt I_b⁻¹ l_m): the Cayley
/// rotation, quaternion [1, dt ω_m / 2] normalised, which carries l_b' back onto l
/// (R' l_b' = R l_b). Returns the new orientation.
Quat midpoint_turn(const Body& body, const Vec3& omega, double dt);

}  // namespace cbps
