// Contact persistence (for warm starting lambda, 7): a contact point of this step that lies where
// a point of the same pair sat last step continues that point, with its id (ContactPoint::id), so
// its contact and friction rows keep their ids and start from last step's lambda.
//
// Why: the clipping's feature ids (collision.hpp) change whenever a different pair of features
// makes a point, and an exactly stacked pair of equal boxes is their worst case: a sub-micrometre
// slide moves a clipped point along a whole edge, and its rows start from 0. Bullet keeps its
// contact points in a persistent manifold instead and matches a new point to a kept one by
// position, within its contact breaking threshold of 0.02 m (btPersistentManifold, Coumans,
// Bullet 2.x, getCacheEntry and gContactBreakingThreshold). This is that matching, on cbps's
// manifolds:
//   - a kept point remembers where it was on each body, in that body's frame: s_a = R_aᵀ (p − x_a)
//     and s_b = R_bᵀ (p − x_b), m;
//   - this step, the kept point would be at x_a + R_a s_a on body a and x_b + R_b s_b on body b;
//     its distance to a new point p is the larger of |p − x_a − R_a s_a| and |p − x_b − R_b s_b|;
//   - new and kept points of the same pair (a, b) are paired by increasing distance (ties: the
//     new point first in order, then the kept one), each at most once and only within the
//     persistence distance; a paired new point takes the kept point's id;
//   - a new point left unpaired gets a fresh id, from a counter that starts at 2³² so that it is
//     never a feature id (a feature id is below 2³²).
#pragma once

#include <cstdint>
#include <vector>

#include "cbps/collision/collision.hpp"

namespace cbps {

/// A contact point as persistence keeps it to the next step.
struct KeptPoint {
  Vec3 on_a = Vec3::Zero();  ///< s_a = R_aᵀ (p − x_a): the point in body a's frame, m
  Vec3 on_b = Vec3::Zero();  ///< s_b = R_bᵀ (p − x_b): the point in body b's frame, m
  std::uint64_t id = 0;      ///< ContactPoint::id
};

/// The contact points of one step, by pair, and the next fresh id.
struct ContactMemory {
  /// One entry per manifold, in the manifolds' ascending (a, b) order.
  struct Pair {
    int a = -1;
    int b = -1;
    std::vector<KeptPoint> points;
  };
  std::vector<Pair> pairs;
  /// The next fresh id (kFirstFreshContactId at first): above every id handed out so far.
  std::uint64_t next_id = kFirstFreshContactId;

  /// Fresh ids start here, above every feature id (those fit in 32 bits).
  static constexpr std::uint64_t kFirstFreshContactId = std::uint64_t(1) << 32;
};

/// Gives each point of `manifolds` (this step's, in ascending (a, b) order, as detect_contacts
/// returns them) its id: that of the kept point of `last` it continues, within `distance` m (> 0),
/// else a fresh id from last.next_id upwards. The bodies are this step's.
void continue_contacts(const ContactMemory& last,
                       const std::vector<Body>& bodies,
                       double distance,
                       std::vector<Manifold>& manifolds);

/// What the next step's continue_contacts needs from this step: each point where it sits on its
/// bodies (the bodies as they were when `manifolds` were found) and its id; next_id above every
/// id of `manifolds` and at least last_next_id.
ContactMemory keep_contacts(const std::vector<Body>& bodies,
                            const std::vector<Manifold>& manifolds,
                            std::uint64_t last_next_id);

/// The manifolds `found` at the start of a step carried with their bodies to where the bodies
/// are now (the substeps of a scheme, docs/schemes.md): each point sits at s_a on body a and s_b
/// on body b as `kept` recorded them (keep_contacts of `found`, one entry per manifold, same
/// order); the normal n stays as found; the point moves to the midpoint of x_a + R_a s_a and
/// x_b + R_b s_b, and its depth to d − n·((x_b + R_b s_b) − (x_a + R_a s_a)), m: the found depth
/// less how far the two points separated along n. Ids and features stay.
void carry_contacts(const std::vector<Manifold>& found,
                    const ContactMemory& kept,
                    const std::vector<Body>& bodies,
                    std::vector<Manifold>& moved);

}  // namespace cbps
