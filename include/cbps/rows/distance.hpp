// The distance constraint (paper 5.2) and its row.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cbps/rows/row.hpp"

namespace cbps {

/// A distance constraint (5.2): |p_b − p_a| = l with p = x + r, r = R anchor; l is `length`.
/// Index -1 attaches that end to the world, the anchor then being a world point (m).
struct DistanceConstraint {
  std::string name;
  int a = -1;                    ///< body index of end a, -1 = world
  int b = -1;                    ///< body index of end b, -1 = world
  Vec3 anchor_a = Vec3::Zero();  ///< body-frame point on a (m), or world point if a = -1
  Vec3 anchor_b = Vec3::Zero();  ///< body-frame point on b (m), or world point if b = -1
  double length = 1.0;           ///< rest length l, m (> 0)
};

/// World position of one end of a distance constraint, m.
Vec3 anchor_point(const std::vector<Body>& bodies, int index, const Vec3& anchor);

/// Position constraint of 5.2 as a violation: c = |p_b − p_a| − l (5.2.2), m.
double distance_violation(const DistanceConstraint& dc, const std::vector<Body>& bodies);

/// The distance row (5.2.1) with its Baumgarte bias (5.2.3):
///   n = (p_b − p_a)/|p_b − p_a|,   j_c = [ −nᵀ, −(r_a × n)ᵀ, nᵀ, (r_b × n)ᵀ ],
///   upsilon_push = −beta (|p_b − p_a| − l) / dt   (m/s; a stretched link pulls its ends
///   together), upsilon = 0,
///   cmin = −∞, cmax = +∞.
/// beta ∈ [0, 1] is dimensionless, dt in s. Ends on the world or on a static body get no block.
Row distance_row(const DistanceConstraint& dc,
                 const std::vector<Body>& bodies,
                 double beta,
                 double dt,
                 std::uint64_t id);

}  // namespace cbps
