// A problem's contacts beside the box: their checks, the projection onto the problem's set,
// the law's measures and the residual's cone part (system/cone_problem.hpp).
#include "cbps/system/cone_problem.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "cbps/base/error.hpp"
#include "cbps/system/boxed_problem.hpp"

namespace cbps {

std::vector<char> FrictionContacts::rows_in_cones(Eigen::Index rows) const {
  std::vector<char> in(static_cast<std::size_t>(rows), 0);
  for (const int n : normal)
    for (int k = n; k < n + 3; ++k) in[static_cast<std::size_t>(k)] = 1;
  return in;
}

std::string mu_text(const FrictionContacts& contacts) {
  if (contacts.empty()) return "none";
  const double lo = contacts.mu.minCoeff(), hi = contacts.mu.maxCoeff();
  return lo == hi ? number_text(lo) : number_text(lo) + " to " + number_text(hi);
}

std::string cone_contacts_error(const FrictionContacts& cones, long rows) {
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

ConeMeasures cone_measures(const FrictionContacts& cones,
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
    merit_squares += cone_natural_map(r, u, mu, FrictionLaw::CoulombCone).squaredNorm();
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
                            const FrictionContacts& cones) {
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

void project_onto_set(const VecX& cmin, const VecX& cmax, const FrictionContacts* cones, VecX& x) {
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
