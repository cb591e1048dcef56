// Constraint rows (paper 5.1) and the distance constraint (5.2).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cbps/body.hpp"

namespace cbps {

/// One row of the system (5.1.3): ċ = j_c v_ab = upsilon, with cmin ≤ lambda ≤ cmax.
/// j_c = [j_a, j_b] ∈ R^{1×12} is kept as two 6-blocks over [v; omega] of body a and body b.
/// A block whose body index is -1 (the world, or a static body) has no columns in J (5.3).
struct Row {
  std::string label;        ///< human-readable, e.g. "distance 3 (world-ball3)"
  std::uint64_t id = 0;     ///< identity across steps, for warm starting lambda (7)
  int body_a = -1;          ///< body index of the first block, -1 for none
  int body_b = -1;          ///< body index of the second block, -1 for none
  Row6 j_a = Row6::Zero();  ///< [∂ċ/∂v_a, ∂ċ/∂omega_a]: dimensionless | m
  Row6 j_b = Row6::Zero();  ///< [∂ċ/∂v_b, ∂ċ/∂omega_b]: dimensionless | m
  double upsilon = 0.0;     ///< velocity bias (5.1.2), m/s
  double cmin = -kInf;      ///< lower bound on lambda (5.1), N
  double cmax = kInf;       ///< upper bound on lambda (5.1), N
  /// The bias of the position system of the improved push factor (8.1), m/s; equals upsilon
  /// when the push is in the one system.
  double upsilon_position = 0.0;
  int normal_row = -1;  ///< Coulomb friction (5.4): index of the contact row bounding it
  double mu = 0.0;  ///< and its coefficient: cmin = −mu lambda_normal, cmax = mu lambda_normal
  /// The contact manifold (4) whose contact or friction row this is, −1 for other rows. Block
  /// PGS solves the rows of one manifold together.
  int manifold = -1;
};

/// A distance constraint (5.2): |p_b − p_a| = l with p = x + r, r = R anchor.
/// Index -1 attaches that end to the world, the anchor then being a world point (m).
struct DistanceConstraint {
  std::string name;
  int a = -1;                    ///< body index of end a, -1 = world
  int b = -1;                    ///< body index of end b, -1 = world
  Vec3 anchor_a = Vec3::Zero();  ///< body-frame point on a (m), or world point if a = -1
  Vec3 anchor_b = Vec3::Zero();  ///< body-frame point on b (m), or world point if b = -1
  double l = 1.0;                ///< rest length, m (> 0)
};

/// The row form shared by distance (5.2.1), contact (5.3) and friction (5.4) rows: the rate of
/// separation along the unit direction n of point p_a on body a and point p_b on body b,
///   j_c = [ −nᵀ, −(r_a × n)ᵀ, nᵀ, (r_b × n)ᵀ ],   r_a = p_a − x_a, r_b = p_b − x_b,
/// with no block for an index of −1 (the world) or a static body. upsilon 0, bounds ±∞.
Row direction_row(
    const std::vector<Body>& bodies, int a, const Vec3& p_a, int b, const Vec3& p_b, const Vec3& n);

/// World position of one end of a distance constraint, m.
Vec3 anchor_point(const std::vector<Body>& bodies, int index, const Vec3& anchor);

/// Position constraint of 5.2 as a violation: c = |p_b − p_a| − l (5.2.2), m.
double distance_violation(const DistanceConstraint& dc, const std::vector<Body>& bodies);

/// The distance row (5.2.1) with its Baumgarte bias (5.2.3):
///   n = (p_b − p_a)/|p_b − p_a|,   j_c = [ −nᵀ, −(r_a × n)ᵀ, nᵀ, (r_b × n)ᵀ ],
///   upsilon = −beta (|p_b − p_a| − l) / dt   (m/s; a stretched link pulls its ends together),
///   cmin = −∞, cmax = +∞.
/// beta ∈ [0, 1] is dimensionless, dt in s. Ends on the world or on a static body get no block.
Row distance_row(const DistanceConstraint& dc,
                 const std::vector<Body>& bodies,
                 double beta,
                 double dt,
                 std::uint64_t id);

}  // namespace cbps
