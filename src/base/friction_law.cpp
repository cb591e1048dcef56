// Each friction law's per-contact pieces (base/friction_law.hpp).
#include "cbps/base/friction_law.hpp"

#include <cmath>

namespace cbps {

std::string_view friction_name(FrictionLaw law) {
  switch (law) {
    case FrictionLaw::PaperBox:
      return "paper";
    case FrictionLaw::CoulombBox:
      return "coulomb";
    case FrictionLaw::CoulombCone:
    case FrictionLaw::Relaxation:
      return "cone";
  }
  return "paper";
}

std::string_view cone_law_name(FrictionLaw law) {
  return law == FrictionLaw::CoulombCone ? "coulomb" : law == FrictionLaw::Relaxation ? "ccp" : "";
}

std::string_view law_name(FrictionLaw law) {
  if (law == FrictionLaw::CoulombCone) return "cone coulomb";
  if (law == FrictionLaw::Relaxation) return "cone ccp";
  return friction_name(law);  // the boxes: "paper", "coulomb"
}

bool cone_law_from_string(std::string_view name, FrictionLaw& law) {
  if (name == "coulomb") {
    law = FrictionLaw::CoulombCone;
  } else if (name == "ccp") {
    law = FrictionLaw::Relaxation;
  } else {
    return false;
  }
  return true;
}

void project_onto_cone(double mu, Vec3& r) {
  const double t = std::hypot(r(1), r(2));  // ‖r_t‖
  if (t <= mu * r(0)) return;               // in K_mu
  if (mu * t <= -r(0)) {                    // in the polar cone −K*_mu: the apex is nearest
    r.setZero();
    return;
  }
  // The nearest point of the surface ‖r_t‖ = mu r_n, in the plane of e_n and r_t.
  const double n = (mu * t + r(0)) / (mu * mu + 1.0);
  r(1) *= mu * n / t;
  r(2) *= mu * n / t;
  r(0) = n;
}

Mat3 cone_projection_jacobian(double mu, const Vec3& x) {
  Mat3 D = Mat3::Zero();
  if (mu == 0.0) {  // the ray: P(x) = (max(x_n, 0), 0, 0)
    D(0, 0) = x(0) > 0.0 ? 1.0 : 0.0;
    return D;
  }
  const double t = std::hypot(x(1), x(2));  // ‖x_t‖, the cases of project_onto_cone
  if (t <= mu * x(0)) return Mat3::Identity();
  if (mu * t <= -x(0)) return D;
  const Eigen::Vector2d d(x(1) / t, x(2) / t);
  const double k = 1.0 / (1.0 + mu * mu);
  const double a = (x(0) + mu * t) * k;
  D(0, 0) = k;
  D.block<1, 2>(0, 1) = mu * k * d.transpose();
  D.block<2, 1>(1, 0) = mu * k * d;
  D.block<2, 2>(1, 1) = mu * mu * k * d * d.transpose() +
                        (mu * a / t) * (Eigen::Matrix2d::Identity() - d * d.transpose());
  return D;
}

Vec3 law_velocity(const Vec3& u, double mu, FrictionLaw law) {
  Vec3 u_hat = u;
  if (law == FrictionLaw::CoulombCone) u_hat(0) += mu * std::hypot(u(1), u(2));  // De Saxcé
  return u_hat;
}

Mat3 law_velocity_jacobian(const Vec3& u, double mu, FrictionLaw law) {
  Mat3 G = Mat3::Identity();
  const double t = std::hypot(u(1), u(2));
  if (law == FrictionLaw::CoulombCone && t > 0.0) {
    G(0, 1) = mu * u(1) / t;
    G(0, 2) = mu * u(2) / t;
  }
  return G;
}

Vec3 cone_natural_map(const Vec3& r, const Vec3& u, double mu, FrictionLaw law) {
  Vec3 projected = r - law_velocity(u, mu, law);
  project_onto_cone(mu, projected);
  return r - projected;
}

}  // namespace cbps
