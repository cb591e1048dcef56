// A constraint row (paper 5.1): j_c, its bias and its bounds; the form every row kind shares.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cbps/base/friction_law.hpp"
#include "cbps/base/row_kind.hpp"
#include "cbps/body/body.hpp"

namespace cbps {

/// The push factor's form (8): Baumgarte in the one system (5.2.3, 5.3), or the improved
/// technique of 8.1 (a velocity system without the push, whose v2 is kept, and a position
/// system with it, whose velocities only move the bodies).
enum class PushMode { Original, Improved };

/// One row of the system (5.1.3): ċ = j_c v_ab = upsilon, with cmin ≤ lambda ≤ cmax.
/// j_c = [j_a, j_b] ∈ R^{1×12} is kept as two 6-blocks over [v; omega] of body a and body b.
/// A block whose body index is -1 (the world, or a static body) has no columns in J (5.3).
struct Row {
  std::string label;                 ///< human-readable, e.g. "distance 3 (world-ball3)"
  std::uint64_t id = 0;              ///< identity across steps, for warm starting lambda (7)
  RowKind kind = RowKind::Distance;  ///< what it constrains (direction_row's caller says)
  int body_a = -1;                   ///< body index of the first block, -1 for none
  int body_b = -1;                   ///< body index of the second block, -1 for none
  Row6 j_a = Row6::Zero();           ///< [∂ċ/∂v_a, ∂ċ/∂omega_a]: dimensionless | m
  Row6 j_b = Row6::Zero();           ///< [∂ċ/∂v_b, ∂ċ/∂omega_b]: dimensionless | m
  /// Velocity bias (5.1.2) without the push term, m/s: restitution (8.2.1) and the closing
  /// of a contact gap; 0 for distance rows.
  double upsilon = 0.0;
  /// The push term alone, m/s: −beta C / dt for a distance row (5.2.3), beta d / dt for a
  /// contact at depth d ≥ 0 (5.3), else 0. Which system it enters is the push factor's form
  /// (PushMode): the one system (5.2.3, 5.3) or only the position system (8.1).
  double upsilon_push = 0.0;
  /// A contact row's depth d (4, 5.3), m: ≥ 0 overlapping, < 0 a gap inside the margin; 0 for
  /// other rows. The soft step softens only rows with d ≥ 0 (docs/schemes.md).
  double depth = 0.0;
  double cmin = -kInf;  ///< lower bound on lambda (5.1), N
  double cmax = kInf;   ///< upper bound on lambda (5.1), N
  /// A friction row (5.4): the index of its contact's row (the contact's normal), −1 for every
  /// other row.
  int normal_row = -1;
  /// The contact manifold (4) whose contact or friction row this is, −1 for other rows. Block
  /// PGS solves the rows of one manifold together.
  int manifold = -1;
  /// A contact row whose two friction rows follow it: its contact's friction coefficient and
  /// law (5.4, base/friction_law.hpp); mu −1 for every other row (a contact without friction
  /// rows, at mu = 0, included).
  double mu = -1.0;
  FrictionLaw law = FrictionLaw::PaperBox;
};

/// upsilon + upsilon_push, m/s: the bias of a system with the push in it (the one system of
/// 5.2.3 and 5.3, the position system of 8.1). A term that is exactly 0 leaves the other as it
/// is, sign of zero included, so a row without a push (or without a velocity bias) has the
/// same bias bit for bit whichever system it is in.
inline double with_push(double upsilon, double upsilon_push) {
  if (upsilon == 0.0) return upsilon_push;
  if (upsilon_push == 0.0) return upsilon;
  return upsilon_push + upsilon;
}

/// The row form shared by distance (5.2.1), contact (5.3) and friction (5.4) rows: the rate of
/// separation along the unit direction n of point p_a on body a and point p_b on body b,
///   j_c = [ −nᵀ, −(r_a × n)ᵀ, nᵀ, (r_b × n)ᵀ ],   r_a = p_a − x_a, r_b = p_b − x_b,
/// with no block for an index of −1 (the world) or a static body. upsilon 0, bounds ±∞; `kind`
/// is the caller's (distance_row, contact_row, friction_row).
Row direction_row(RowKind kind,
                  const std::vector<Body>& bodies,
                  int a,
                  const Vec3& p_a,
                  int b,
                  const Vec3& p_b,
                  const Vec3& n);

}  // namespace cbps
