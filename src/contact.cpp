// Contact (paper 5.3) and friction (5.4) rows, restitution (8.2.1).
#include "cbps/contact.hpp"

#include <cmath>

namespace cbps {

void tangent_basis(const Vec3& n, Vec3& t1, Vec3& t2) {
  // The components of a unit n cannot all reach 0.6 in magnitude (3 · 0.36 > 1).
  Eigen::Index axis = 0;
  while (axis < 2 && std::abs(n(axis)) >= 0.6) ++axis;
  t1 = n.cross(Vec3::Unit(axis)).normalized();
  t2 = n.cross(t1);
}

double row_velocity(const Row& row, const std::vector<Body>& bodies) {
  const auto part = [&](int index, const Row6& j) {
    if (index < 0) return 0.0;
    const Body& body = bodies[static_cast<std::size_t>(index)];
    Eigen::Matrix<double, 6, 1> v;
    v << body.v(), body.omega();
    return j.dot(v.transpose());
  };
  return part(row.body_a, row.j_a) + part(row.body_b, row.j_b);  // j_c v1 (8.2.1)
}

namespace {

std::string pair_label(const Manifold& m, const std::vector<Body>& bodies) {
  std::string s = bodies[static_cast<std::size_t>(m.a)].name;
  s.push_back('-');
  s.append(bodies[static_cast<std::size_t>(m.b)].name);
  return s;
}

}  // namespace

Row contact_row(const Manifold& m, const ContactPoint& point, const std::vector<Body>& bodies) {
  Row row = direction_row(bodies, m.a, point.p, m.b, point.p, m.n);  // (5.3)
  row.cmin = 0.0;                                                    // push only
  row.cmax = kInf;
  row.label = "contact ";
  row.label.append(pair_label(m, bodies));
  row.label.append(" #");
  row.label.append(std::to_string(point.feature));
  row.id = contact_row_id(m.a, m.b, point.feature, 0);
  return row;
}

Row friction_row(const Manifold& m,
                 const ContactPoint& point,
                 int k,
                 const Vec3& t,
                 double bound,
                 const std::vector<Body>& bodies) {
  Row row = direction_row(bodies, m.a, point.p, m.b, point.p, t);  // (5.4)
  row.cmin = -bound;
  row.cmax = bound;
  row.label = "friction ";
  row.label.append(pair_label(m, bodies));
  row.label.append(" #");
  row.label.append(std::to_string(point.feature));
  row.label.append(k == 1 ? " t1" : " t2");
  row.id = contact_row_id(m.a, m.b, point.feature, k);
  return row;
}

double paper_friction_bound(const Manifold& m,
                            const std::vector<Body>& bodies,
                            double mu,
                            const Vec3& g) {
  double mass = 0.0;
  for (const int index : {m.a, m.b}) {
    const Body& body = bodies[static_cast<std::size_t>(index)];
    if (!body.is_static) mass += body.m;
  }
  const double per_point = mass / static_cast<double>(std::max<std::size_t>(1, m.points.size()));
  return mu * per_point * std::abs(g.dot(m.n));  // mu m |g·n| (5.4)
}

double contact_bias(double depth,
                    double approach_velocity,
                    double beta,
                    double dt,
                    double epsilon,
                    double threshold,
                    bool with_push) {
  const bool impact = approach_velocity < -threshold;
  if (depth < 0.0) {
    // A gap (margin point): it may close in this step, no more (d / dt < 0). If the approach
    // would close it within the step, the impact happens now: the restitution target alone
    // (adding d / dt to it would take |d| / dt off the rebound speed).
    if (impact && approach_velocity < depth / dt) return -epsilon * approach_velocity;  // (8.2.1)
    return depth / dt;
  }
  double upsilon = with_push ? beta * depth / dt : 0.0;  // (5.3)
  if (impact) upsilon += -epsilon * approach_velocity;   // (8.2.1)
  return upsilon;
}

std::uint64_t contact_row_id(int a, int b, std::uint32_t feature, int k) {
  // Distance rows use ids 0 … (number of distances − 1); contact ids set the top bit.
  std::uint64_t h = 0xcbf29ce484222325ULL;  // FNV-1a over the four fields
  for (const std::uint64_t x : {std::uint64_t(std::uint32_t(a)),
                                std::uint64_t(std::uint32_t(b)),
                                std::uint64_t(feature),
                                std::uint64_t(k)}) {
    for (int byte = 0; byte < 8; ++byte) {
      h ^= (x >> (8 * byte)) & 0xffU;
      h *= 0x100000001b3ULL;
    }
  }
  return h | (std::uint64_t(1) << 63);
}

}  // namespace cbps
