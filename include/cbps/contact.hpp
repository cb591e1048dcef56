// Contact (5.3) and friction (5.4) rows from collision manifolds (4), restitution (8.2.1).
#pragma once

#include <cstdint>
#include <vector>

#include "cbps/collision.hpp"
#include "cbps/constraint.hpp"

namespace cbps {

/// Two unit tangents t1, t2 with (n, t1, t2) right-handed and orthonormal (5.4). Deterministic
/// and continuous in n: t1 is n × e normalised, for e the first world axis of x, y, z with
/// |n · e| < 0.6 (one exists for any unit n: 3 · 0.6² > 1); t2 = n × t1. Continuity matters for the
/// warm start of friction rows (7): taking the least aligned axis instead flips t1 by 90° whenever
/// a contact normal near +y tips from x to z, and last step's friction lambda then pushes the wrong
/// way.
void tangent_basis(const Vec3& n, Vec3& t1, Vec3& t2);

/// Relative velocity of a row at the start of the step, j_c v1 (8.2.1), m/s.
double row_velocity(const Row& row, const std::vector<Body>& bodies);

/// The contact row (5.3) of one manifold point: j_c = [−nᵀ, −(r_a × n)ᵀ, nᵀ, (r_b × n)ᵀ] with
/// r_a = p − x_a, r_b = p − x_b; cmin = 0, cmax = +∞ (push only). upsilon is left 0: the caller
/// adds the push term and restitution (contact_bias). Static bodies get no block.
Row contact_row(const Manifold& m, const ContactPoint& point, const std::vector<Body>& bodies);

/// Friction row k = 1 or 2 (5.4) along tangent t at the same point: the contact row's form
/// with t for n, upsilon = 0, bounds ±bound (N).
Row friction_row(const Manifold& m,
                 const ContactPoint& point,
                 int k,
                 const Vec3& t,
                 double bound,
                 const std::vector<Body>& bodies);

/// The paper's friction bound mu m |g·n| (5.4), N: m is the sum of the pair's movable masses
/// divided over the manifold's points (static bodies add nothing); g in m/s².
double paper_friction_bound(const Manifold& m,
                            const std::vector<Body>& bodies,
                            double mu,
                            const Vec3& g);

/// The bias of a contact row (5.3, 8.2.1), m/s:
///   push        beta d / dt for d ≥ 0 (separate the bodies by beta of the depth in one step);
///   gap         d / dt for a margin point with d < 0: the gap may close in this step, no more
///               (not a push: it is there with or without with_push);
///   restitution −epsilon j_c v1 when the bodies approach faster than threshold (j_c v1 <
///               −threshold), else 0, so resting contacts do not bounce. At a gap it is the
///               whole bias, and only if the approach closes the gap within the step
///               (j_c v1 < d / dt): the impact is then this step's.
/// with_push = false leaves the push out (the velocity system of 8.1).
double contact_bias(double depth,
                    double approach_velocity,
                    double beta,
                    double dt,
                    double epsilon,
                    double threshold,
                    bool with_push);

/// The row id of a contact (k = 0) or friction (k = 1, 2) row: the pair, the point's feature
/// and k, hashed so that a point keeps its id from step to step (warm starting, 7).
std::uint64_t contact_row_id(int a, int b, std::uint32_t feature, int k);

}  // namespace cbps
