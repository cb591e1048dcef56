// The distance constraint (paper 5.2).
#include "cbps/rows/distance.hpp"

namespace cbps {

Vec3 anchor_point(const std::vector<Body>& bodies, int index, const Vec3& anchor) {
  if (index < 0) return anchor;
  return bodies[static_cast<std::size_t>(index)].world_point(anchor);
}

double distance_violation(const DistanceConstraint& dc, const std::vector<Body>& bodies) {
  const Vec3 p_ab =
      anchor_point(bodies, dc.b, dc.anchor_b) - anchor_point(bodies, dc.a, dc.anchor_a);
  return p_ab.norm() - dc.length;  // c = |p_b − p_a| − l (5.2.2)
}

// Distance row, paper 5.2.1 and 5.2.3.
//   C     = |p_b − p_a| − l,                p_i = x_i + r_i
//   Ċ     = n · (v_b + ω_b × r_b − v_a − ω_a × r_a),   n = (p_b − p_a)/|p_b − p_a|
//         = −n·v_a − (r_a × n)·ω_a + n·v_b + (r_b × n)·ω_b     (n·(ω × r) = (r × n)·ω)
//   j_c   = [ −nᵀ, −(r_a × n)ᵀ, nᵀ, (r_b × n)ᵀ ]
//   υ     = −β C / Δt   (the push term, upsilon_push; the row has no other bias)
Row distance_row(const DistanceConstraint& dc,
                 const std::vector<Body>& bodies,
                 double beta,
                 double dt,
                 std::uint64_t id) {
  const Vec3 p_a = anchor_point(bodies, dc.a, dc.anchor_a);
  const Vec3 p_b = anchor_point(bodies, dc.b, dc.anchor_b);
  const Vec3 p_ab = p_b - p_a;
  const double dist = p_ab.norm();
  // Coincident ends have no direction; any unit n gives a valid row (it pushes them apart).
  const Vec3 n = dist > 0.0 ? Vec3(p_ab / dist) : Vec3::UnitX();

  Row row = direction_row(RowKind::Distance, bodies, dc.a, p_a, dc.b, p_b, n);
  row.label = dc.name;
  row.id = id;
  row.upsilon_push = -beta * (dist - dc.length) / dt;  // (5.2.3)
  row.cmin = -kInf;
  row.cmax = kInf;
  return row;
}

}  // namespace cbps
