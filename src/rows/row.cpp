// The row form of 5.2.1, 5.3 and 5.4 (paper 5.1.3).
#include "cbps/rows/row.hpp"

namespace cbps {

namespace {
/// A body that contributes columns to J: movable, not the world.
bool has_block(const std::vector<Body>& bodies, int index) {
  return index >= 0 && !bodies[static_cast<std::size_t>(index)].is_static;
}
}  // namespace

Row direction_row(RowKind kind,
                  const std::vector<Body>& bodies,
                  int a,
                  const Vec3& p_a,
                  int b,
                  const Vec3& p_b,
                  const Vec3& n) {
  Row row;
  row.kind = kind;
  if (has_block(bodies, a)) {
    const Vec3 r_a = p_a - bodies[static_cast<std::size_t>(a)].x;
    row.body_a = a;
    row.j_a << -n.transpose(), -r_a.cross(n).transpose();
  }
  if (has_block(bodies, b)) {
    const Vec3 r_b = p_b - bodies[static_cast<std::size_t>(b)].x;
    row.body_b = b;
    row.j_b << n.transpose(), r_b.cross(n).transpose();
  }
  return row;
}

}  // namespace cbps
