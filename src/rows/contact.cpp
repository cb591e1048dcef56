// Contact rows (paper 5.3) with restitution (8.2.1).
#include "cbps/rows/contact.hpp"

#include <cmath>

namespace cbps {

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

std::string point_label(const Manifold& manifold,
                        const ContactPoint& point,
                        const std::vector<Body>& bodies) {
  std::size_t k = 0;  // the point's place in the manifold (by address, else by id)
  while (k < manifold.points.size() && &manifold.points[k] != &point &&
         manifold.points[k].id != point.id)
    ++k;
  return pair_label(manifold, bodies) + " point " + std::to_string(k);
}

std::string pair_label(const Manifold& manifold, const std::vector<Body>& bodies) {
  std::string s = bodies[static_cast<std::size_t>(manifold.a)].name;
  s.push_back('-');
  s.append(bodies[static_cast<std::size_t>(manifold.b)].name);
  return s;
}

// Contact row, paper 5.3. A manifold point p with normal n from a to b and depth d
// (d > 0: overlapping, d < 0: a gap inside the margin, 4).
//   C     = −d                                    separation along n, m (≥ 0 wanted)
//   Ċ     = n · (v_b + ω_b × r_b − v_a − ω_a × r_a),   r_a = p − x_a, r_b = p − x_b
//         = −n·v_a − (r_a × n)·ω_a + n·v_b + (r_b × n)·ω_b     (n·(ω × r) = (r × n)·ω)
//   j_c   = [ −nᵀ, −(r_a × n)ᵀ, nᵀ, (r_b × n)ᵀ ]    the distance row's form with p_a = p_b = p
//   υ     = β d / Δt (d ≥ 0)                      the push term, upsilon_push (5.3)
//         + −ε j_c v1 on an impact                 restitution, upsilon (8.2.1)
//   0 ≤ λ < ∞                                     a contact pushes, never pulls
Row contact_row(const Manifold& manifold,
                const ContactPoint& point,
                const std::vector<Body>& bodies) {
  Row row = direction_row(
      RowKind::Contact, bodies, manifold.a, point.p, manifold.b, point.p, manifold.n);  // (5.3)
  row.cmin = 0.0;                                                                       // push only
  row.cmax = kInf;
  row.label = "contact " + point_label(manifold, point, bodies);
  row.id = contact_row_id(manifold.a, manifold.b, point.id, 0);
  return row;
}

double contact_bias(
    double depth, double approach_velocity, double dt, double epsilon, double threshold) {
  const bool impact = approach_velocity < -threshold;
  if (depth < 0.0) {
    // A gap (margin point): it may close in this step, no more (d / dt < 0). If the approach
    // would close it within the step, the impact happens now: the restitution target alone
    // (adding d / dt to it would take |d| / dt off the rebound speed).
    if (impact && approach_velocity < depth / dt) return -epsilon * approach_velocity;  // (8.2.1)
    return depth / dt;
  }
  double upsilon = 0.0;
  if (impact) upsilon += -epsilon * approach_velocity;  // (8.2.1)
  return upsilon;
}

double contact_push(double depth, double beta, double dt) {
  return depth < 0.0 ? 0.0 : beta * depth / dt;  // (5.3)
}

std::uint64_t contact_row_id(int a, int b, std::uint64_t point_id, int k) {
  // Distance rows use ids 0 … (number of distances − 1); contact ids set the top bit.
  std::uint64_t h = 0xcbf29ce484222325ULL;  // FNV-1a over the four fields
  for (const std::uint64_t x : {std::uint64_t(std::uint32_t(a)),
                                std::uint64_t(std::uint32_t(b)),
                                point_id,
                                std::uint64_t(k)}) {
    for (int byte = 0; byte < 8; ++byte) {
      h ^= (x >> (8 * byte)) & 0xffU;
      h *= 0x100000001b3ULL;
    }
  }
  return h | (std::uint64_t(1) << 63);
}

}  // namespace cbps
