// Contact rows (paper 5.3) from collision manifolds (4), with restitution (8.2.1).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cbps/collision/collision.hpp"
#include "cbps/rows/row.hpp"

namespace cbps {

/// Relative velocity of a row at the start of the step, j_c v1 (8.2.1), m/s.
double row_velocity(const Row& row, const std::vector<Body>& bodies);

/// The contact row (5.3) of one manifold point: j_c = [−nᵀ, −(r_a × n)ᵀ, nᵀ, (r_b × n)ᵀ] with
/// r_a = p − x_a, r_b = p − x_b; cmin = 0, cmax = +∞ (push only). upsilon and upsilon_push are
/// left 0: the row stage sets them (contact_bias, contact_push). Static bodies get no block.
Row contact_row(const Manifold& manifold,
                const ContactPoint& point,
                const std::vector<Body>& bodies);

/// The velocity bias of a contact row (5.3, 8.2.1), m/s, without the push term:
///   gap         d / dt for a margin point with d < 0: the gap may close in this step, no more;
///   restitution −epsilon j_c v1 when the bodies approach faster than threshold (j_c v1 <
///               −threshold), else 0, so resting contacts do not bounce. At a gap it is the
///               whole bias, and only if the approach closes the gap within the step
///               (j_c v1 < d / dt): the impact is then this step's.
/// The push is contact_push; with_push adds it where the push factor's form puts it (8.1).
double contact_bias(
    double depth, double approach_velocity, double dt, double epsilon, double threshold);

/// The push term of a contact row (5.3), m/s: beta d / dt for depth d ≥ 0 (separate the bodies
/// by beta of the depth in one step), 0 at a gap (d < 0).
double contact_push(double depth, double beta, double dt);

/// The pair's body names "a-b", for the labels of its contact and friction rows.
std::string pair_label(const Manifold& manifold, const std::vector<Body>& bodies);

/// "a-b point K": the pair and the point's place K (0-based) in its manifold, the part of a
/// contact row's label ("contact a-b point K") and its friction rows' ("friction a-b point K
/// t1"). Readable on a page and distinct within a step; the point's identity from step to step
/// is its row id (contact_row_id), not its label.
std::string point_label(const Manifold& manifold,
                        const ContactPoint& point,
                        const std::vector<Body>& bodies);

/// The row id of a contact (k = 0) or friction (k = 1, 2) row: the pair, the point's id
/// (ContactPoint::id) and k, hashed so that a point keeps its rows' ids from step to step
/// (warm starting, 7).
std::uint64_t contact_row_id(int a, int b, std::uint64_t point_id, int k);

}  // namespace cbps
