// Contact persistence (7): this step's contact points continue last step's by position.
#include "cbps/collision/persistence.hpp"

#include <algorithm>
#include <tuple>

namespace cbps {

namespace {

/// The distance of new point p from kept point k: the larger of its distances from where k
/// now sits on body a and on body b, m.
double distance_from(const Vec3& p, const KeptPoint& k, const Body& a, const Body& b) {
  return std::max((p - a.world_point(k.on_a)).norm(), (p - b.world_point(k.on_b)).norm());
}

}  // namespace

void continue_contacts(const ContactMemory& last,
                       const std::vector<Body>& bodies,
                       double distance,
                       std::vector<Manifold>& manifolds) {
  std::uint64_t next_id = last.next_id;
  auto kept = last.pairs.begin();
  struct Candidate {
    double d;
    std::size_t fresh, old;
  };
  std::vector<Candidate> candidates;
  std::vector<char> taken;
  for (Manifold& m : manifolds) {
    // last.pairs and manifolds both ascend by (a, b): walk them together.
    while (kept != last.pairs.end() && std::tie(kept->a, kept->b) < std::tie(m.a, m.b)) ++kept;
    const bool same_pair = kept != last.pairs.end() && kept->a == m.a && kept->b == m.b;
    std::vector<char> paired(m.points.size(), 0);
    if (same_pair) {
      const Body& a = bodies[static_cast<std::size_t>(m.a)];
      const Body& b = bodies[static_cast<std::size_t>(m.b)];
      candidates.clear();
      for (std::size_t i = 0; i < m.points.size(); ++i)
        for (std::size_t j = 0; j < kept->points.size(); ++j) {
          const double d = distance_from(m.points[i].p, kept->points[j], a, b);
          if (d <= distance) candidates.push_back({d, i, j});
        }
      std::sort(candidates.begin(), candidates.end(), [](const Candidate& x, const Candidate& y) {
        return std::tie(x.d, x.fresh, x.old) < std::tie(y.d, y.fresh, y.old);
      });
      taken.assign(kept->points.size(), 0);
      for (const Candidate& c : candidates) {
        if (paired[c.fresh] != 0 || taken[c.old] != 0) continue;
        paired[c.fresh] = 1;
        taken[c.old] = 1;
        m.points[c.fresh].id = kept->points[c.old].id;
      }
    }
    for (std::size_t i = 0; i < m.points.size(); ++i)
      if (paired[i] == 0) m.points[i].id = next_id++;
  }
}

ContactMemory keep_contacts(const std::vector<Body>& bodies,
                            const std::vector<Manifold>& manifolds,
                            std::uint64_t last_next_id) {
  ContactMemory memory;
  memory.next_id = std::max(last_next_id, ContactMemory::kFirstFreshContactId);
  memory.pairs.reserve(manifolds.size());
  for (const Manifold& m : manifolds) {
    const Body& a = bodies[static_cast<std::size_t>(m.a)];
    const Body& b = bodies[static_cast<std::size_t>(m.b)];
    ContactMemory::Pair pair{m.a, m.b, {}};
    pair.points.reserve(m.points.size());
    for (const ContactPoint& point : m.points) {
      // s = Rᵀ (p − x): the inverse of Body::world_point.
      pair.points.push_back(
          {a.q.conjugate() * (point.p - a.x), b.q.conjugate() * (point.p - b.x), point.id});
      memory.next_id = std::max(memory.next_id, point.id + 1);
    }
    memory.pairs.push_back(std::move(pair));
  }
  return memory;
}

void carry_contacts(const std::vector<Manifold>& found,
                    const ContactMemory& kept,
                    const std::vector<Body>& bodies,
                    std::vector<Manifold>& moved) {
  moved = found;
  for (std::size_t m = 0; m < moved.size(); ++m) {
    Manifold& manifold = moved[m];
    const Body& a = bodies[static_cast<std::size_t>(manifold.a)];
    const Body& b = bodies[static_cast<std::size_t>(manifold.b)];
    for (std::size_t k = 0; k < manifold.points.size(); ++k) {
      const KeptPoint& on = kept.pairs[m].points[k];
      const Vec3 p_a = a.world_point(on.on_a), p_b = b.world_point(on.on_b);
      ContactPoint& point = manifold.points[k];
      point.depth = found[m].points[k].depth - manifold.n.dot(p_b - p_a);  // m
      point.p = 0.5 * (p_a + p_b);
    }
  }
}

}  // namespace cbps
