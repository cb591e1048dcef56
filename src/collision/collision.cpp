// Narrow phase (paper 4): one function per pair of shapes, the contact manifolds for the contact
// constraint (5.3), and the dispatch. Conventions and feature ids: collision.hpp.
#include "cbps/collision/collision.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <optional>

namespace cbps {

namespace {

// Tolerances, each relative to a length of the pair (so a scene in cm behaves as one in m).
constexpr double kTie = 1e-9;        // candidates within this are equal: the lower index wins
constexpr double kPreferRel = 0.05;  // SAT: b's face over a's, an edge over a face, only when
constexpr double kPreferAbs = 1e-6;  //   better by 5 % of |separation| + 1e-6 of the box size
constexpr double kClip = 1e-6;       // clipping keeps incident points this far outside a side
constexpr double kParallel = 1e-6;   // |u_a × u_b| below this: parallel edges, no edge axis

constexpr std::uint32_t kFaceContact = 1u << 24;  // feature tags of box–box contacts
constexpr std::uint32_t kEdgeContact = 2u << 24;

/// A box in world coordinates: centre c, axes u_k (the columns of R), half extents h.
struct OrientedBox {
  Vec3 c;
  Mat3 R;
  Vec3 h;

  explicit OrientedBox(const Body& body) : c(body.x), R(body.R()), h(body.shape.half_extents) {}
  Vec3 u(int k) const { return R.col(k); }
  /// Vertex v = 0..7 in world coordinates: bit k of v set for +h_k, clear for −h_k.
  Vec3 vertex(int v) const {
    const Vec3 local((v & 1) ? h.x() : -h.x(), (v & 2) ? h.y() : -h.y(), (v & 4) ? h.z() : -h.z());
    return c + R * local;
  }
  /// Half the length of the box's projection on a unit axis L: Σ_k h_k |u_k · L|, m.
  double radius(const Vec3& L) const { return (R.transpose() * L).cwiseAbs().dot(h); }
};

/// The plane's outward normal R (0, 1, 0) (body.hpp).
Vec3 plane_normal(const Body& plane) { return plane.q * Vec3::UnitY(); }

/// Vertex index of corner c = 0..3 of face (k, s): corners (−,−), (+,−), (+,+), (−,+) in
/// (u_i, u_j), (i, j) = (k+1, k+2) mod 3; s = 1 for the face at +h_k.
int face_corner(int k, int s, int c) {
  const int b_i = (c == 1 || c == 2) ? 1 : 0;
  const int b_j = c >= 2 ? 1 : 0;
  return (s << k) | (b_i << ((k + 1) % 3)) | (b_j << ((k + 2) % 3));
}

/// Reduces points to kMaxContactPoints: the deepest, the one farthest from it across n, the one
/// spanning the largest triangle with these two, and the largest on the other side of their
/// line. Kept points stay in their order. scale: a length of the pair, m, for ties.
void keep_four(std::vector<ContactPoint>& points, const Vec3& n, double scale) {
  const int count = static_cast<int>(points.size());
  if (count <= kMaxContactPoints) return;
  const double tie = kTie * scale;
  const double tie2 = kTie * scale * scale;
  auto at = [&](int i) -> const ContactPoint& { return points[static_cast<std::size_t>(i)]; };
  auto across = [&](int i, int j) {  // p_j − p_i projected on the plane ⟂ n
    const Vec3 d = at(j).p - at(i).p;
    return Vec3(d - n * n.dot(d));
  };
  std::vector<char> chosen(points.size(), 0);
  // Chooses the unchosen index maximising score (the lowest index among near-ties).
  auto choose = [&](auto score, double tolerance) {
    int i_best = -1;
    double s_best = 0.0;
    for (int i = 0; i < count; ++i) {
      if (chosen[static_cast<std::size_t>(i)]) continue;
      const double s = score(i);
      if (i_best < 0 || s > s_best + tolerance) i_best = i, s_best = s;
    }
    chosen[static_cast<std::size_t>(i_best)] = 1;
    return std::pair{i_best, s_best};
  };

  const int i1 = choose([&](int i) { return at(i).depth; }, tie).first;
  const int i2 = choose([&](int i) { return across(i1, i).squaredNorm(); }, tie2).first;
  const Vec3 e12 = across(i1, i2);
  auto area = [&](int i) { return e12.cross(across(i1, i)).dot(n); };  // twice the signed area
  const int i3 = choose([&](int i) { return std::abs(area(i)); }, tie2).first;
  const double side = area(i3) >= 0.0 ? -1.0 : 1.0;  // the other side of the line i1–i2
  const auto [i4, area4] = choose([&](int i) { return side * area(i); }, tie2);
  if (area4 <= tie2) {  // nothing on the other side: the point farthest from the three
    chosen[static_cast<std::size_t>(i4)] = 0;
    choose(
        [&](int i) {
          return std::min({across(i1, i).squaredNorm(),
                           across(i2, i).squaredNorm(),
                           across(i3, i).squaredNorm()});
        },
        tie2);
  }

  std::vector<ContactPoint> kept;
  for (int i = 0; i < count; ++i)
    if (chosen[static_cast<std::size_t>(i)]) kept.push_back(at(i));
  points = std::move(kept);
}

/// A vertex of the polygon being clipped, with the lines it lies on (feature mask, collision.hpp).
struct ClipVertex {
  Vec3 q;
  std::uint8_t lines = 0;
};

/// A convex polygon of at most 16 vertices (a quad clipped by 4 planes has at most 8).
struct Polygon {
  std::array<ClipVertex, 16> v{};
  int count = 0;
  void push(const ClipVertex& w) {
    if (count < static_cast<int>(v.size())) v[static_cast<std::size_t>(count++)] = w;
  }
  const ClipVertex& operator[](int i) const { return v[static_cast<std::size_t>(i)]; }
};

/// Sutherland–Hodgman: the part of the polygon with m·q − offset ≤ 0, where points outside by at
/// most tol are kept as they are (not moved), so that a corner exactly on a side plane keeps its
/// feature under round-off. A point made on an edge crossing the plane lies on the edge's line
/// (the bit both ends share) and on the plane (side_bit).
Polygon clip(const Polygon& in, const Vec3& m, double offset, std::uint8_t side_bit, double tol) {
  Polygon out;
  for (int k = 0; k < in.count; ++k) {
    const ClipVertex& P = in[k];
    const ClipVertex& Q = in[(k + 1) % in.count];
    const double d_P = m.dot(P.q) - offset;
    const double d_Q = m.dot(Q.q) - offset;
    if (d_P <= tol) out.push(P);
    if ((d_P < -tol && d_Q > tol) || (d_P > tol && d_Q < -tol)) {
      const double t = d_P / (d_P - d_Q);
      out.push({P.q + t * (Q.q - P.q), static_cast<std::uint8_t>((P.lines & Q.lines) | side_bit)});
    }
  }
  return out;
}

/// Face contact of a box pair (4): reference face (axis k of ref, outward normal n_ref pointing
/// towards inc) and the face of inc most anti-parallel to it. The incident face is clipped against
/// the 4 side planes of the reference face; points below the reference face (depth ≥ −margin) are
/// kept, each moved halfway up through the overlap. ref_face: the reference face's id (0..11).
void face_contact(const OrientedBox& ref,
                  int k,
                  const Vec3& n_ref,
                  std::uint32_t ref_face,
                  const OrientedBox& inc,
                  double margin,
                  std::vector<ContactPoint>& points) {
  // Incident face: axis j of inc with the largest |u_j · n_ref|, on the side facing ref.
  int j = 0;
  for (int l = 1; l < 3; ++l)
    if (std::abs(inc.u(l).dot(n_ref)) > std::abs(inc.u(j).dot(n_ref)) + kTie) j = l;
  const int s_inc = inc.u(j).dot(n_ref) > 0.0 ? 0 : 1;
  Polygon polygon;
  for (int c = 0; c < 4; ++c) {
    const auto lines = static_cast<std::uint8_t>((1u << ((c + 3) % 4)) | (1u << c));
    polygon.push({inc.vertex(face_corner(j, s_inc, c)), lines});
  }

  // Side planes m = 0..3 of the reference face: +u_i, +u_j, −u_i, −u_j at distance h from c.
  const int axis_i = (k + 1) % 3;
  const int axis_j = (k + 2) % 3;
  const double tol = kClip * ref.h.maxCoeff();
  for (int m = 0; m < 4; ++m) {
    const int axis = m % 2 == 0 ? axis_i : axis_j;
    const Vec3 normal = (m < 2 ? 1.0 : -1.0) * ref.u(axis);
    const auto side_bit = static_cast<std::uint8_t>(1u << (4 + m));
    polygon = clip(polygon, normal, normal.dot(ref.c) + ref.h[axis], side_bit, tol);
  }

  const std::uint32_t inc_face = static_cast<std::uint32_t>(2 * j + s_inc);
  for (int v = 0; v < polygon.count; ++v) {
    const Vec3& q = polygon[v].q;
    const double depth = ref.h[k] - n_ref.dot(q - ref.c);  // below the reference face
    if (depth < -margin) continue;
    points.push_back({q + 0.5 * depth * n_ref,
                      depth,
                      kFaceContact | (ref_face << 16) | (inc_face << 8) | polygon[v].lines});
  }
  keep_four(points, n_ref, ref.h.maxCoeff() + inc.h.maxCoeff());
}

/// The edge of a box along axis k on the side facing direction `toward`: its id (collision.hpp)
/// and end points.
struct Edge {
  std::uint32_t id;
  Vec3 p0;
  Vec3 p1;
};
Edge facing_edge(const OrientedBox& box, int k, const Vec3& toward) {
  const int i = (k + 1) % 3;
  const int j = (k + 2) % 3;
  const int b_i = box.u(i).dot(toward) > 0.0 ? 1 : 0;
  const int b_j = box.u(j).dot(toward) > 0.0 ? 1 : 0;
  const int v0 = (b_i << i) | (b_j << j);
  return {
      static_cast<std::uint32_t>(4 * k + b_i + 2 * b_j), box.vertex(v0), box.vertex(v0 | (1 << k))};
}

/// Closest points c_1 on segment [p0, p1] and c_2 on [q0, q1] (non-parallel segments): minimise
/// |p0 + s d_1 − q0 − t d_2|² over s, t ∈ [0, 1].
std::pair<Vec3, Vec3> closest_points(const Edge& e1, const Edge& e2) {
  const Vec3 d_1 = e1.p1 - e1.p0;
  const Vec3 d_2 = e2.p1 - e2.p0;
  const Vec3 r = e1.p0 - e2.p0;
  const double a = d_1.dot(d_1), b = d_1.dot(d_2), e = d_2.dot(d_2);
  const double c = d_1.dot(r), f = d_2.dot(r);
  const double denom = a * e - b * b;  // > 0 for non-parallel segments
  double s = std::clamp((b * f - c * e) / denom, 0.0, 1.0);
  double t = (b * s + f) / e;
  if (t < 0.0) {
    t = 0.0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else if (t > 1.0) {
    t = 1.0;
    s = std::clamp((b - c) / a, 0.0, 1.0);
  }
  return {e1.p0 + s * d_1, e2.p0 + t * d_2};
}

/// A candidate separating axis (4): unit L from a to b, separation s = |d·L| − r_a(L) − r_b(L).
struct Axis {
  enum class Kind { FaceA, FaceB, Edge };
  Kind kind = Kind::FaceA;
  int i = 0;  ///< face axis (of a or b), or the edge axis of a
  int j = 0;  ///< the edge axis of b
  Vec3 L = Vec3::Zero();
  double s = -kInf;  ///< m; > 0 separated
};

/// The separating axis test (4) over the 15 axes: nullopt when some axis has s > margin, else the
/// axis of largest s. Within a kind near-ties go to the lower index; the preferred kind (a's
/// faces, then b's faces, then edges) is left only for a clearly larger s.
std::optional<Axis> least_separated_axis(const OrientedBox& a,
                                         const OrientedBox& b,
                                         double margin) {
  const Vec3 d = b.c - a.c;
  const double scale = a.h.maxCoeff() + b.h.maxCoeff();
  auto make = [&](Vec3 L, Axis::Kind kind, int i, int j) {
    if (d.dot(L) < 0.0) L = -L;  // orient from a to b
    return Axis{kind, i, j, L, d.dot(L) - a.radius(L) - b.radius(L)};
  };
  auto larger = [&](double s, double s_best) { return s > s_best + kTie * scale; };
  auto clearly_larger = [&](double s, double s_best) {
    return s > s_best + kPreferRel * std::abs(s_best) + kPreferAbs * scale;
  };
  Axis face_a, face_b, edge;
  for (int i = 0; i < 3; ++i) {
    const Axis L = make(a.u(i), Axis::Kind::FaceA, i, 0);
    if (L.s > margin) return std::nullopt;
    if (larger(L.s, face_a.s)) face_a = L;
  }
  for (int j = 0; j < 3; ++j) {
    const Axis L = make(b.u(j), Axis::Kind::FaceB, j, 0);
    if (L.s > margin) return std::nullopt;
    if (larger(L.s, face_b.s)) face_b = L;
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const Vec3 cross = a.u(i).cross(b.u(j));
      const double length = cross.norm();
      if (length < kParallel) continue;  // parallel edges: their axis is a face axis
      const Axis L = make(cross / length, Axis::Kind::Edge, i, j);
      if (L.s > margin) return std::nullopt;
      if (larger(L.s, edge.s)) edge = L;
    }
  }
  Axis best = face_a;
  if (clearly_larger(face_b.s, best.s)) best = face_b;
  if (clearly_larger(edge.s, best.s)) best = edge;
  return best;
}

/// The shape-pair functions in canonical order (rank of the first ≤ rank of the second).
int rank(Shape::Kind kind) {
  switch (kind) {
    case Shape::Kind::Plane:
      return 0;
    case Shape::Kind::Box:
      return 1;
    case Shape::Kind::Sphere:
      return 2;
  }
  return 2;
}

bool collide_ordered(const Body& a, const Body& b, Manifold& out, double margin) {
  using K = Shape::Kind;
  const K ka = a.shape.kind;
  const K kb = b.shape.kind;
  if (ka == K::Plane && kb == K::Sphere) return collide_plane_sphere(a, b, out, margin);
  if (ka == K::Plane && kb == K::Box) return collide_plane_box(a, b, out, margin);
  if (ka == K::Box && kb == K::Box) return collide_box_box(a, b, out, margin);
  if (ka == K::Box && kb == K::Sphere) return collide_box_sphere(a, b, out, margin);
  if (ka == K::Sphere && kb == K::Sphere) return collide_sphere_sphere(a, b, out, margin);
  out = Manifold{};
  return false;  // plane–plane
}

}  // namespace

bool collide_sphere_sphere(const Body& a, const Body& b, Manifold& out, double margin) {
  out = Manifold{};
  const Vec3 x_ab = b.x - a.x;
  const double dist = x_ab.norm();
  const double depth = a.shape.radius + b.shape.radius - dist;
  if (depth < -margin) return false;
  // Coincident centres have no direction; any unit n separates them.
  out.n = dist > 0.0 ? Vec3(x_ab / dist) : Vec3::UnitY();
  const Vec3 surface_a = a.x + a.shape.radius * out.n;
  const Vec3 surface_b = b.x - b.shape.radius * out.n;
  out.points.push_back({0.5 * (surface_a + surface_b), depth, 0});
  return true;
}

bool collide_plane_sphere(const Body& plane, const Body& sphere, Manifold& out, double margin) {
  out = Manifold{};
  out.n = plane_normal(plane);
  const double height = out.n.dot(sphere.x - plane.x);  // of the centre above the plane
  const double depth = sphere.shape.radius - height;
  if (depth < -margin) return false;
  // Midway between the sphere's lowest point (height − radius) and the plane (height 0).
  out.points.push_back({sphere.x - 0.5 * (sphere.shape.radius + height) * out.n, depth, 0});
  return true;
}

bool collide_box_sphere(const Body& box_body, const Body& sphere, Manifold& out, double margin) {
  out = Manifold{};
  const OrientedBox box(box_body);
  const double radius = sphere.shape.radius;
  const Vec3 s = box.R.transpose() * (sphere.x - box.c);  // centre in the box frame
  Vec3 closest = s.cwiseMax(-box.h).cwiseMin(box.h);      // closest box point, box frame
  double depth = 0.0;
  std::uint32_t feature = 0;
  if (closest != s) {  // centre outside: n along centre − closest point
    const Vec3 d = s - closest;
    const double dist = d.norm();
    depth = radius - dist;
    if (depth < -margin) return false;
    out.n = box.R * (d / dist);
    for (int k = 2; k >= 0; --k)
      feature = 3 * feature + (s[k] < -box.h[k] ? 0 : s[k] > box.h[k] ? 2 : 1);
  } else {  // centre inside: out through the face of least penetration h_k − |s_k|
    int k = 0;
    for (int l = 1; l < 3; ++l)
      if (box.h[l] - std::abs(s[l]) < box.h[k] - std::abs(s[k]) - kTie * box.h.maxCoeff()) k = l;
    const double sign = s[k] >= 0.0 ? 1.0 : -1.0;
    closest[k] = sign * box.h[k];
    depth = radius + box.h[k] - std::abs(s[k]);
    out.n = sign * box.u(k);
    feature = static_cast<std::uint32_t>(27 + 2 * k + (sign > 0.0 ? 1 : 0));
  }
  const Vec3 surface_box = box.c + box.R * closest;
  const Vec3 surface_sphere = sphere.x - radius * out.n;
  out.points.push_back({0.5 * (surface_box + surface_sphere), depth, feature});
  return true;
}

bool collide_plane_box(const Body& plane, const Body& box_body, Manifold& out, double margin) {
  out = Manifold{};
  const OrientedBox box(box_body);
  out.n = plane_normal(plane);
  for (int v = 0; v < 8; ++v) {
    const Vec3 w = box.vertex(v);
    const double depth = -out.n.dot(w - plane.x);  // how far the vertex is below the plane
    if (depth < -margin) continue;
    out.points.push_back({w + 0.5 * depth * out.n, depth, static_cast<std::uint32_t>(v)});
  }
  keep_four(out.points, out.n, box.h.maxCoeff());
  return !out.points.empty();
}

// Box–box (4). Separating axis test: for a unit axis L oriented from a to b, with d = x_b − x_a,
//   s(L) = d·L − r_a(L) − r_b(L),   r(L) = Σ_k h_k |u_k · L|,
// is the gap between the boxes' projections on L; the boxes are apart when any s(L) > 0 (> margin),
// and otherwise the axis of largest s is the normal n, with penetration −s. Candidates: u_a,k,
// u_b,k and u_a,i × u_b,j. Then the manifold of a face axis (clipping) or of an edge axis (one
// point between the edges' closest points).
bool collide_box_box(const Body& a_body, const Body& b_body, Manifold& out, double margin) {
  out = Manifold{};
  const OrientedBox a(a_body);
  const OrientedBox b(b_body);
  const std::optional<Axis> best = least_separated_axis(a, b, margin);
  if (!best) return false;
  out.n = best->L;
  if (best->kind == Axis::Kind::FaceA) {
    const auto ref_face =
        static_cast<std::uint32_t>(2 * best->i + (best->L.dot(a.u(best->i)) > 0.0));
    face_contact(a, best->i, best->L, ref_face, b, margin, out.points);
  } else if (best->kind == Axis::Kind::FaceB) {
    const Vec3 n_ref = -best->L;  // b's face, facing a
    const auto ref_face =
        static_cast<std::uint32_t>(6 + 2 * best->i + (n_ref.dot(b.u(best->i)) > 0.0));
    face_contact(b, best->i, n_ref, ref_face, a, margin, out.points);
  } else {  // edge–edge: the edges of a and b that face each other across n
    const Edge e_a = facing_edge(a, best->i, best->L);
    const Edge e_b = facing_edge(b, best->j, -best->L);
    const auto [c_a, c_b] = closest_points(e_a, e_b);
    out.points.push_back({0.5 * (c_a + c_b), -best->s, kEdgeContact | (e_a.id << 8) | e_b.id});
  }
  return !out.points.empty();
}

bool collide(const Body& a, const Body& b, int index_a, int index_b, Manifold& out, double margin) {
  out = Manifold{};
  bool hit = false;
  if (!(a.is_static && b.is_static)) {
    if (rank(a.shape.kind) <= rank(b.shape.kind)) {
      hit = collide_ordered(a, b, out, margin);
    } else {
      hit = collide_ordered(b, a, out, margin);
      out.n = -out.n;
    }
  }
  out.a = index_a;
  out.b = index_b;
  for (ContactPoint& point : out.points) point.id = point.feature;
  return hit;
}

}  // namespace cbps
