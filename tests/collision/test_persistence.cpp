// Contact persistence (collision/persistence.hpp): a point continues last step's point of the same
// pair that sat within the persistence distance of it on both bodies. Expected ids follow from the
// geometry written beside each case.
#include <catch2/catch.hpp>
#include <cstdint>
#include <vector>

#include "cbps/collision/persistence.hpp"

using namespace cbps;

namespace {

constexpr std::uint64_t kFresh = ContactMemory::kFirstFreshContactId;

Body body_at(const Vec3& x, const Quat& q = Quat::Identity()) {
  Body body;
  body.shape.kind = Shape::Kind::Box;
  body.x = x;
  body.q = q;
  return body;
}

ContactPoint point_at(const Vec3& p, std::uint32_t feature) {
  ContactPoint point;
  point.p = p;
  point.feature = feature;
  point.id = feature;
  return point;
}

Manifold pair_of(int a, int b, std::vector<ContactPoint> points) {
  Manifold m;
  m.a = a;
  m.b = b;
  m.n = Vec3::UnitY();
  m.points = std::move(points);
  return m;
}

}  // namespace

TEST_CASE("persistence: a point within the distance keeps its id, one beyond gets a fresh one",
          "[persistence]") {
  std::vector<Body> bodies = {body_at(Vec3::Zero()), body_at(Vec3(0.0, 1.0, 0.0))};
  const std::vector<Manifold> before = {
      pair_of(0, 1, {point_at(Vec3(0.5, 0.5, 0.5), 7), point_at(Vec3(-0.5, 0.5, 0.5), 9)})};
  const ContactMemory last = keep_contacts(bodies, before, kFresh);
  CHECK(last.next_id == kFresh);  // feature ids are below 2^32: nothing fresh was handed out
  REQUIRE(last.pairs.size() == 1);
  // Body 1's frame has its origin at (0, 1, 0): the first point sits at (0.5, −0.5, 0.5) in it.
  CHECK(last.pairs[0].points[0].on_b.isApprox(Vec3(0.5, -0.5, 0.5)));

  // This step the clipping names the points differently (features 3 and 4); the first is 1 cm
  // from where point 7 sat, the second 3 cm from where point 9 sat.
  std::vector<Manifold> now = {
      pair_of(0, 1, {point_at(Vec3(0.51, 0.5, 0.5), 3), point_at(Vec3(-0.5, 0.5, 0.53), 4)})};
  continue_contacts(last, bodies, 0.02, now);
  CHECK(now[0].points[0].id == 7);
  CHECK(now[0].points[1].id == kFresh);

  // With 5 cm both continue.
  now[0].points[0].id = 3;
  now[0].points[1].id = 4;
  continue_contacts(last, bodies, 0.05, now);
  CHECK(now[0].points[0].id == 7);
  CHECK(now[0].points[1].id == 9);

  // The memory of this step hands out ids above every one in use.
  const ContactMemory next = keep_contacts(bodies, now, last.next_id);
  CHECK(next.next_id == kFresh);
  std::vector<Manifold> fresh = {pair_of(0, 1, {point_at(Vec3(5.0, 0.5, 0.5), 1)})};
  now[0].points[1].id = kFresh + 4;
  const ContactMemory later = keep_contacts(bodies, now, kFresh);
  CHECK(later.next_id == kFresh + 5);
  continue_contacts(later, bodies, 0.02, fresh);
  CHECK(fresh[0].points[0].id == kFresh + 5);
}

TEST_CASE(
    "persistence: points are matched in the bodies' frames, so a pair moving together "
    "keeps its ids",
    "[persistence]") {
  std::vector<Body> bodies = {body_at(Vec3::Zero()), body_at(Vec3(0.0, 1.0, 0.0))};
  const std::vector<Manifold> before = {
      pair_of(0, 1, {point_at(Vec3(0.5, 0.5, 0.5), 1), point_at(Vec3(-0.5, 0.5, -0.5), 2)})};
  const ContactMemory last = keep_contacts(bodies, before, kFresh);
  // Both bodies turn 90° about y and move 3 m along x: (x, y, z) → (z + 3, y, −x).
  const Quat turn(Eigen::AngleAxisd(M_PI / 2.0, Vec3::UnitY()));
  for (Body& body : bodies) {
    body.x = turn * body.x + Vec3(3.0, 0.0, 0.0);
    body.q = turn;
  }
  std::vector<Manifold> now = {
      pair_of(0, 1, {point_at(Vec3(2.5, 0.5, 0.5), 5), point_at(Vec3(3.5, 0.5, -0.5), 6)})};
  continue_contacts(last, bodies, 0.02, now);
  CHECK(now[0].points[0].id == 2);  // (−0.5, 0.5, −0.5) → (2.5, 0.5, 0.5)
  CHECK(now[0].points[1].id == 1);  // (0.5, 0.5, 0.5) → (3.5, 0.5, −0.5)

  // A point that stays put in the world while body 1 slides 5 cm is 5 cm from where it sat on
  // body 1: it does not continue at 2 cm.
  bodies = {body_at(Vec3::Zero()), body_at(Vec3(0.05, 1.0, 0.0))};
  std::vector<Manifold> slid = {pair_of(0, 1, {point_at(Vec3(0.5, 0.5, 0.5), 5)})};
  continue_contacts(last, bodies, 0.02, slid);
  CHECK(slid[0].points[0].id == kFresh);
}

TEST_CASE(
    "persistence: the nearest pairs are made first, each kept point continues once, and "
    "only within its pair",
    "[persistence]") {
  std::vector<Body> bodies = {
      body_at(Vec3::Zero()), body_at(Vec3(0.0, 1.0, 0.0)), body_at(Vec3(0.0, 2.0, 0.0))};
  const std::vector<Manifold> before = {pair_of(0, 1, {point_at(Vec3(0.5, 0.5, 0.5), 1)}),
                                        pair_of(1, 2, {point_at(Vec3(0.5, 1.5, 0.5), 1)})};
  const ContactMemory last = keep_contacts(bodies, before, kFresh);
  // Two new points near kept point 1 of (0, 1): 1.5 cm and 0.5 cm away; the nearer continues it.
  // Pair (0, 2) is new: its point at the kept point of (1, 2) does not continue it.
  std::vector<Manifold> now = {
      pair_of(0, 1, {point_at(Vec3(0.515, 0.5, 0.5), 8), point_at(Vec3(0.505, 0.5, 0.5), 9)}),
      pair_of(0, 2, {point_at(Vec3(0.5, 1.5, 0.5), 1)}),
      pair_of(1, 2, {point_at(Vec3(0.5, 1.5, 0.51), 4)})};
  continue_contacts(last, bodies, 0.02, now);
  CHECK(now[0].points[0].id == kFresh);
  CHECK(now[0].points[1].id == 1);
  CHECK(now[1].points[0].id == kFresh + 1);
  CHECK(now[2].points[0].id == 1);
}
