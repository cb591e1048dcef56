// Torque-free rigid body by GSL's ODE driver (gsl_odeiv2, rk8pd).
#include "cbps/studies/euler_reference.hpp"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

#include <memory>
#include <string>

#include "cbps/base/error.hpp"

namespace cbps {

namespace {

/// Euler's equations: omega' = I⁻¹ ((I omega) × omega) in body axes, I diagonal.
int euler_rhs(double /*t*/, const double w[], double dwdt[], void* params) {
  const double* I = static_cast<const double*>(params);
  dwdt[0] = (I[1] - I[2]) * w[1] * w[2] / I[0];
  dwdt[1] = (I[2] - I[0]) * w[2] * w[0] / I[1];
  dwdt[2] = (I[0] - I[1]) * w[0] * w[1] / I[2];
  return GSL_SUCCESS;
}

}  // namespace

std::vector<Vec3> euler_reference(const Vec3& I, const Vec3& omega0, double dt_out, long count) {
  // GSL calls abort() on errors unless told not to; its status codes are checked instead.
  gsl_set_error_handler_off();
  double moments[3] = {I.x(), I.y(), I.z()};
  gsl_odeiv2_system system{euler_rhs, nullptr, 3, moments};
  const std::unique_ptr<gsl_odeiv2_driver, decltype(&gsl_odeiv2_driver_free)> driver(
      gsl_odeiv2_driver_alloc_y_new(&system, gsl_odeiv2_step_rk8pd, dt_out * 1e-2, 1e-12, 1e-12),
      &gsl_odeiv2_driver_free);
  if (!driver) throw ComputationError("euler_reference: GSL could not allocate its driver");
  std::vector<Vec3> out;
  out.reserve(static_cast<std::size_t>(count));
  double w[3] = {omega0.x(), omega0.y(), omega0.z()};
  double t = 0.0;
  for (long k = 0; k < count; ++k) {
    const double target = static_cast<double>(k) * dt_out;
    if (k > 0) {
      const int status = gsl_odeiv2_driver_apply(driver.get(), &t, target, w);
      if (status != GSL_SUCCESS) {
        throw ComputationError("euler_reference: GSL's driver failed at t = " + std::to_string(t) +
                               " s: " + gsl_strerror(status));
      }
    }
    out.emplace_back(w[0], w[1], w[2]);
  }
  return out;
}

}  // namespace cbps
