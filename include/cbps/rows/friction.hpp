// Friction rows (paper 5.4): the tangent basis, the rows, and the paper's bound.
#pragma once

#include <vector>

#include "cbps/base/friction_law.hpp"
#include "cbps/collision/collision.hpp"
#include "cbps/rows/row.hpp"

namespace cbps {

/// Two unit tangents t1, t2 with (n, t1, t2) right-handed and orthonormal (5.4). Deterministic
/// and continuous in n: t1 is n × e normalised, for e the first world axis of x, y, z with
/// |n · e| < 0.6 (one exists for any unit n: 3 · 0.6² > 1); t2 = n × t1. Continuity matters for the
/// warm start of friction rows (7): taking the least aligned axis instead flips t1 by 90° whenever
/// a contact normal near +y tips from x to z, and last step's friction lambda then pushes the wrong
/// way.
void tangent_basis(const Vec3& n, Vec3& t1, Vec3& t2);

/// Friction row k = 1 or 2 (5.4) along tangent t at the same point: the contact row's form
/// with t for n, upsilon = 0, bounds ±bound (N).
Row friction_row(const Manifold& manifold,
                 const ContactPoint& point,
                 int k,
                 const Vec3& t,
                 double bound,
                 const std::vector<Body>& bodies);

/// The paper's friction bound mu m |g·n| (5.4), N: m is the sum of the pair's movable masses
/// divided over the manifold's points (static bodies add nothing); g in m/s².
double paper_friction_bound(const Manifold& manifold,
                            const std::vector<Body>& bodies,
                            double mu,
                            const Vec3& g);

}  // namespace cbps
