// A reference solution of a torque-free rigid body: Euler's equations (12.3 in body axes),
// integrated by GSL's Runge-Kutta-Prince-Dormand (8, 9) with tight tolerances. The stress
// catalogue's Dzhanibekov case compares the simulation against it.
#pragma once

#include <vector>

#include "cbps/base/types.hpp"

namespace cbps {

/// Body-frame angular velocity omega(t) of a torque-free body with principal moments I
/// (kg m², the body frame's axes), from omega0 (rad/s) at t = 0, at the times t_k = k dt_out,
/// k = 0 … count − 1:
///   I1 omega1' = (I2 − I3) omega2 omega3,  and cyclically (Euler's equations).
/// Relative and absolute tolerance 1e-12 per step of the driver. Throws ComputationError if
/// GSL's driver fails.
std::vector<Vec3> euler_reference(const Vec3& I, const Vec3& omega0, double dt_out, long count);

}  // namespace cbps
