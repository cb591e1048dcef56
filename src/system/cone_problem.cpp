// Coulomb's cone beside the box: its projection, its laws and the residual's cone part
// (system/cone_problem.hpp).
#include "cbps/system/cone_problem.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "cbps/base/error.hpp"
#include "cbps/system/boxed_problem.hpp"

namespace cbps {

std::string_view to_string(ConeLaw law) { return law == ConeLaw::Coulomb ? "coulomb" : "ccp"; }

bool cone_law_from_string(std::string_view name, ConeLaw& law) {
  if (name == "coulomb") {
    law = ConeLaw::Coulomb;
  } else if (name == "ccp") {
    law = ConeLaw::Ccp;
  } else {
    return false;
  }
  return true;
}

std::vector<char> ConeContacts::rows_in_cones(Eigen::Index rows) const {
  std::vector<char> in(static_cast<std::size_t>(rows), 0);
  for (const int n : normal)
    for (int k = n; k < n + 3; ++k) in[static_cast<std::size_t>(k)] = 1;
  return in;
}

std::string cone_contacts_error(const ConeContacts& cones, long rows) {
  if (cones.mu.size() != cones.contacts())
    return std::to_string(cones.contacts()) + " normal rows but " +
           std::to_string(cones.mu.size()) + " mu";
  long next_free = 0;  // the first row no earlier contact owns
  for (long i = 0; i < cones.contacts(); ++i) {
    const long n = cones.normal[static_cast<std::size_t>(i)];
    const std::string contact = "contact " + std::to_string(i) + ": ";
    if (n < 0 || n + 3 > rows)
      return contact + "normal row " + std::to_string(n) +
             " has not two rows after it for t1, t2 (the problem has " + std::to_string(rows) +
             " rows)";
    if (n < next_free)
      return contact + "normal row " + std::to_string(n) + " is not after the rows of contact " +
             std::to_string(i - 1) + " (" + std::to_string(next_free - 3) + " to " +
             std::to_string(next_free - 1) + ")";
    if (!(std::isfinite(cones.mu(i)) && cones.mu(i) >= 0.0))
      return contact + "mu " + number_text(cones.mu(i)) + " is not a finite number >= 0";
    next_free = n + 3;
  }
  return {};
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

Vec3 law_velocity(const Vec3& u, double mu, ConeLaw law) {
  Vec3 u_hat = u;
  if (law == ConeLaw::Coulomb) u_hat(0) += mu * std::hypot(u(1), u(2));  // De Saxcé
  return u_hat;
}

Mat3 law_velocity_jacobian(const Vec3& u, double mu, ConeLaw law) {
  Mat3 G = Mat3::Identity();
  const double t = std::hypot(u(1), u(2));
  if (law == ConeLaw::Coulomb && t > 0.0) {
    G(0, 1) = mu * u(1) / t;
    G(0, 2) = mu * u(2) / t;
  }
  return G;
}

Vec3 cone_natural_map(const Vec3& r, const Vec3& u, double mu, ConeLaw law) {
  Vec3 projected = r - law_velocity(u, mu, law);
  project_onto_cone(mu, projected);
  return r - projected;
}

ConeMeasures cone_measures(const ConeContacts& cones,
                           const VecX& lambda,
                           const VecX& w,
                           const VecX& b) {
  ConeMeasures m;
  double merit_squares = 0.0, q_squares = 0.0, r_squares = 0.0, u_squares = 0.0;
  for (long i = 0; i < cones.contacts(); ++i) {
    const int n = cones.normal[static_cast<std::size_t>(i)];
    const double mu = cones.mu(i);
    const Vec3 r = lambda.segment<3>(n), u = w.segment<3>(n);
    max_keep_nan(m.natural_map, cone_natural_map(r, u, mu, cones.law).norm());
    max_keep_nan(m.signorini, std::abs(r(0) * u(0)));
    const double r_t = std::hypot(r(1), r(2)), u_t = std::hypot(u(1), u(2));
    max_keep_nan(m.violation, std::max({r_t - mu * r(0), -r(0), 0.0}));
    max_keep_nan(m.dissipation,
                 std::max(0.0, r(1) * u(1) + r(2) * u(2) + mu * std::max(r(0), 0.0) * u_t));
    merit_squares += cone_natural_map(r, u, mu, ConeLaw::Coulomb).squaredNorm();
    q_squares += b.segment<3>(n).squaredNorm();
    r_squares += r.squaredNorm();
    u_squares += u.squaredNorm();
  }
  m.fclib_merit = std::sqrt(merit_squares) / (1.0 + std::sqrt(std::sqrt(q_squares)));
  const double relative_to =
      std::sqrt(std::max({q_squares, r_squares, u_squares}));  // max(‖q‖₂, ‖r‖₂, ‖u‖₂)
  m.siconos_error = relative_to > std::numeric_limits<double>::epsilon()
                        ? std::sqrt(merit_squares) / relative_to
                        : std::sqrt(merit_squares);
  return m;
}

double natural_map_residual(const VecX& w,
                            const VecX& lambda,
                            const VecX& cmin,
                            const VecX& cmax,
                            const ConeContacts& cones) {
  const std::vector<char> in_cone = cones.rows_in_cones(lambda.size());
  double r = 0.0;
  for (Eigen::Index k = 0; k < lambda.size(); ++k) {
    if (in_cone[static_cast<std::size_t>(k)]) continue;
    max_keep_nan(r, natural_map_row(lambda(k), w(k), cmin(k), cmax(k)));
  }
  for (long i = 0; i < cones.contacts(); ++i) {
    const int n = cones.normal[static_cast<std::size_t>(i)];
    const Vec3 map =
        cone_natural_map(lambda.segment<3>(n), w.segment<3>(n), cones.mu(i), cones.law);
    max_keep_nan(r, map.norm());
  }
  return r;
}

void project_onto_set(const VecX& cmin, const VecX& cmax, const ConeContacts* cones, VecX& x) {
  if (cones == nullptr) {
    for (Eigen::Index k = 0; k < x.size(); ++k) x(k) = clamp(x(k), cmin(k), cmax(k));
    return;
  }
  const std::vector<char> in_cone = cones->rows_in_cones(x.size());
  for (Eigen::Index k = 0; k < x.size(); ++k)
    if (!in_cone[static_cast<std::size_t>(k)]) x(k) = clamp(x(k), cmin(k), cmax(k));
  for (long i = 0; i < cones->contacts(); ++i) {
    const int n = cones->normal[static_cast<std::size_t>(i)];
    Vec3 r = x.segment<3>(n);
    project_onto_cone(cones->mu(i), r);
    x.segment<3>(n) = r;
  }
}

}  // namespace cbps
