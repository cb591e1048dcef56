// Collision detection (paper 4): broad phase, narrow phase and the contact manifolds that the
// contact constraint (5.3) is built from.
//
// Symbols, as in 5.3:
//   n      unit contact normal, from body a to body b: moving b along +n separates the pair
//   p      world contact point, m: the midpoint between the two surfaces along n (halfway through
//          the overlap), so r_a = p − x_a and r_b = p − x_b both reach into the contact
//   depth  penetration depth d along n, m: d ≥ 0 when the surfaces overlap or touch (touching
//          surfaces give d = 0)
//   margin m, ≥ 0, default 0: points separated by up to margin are reported too, with
//          −margin ≤ d < 0. A small margin keeps resting contacts in the manifold when round-off
//          or the solver separates them slightly; the contact row (5.3) must expect d < 0 then.
//
// Feature ids (ContactPoint::feature) name the touching features, so they stay the same from step
// to step while the same features touch; a point's id (ContactPoint::id, the identity its rows
// warm-start by, 7) is its feature id unless contact persistence (persistence.hpp) continues it:
//   sphere–sphere, plane–sphere: 0.
//   box–sphere: the box's region of the sphere centre in the box frame: outside the box,
//     d_x + 3 d_y + 9 d_z with d_k = 0 below −h_k, 1 within ±h_k, 2 above +h_k; centre inside the
//     box, 27 + the face it leaves through.
//   plane–box: the box vertex.
//   box–box, face contact (n is a face normal): bits 24..31 = 1; bits 16..23 = reference face
//     (0..5 on body a, 6 + face on body b); bits 8..15 = incident face (0..5, on the other box);
//     bits 0..7 = the two lines whose crossing is the point: bit c (0..3) = incident edge c, from
//     incident corner c to c+1; bit 4+m = reference side plane m (0: +u_i, 1: +u_j, 2: −u_i,
//     3: −u_j, k the reference face's axis, (i, j) = (k+1, k+2) mod 3). An incident corner c that
//     survives clipping has bits c−1 and c; a clipped incident edge gives one edge and one side
//     bit; a reference corner two side bits. Incident corners within 1e-6 h of a side plane are
//     kept unclipped, so equal boxes stacked exactly keep their ids under round-off.
//   box–box, edge–edge contact: bits 24..31 = 2; bits 8..15 = edge of body a; bits 0..7 = edge of
//     body b.
// Box numbering, in the box frame (axes u_0, u_1, u_2 = x, y, z), half extents h:
//   vertex v = 0..7: the corner (±h_x, ±h_y, ±h_z), bit k of v set for +h_k;
//   face 2k + s: the face normal to u_k, s = 1 at +h_k, s = 0 at −h_k;
//   corner c = 0..3 of face (k, s): (−,−), (+,−), (+,+), (−,+) along (u_i, u_j);
//   edge 4k + b_i + 2 b_j: the edge along u_k at the sides b_i, b_j (1 for +) of u_i, u_j.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "cbps/body/body.hpp"

namespace cbps {

inline constexpr int kMaxContactPoints = 4;

/// One point of a contact manifold (4, 5.3).
struct ContactPoint {
  Vec3 p = Vec3::Zero();      ///< world point halfway through the overlap along n, m
  double depth = 0.0;         ///< penetration d along n, m (≥ 0; ≥ −margin with a margin)
  std::uint32_t feature = 0;  ///< the touching features (see the top of this file)
  /// Identity across steps, for warm starting lambda (7): the contact rows' ids are made from it
  /// (contact_row_id). collide() sets it to `feature`; contact persistence
  /// (collision/persistence.hpp) replaces it with the id of the last step's point it continues.
  std::uint64_t id = 0;
};

/// The contact manifold of bodies a and b (4): one normal n from a to b, 1 to 4 points.
struct Manifold {
  int a = -1;                        ///< index of body a (the caller's first body)
  int b = -1;                        ///< index of body b
  Vec3 n = Vec3::Zero();             ///< unit normal from a to b
  std::vector<ContactPoint> points;  ///< at most kMaxContactPoints
};

// Narrow phase, one function per pair of shapes (4). Each fills out.n (from its first argument to
// its second) and out.points, and returns true when at least one point has d ≥ −margin; otherwise
// it returns false with out.points empty. out.a and out.b stay −1: collide() sets them.

/// Spheres: n = (x_b − x_a)/|x_b − x_a| (+y for coincident centres), d = r_a + r_b − |x_b − x_a|,
/// p midway between x_a + r_a n and x_b − r_b n.
bool collide_sphere_sphere(const Body& a, const Body& b, Manifold& out, double margin = 0.0);

/// Plane (static half-space) and sphere: n = the plane's outward normal, d = radius − height of
/// the centre above the plane, p midway between the sphere's lowest point and the plane.
bool collide_plane_sphere(const Body& plane,
                          const Body& sphere,
                          Manifold& out,
                          double margin = 0.0);

/// Box and sphere: n from the closest box point to the centre, d = radius − distance; a centre
/// inside the box leaves through the face of least penetration: n = that face's normal,
/// d = radius + distance of the centre below that face. p midway between the box surface point
/// and the sphere's surface point x − radius n.
bool collide_box_sphere(const Body& box, const Body& sphere, Manifold& out, double margin = 0.0);

/// Plane and box: the box vertices at most margin above the plane, each with d = its depth
/// below the plane and p halfway between it and the plane; n = the plane's outward normal. More
/// than 4 are reduced to the deepest and 3 spread around it. A box lying flat gives its 4 bottom
/// corners, on an edge 2, on a vertex 1.
bool collide_plane_box(const Body& plane, const Body& box, Manifold& out, double margin = 0.0);

/// Box and box, by the separating axis test (4) over the 15 axes: the 3 face normals of each box
/// and the 9 edge cross products (near-parallel edge pairs skipped). The axis of least
/// penetration is n, except that face axes are preferred for stable resting contacts: b's face
/// is chosen over a's only when its separation is larger by 5 % of |separation| plus 1e-6 of the
/// boxes' size, and an edge axis over the best face likewise.
///   Face axis (4): the reference face is the box face with normal n; the incident face is the
///   other box's face most anti-parallel to it. The incident face is clipped against the
///   reference face's 4 side planes (Sutherland–Hodgman); the points below the reference face
///   (d ≥ −margin) are kept, each with its own d and moved up by d/2, at most 4 (the deepest and
///   3 spread around it).
///   Edge axis: one point midway between the closest points of the two edges, d = −separation.
bool collide_box_box(const Body& a, const Body& b, Manifold& out, double margin = 0.0);

/// Narrow-phase dispatch (4) for bodies a and b, indices index_a and index_b, any kinds in any
/// order: swaps the arguments for the pair functions above when needed and flips n, so that n
/// always points from a to b. Two static bodies, and two planes, never collide (false). Sets
/// out.a = index_a, out.b = index_b, and each point's id to its feature.
bool collide(
    const Body& a, const Body& b, int index_a, int index_b, Manifold& out, double margin = 0.0);

/// A world axis-aligned bounding box, m. A plane's is infinite.
struct Aabb {
  Vec3 min = Vec3::Zero();
  Vec3 max = Vec3::Zero();
};

/// The body's world AABB: x ± radius for a sphere, x ± |R| h for a box (|R| elementwise).
Aabb world_aabb(const Body& body);

/// True when the gap between a and b is at most margin (m, ≥ 0) along every world axis; touching
/// boxes overlap.
bool aabbs_overlap(const Aabb& a, const Aabb& b, double margin = 0.0);

/// Broad phase (4, step 1): candidate pairs (a, b), a < b, sorted ascending. Spheres and boxes
/// are paired by sort-and-sweep on their world AABBs along the world axis over which the AABB
/// centres spread most, with aabbs_overlap(·, ·, margin). Each plane is paired with every sphere
/// or box whose support point along −n (its lowest point) lies at most margin above it, in
/// O(bodies × planes). Pairs of two static bodies, or of two planes, are never returned.
std::vector<std::pair<int, int>> broad_phase(const std::vector<Body>& bodies, double margin = 0.0);

/// Narrow phase (4, step 2): collide() on each candidate pair in its order; the manifolds of the
/// pairs in contact.
std::vector<Manifold> narrow_phase(const std::vector<Body>& bodies,
                                   const std::vector<std::pair<int, int>>& pairs,
                                   double margin = 0.0);

/// Collision detection (4): broad_phase, then narrow_phase; the manifolds of the pairs in
/// contact, in ascending (a, b) order.
std::vector<Manifold> detect_contacts(const std::vector<Body>& bodies, double margin = 0.0);

}  // namespace cbps
