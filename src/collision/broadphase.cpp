// Broad phase (paper 4, step 1): candidate pairs by sort-and-sweep on world AABBs, planes apart;
// and detect_contacts, broad phase then narrow phase.
#include <algorithm>
#include <numeric>

#include "cbps/collision/collision.hpp"

namespace cbps {

Aabb world_aabb(const Body& body) {
  Vec3 half = Vec3::Zero();  // half widths along the world axes, m
  switch (body.shape.kind) {
    case Shape::Kind::Sphere:
      half = Vec3::Constant(body.shape.radius);
      break;
    case Shape::Kind::Box:  // projection of the box on world axis k: Σ_l |R_kl| h_l
      half = body.R().cwiseAbs() * body.shape.half_extents;
      break;
    case Shape::Kind::Plane:
      return {Vec3::Constant(-kInf), Vec3::Constant(kInf)};
  }
  return {body.x - half, body.x + half};
}

bool aabbs_overlap(const Aabb& a, const Aabb& b, double margin) {
  for (int k = 0; k < 3; ++k) {
    if (b.min[k] > a.max[k] + margin || a.min[k] > b.max[k] + margin) return false;
  }
  return true;
}

namespace {

/// True when the body's support point along −n (its lowest point) is at most margin above the
/// plane: height of x above the plane minus the body's extent along n.
bool reaches_plane(const Body& plane, const Body& body, double margin) {
  const Vec3 n = plane.q * Vec3::UnitY();
  const double height = n.dot(body.x - plane.x);
  const double extent = body.shape.kind == Shape::Kind::Sphere
                            ? body.shape.radius
                            : (body.R().transpose() * n).cwiseAbs().dot(body.shape.half_extents);
  return height - extent <= margin;
}

/// The world axis along which the AABB centres spread most (largest variance).
int sweep_axis(const std::vector<Aabb>& boxes) {
  Vec3 sum = Vec3::Zero();
  Vec3 sum2 = Vec3::Zero();
  for (const Aabb& box : boxes) {
    const Vec3 centre = 0.5 * (box.min + box.max);
    sum += centre;
    sum2 += centre.cwiseProduct(centre);
  }
  const double count = static_cast<double>(boxes.size());
  const Vec3 variance = sum2 / count - (sum / count).cwiseProduct(sum / count);
  int axis = 0;
  variance.maxCoeff(&axis);
  return axis;
}

}  // namespace

std::vector<std::pair<int, int>> broad_phase(const std::vector<Body>& bodies, double margin) {
  auto body = [&](int i) -> const Body& { return bodies[static_cast<std::size_t>(i)]; };
  auto both_static = [&](int i, int j) { return body(i).is_static && body(j).is_static; };
  auto ordered = [](int i, int j) { return std::pair{std::min(i, j), std::max(i, j)}; };

  std::vector<int> planes, solids;
  for (int i = 0; i < static_cast<int>(bodies.size()); ++i)
    (body(i).shape.kind == Shape::Kind::Plane ? planes : solids).push_back(i);

  std::vector<std::pair<int, int>> pairs;
  // Planes have no finite AABB: test each sphere or box against each plane directly.
  for (const int i : planes) {
    for (const int j : solids) {
      if (!both_static(i, j) && reaches_plane(body(i), body(j), margin))
        pairs.push_back(ordered(i, j));
    }
  }

  // Sort and sweep: order the AABBs by their lower bound along one axis; each box then meets only
  // the boxes that start before it ends, and the other two axes are tested for those.
  if (!solids.empty()) {
    std::vector<Aabb> boxes;
    boxes.reserve(solids.size());
    for (const int i : solids) boxes.push_back(world_aabb(body(i)));
    const int axis = sweep_axis(boxes);
    std::vector<std::size_t> order(solids.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(), [&](std::size_t k, std::size_t l) {
      return boxes[k].min[axis] < boxes[l].min[axis] ||
             (boxes[k].min[axis] == boxes[l].min[axis] && k < l);
    });
    for (std::size_t k = 0; k < order.size(); ++k) {
      const Aabb& box_k = boxes[order[k]];
      for (std::size_t l = k + 1; l < order.size(); ++l) {
        const Aabb& box_l = boxes[order[l]];
        if (box_l.min[axis] > box_k.max[axis] + margin) break;  // and so do all later ones
        const int i = solids[order[k]];
        const int j = solids[order[l]];
        if (!both_static(i, j) && aabbs_overlap(box_k, box_l, margin))
          pairs.push_back(ordered(i, j));
      }
    }
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

std::vector<Manifold> detect_contacts(const std::vector<Body>& bodies, double margin) {
  return narrow_phase(bodies, broad_phase(bodies, margin), margin);
}

std::vector<Manifold> narrow_phase(const std::vector<Body>& bodies,
                                   const std::vector<std::pair<int, int>>& pairs,
                                   double margin) {
  std::vector<Manifold> manifolds;
  for (const auto& [a, b] : pairs) {
    Manifold manifold;
    const Body& body_a = bodies[static_cast<std::size_t>(a)];
    const Body& body_b = bodies[static_cast<std::size_t>(b)];
    if (collide(body_a, body_b, a, b, manifold, margin)) manifolds.push_back(std::move(manifold));
  }
  return manifolds;
}

}  // namespace cbps
