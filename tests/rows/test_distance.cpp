// The distance row (5.2.1) and its Baumgarte push (5.2.3), against rows worked by hand from the
// geometry in the comment beside each: j_c = [−nᵀ, −(r_a × n)ᵀ, nᵀ, (r_b × n)ᵀ],
// upsilon_push = −β C / Δt with C = |p_b − p_a| − l.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <vector>

#include "cbps/body/body.hpp"
#include "cbps/rows/distance.hpp"
#include "cbps/rows/row.hpp"

using namespace cbps;

namespace {

/// A few roundings of unit-sized values: the quaternion of a 90° turn, (cos 45°, sin 45°), is
/// rounded, so the points it turns and the n they give are off by a few ulps.
constexpr double kTurnTolerance = 16 * std::numeric_limits<double>::epsilon();

Body body_at(const Vec3& x, const Quat& q = Quat::Identity()) {
  Body body;
  body.x = x;
  body.q = q;
  return body;
}

Row6 row6(double v0, double v1, double v2, double w0, double w1, double w2) {
  Row6 r;
  r << v0, v1, v2, w0, w1, w2;
  return r;
}

}  // namespace

TEST_CASE("distance row: two bodies joined at their centres along x, j_c and the push by hand",
          "[rows][distance][eq5.2.1][eq5.2.3]") {
  // Body a at the origin, body b at (1.5, 0, 0), joined centre to centre with l = 1.25 m:
  //   p_b − p_a = (1.5, 0, 0), |p_b − p_a| = 1.5 m, n = (1, 0, 0), r_a = r_b = 0,
  //   C = |p_b − p_a| − l = 0.25 m (5.2.2), so
  //   j_a = [−nᵀ, −(r_a × n)ᵀ] = [−1 0 0  0 0 0],  j_b = [nᵀ, (r_b × n)ᵀ] = [1 0 0  0 0 0],
  //   upsilon_push = −β C / Δt = −0.25 · 0.25 m / (1/64 s) = −4 m/s (5.2.3):
  // a stretched link asks its ends to approach at 4 m/s. The row has no other bias and is
  // unbounded. Every number here is a dyadic rational, so each operation on the way is exact
  // and the row is compared with ==.
  const std::vector<Body> bodies = {body_at(Vec3::Zero()), body_at(Vec3(1.5, 0.0, 0.0))};
  DistanceConstraint dc;
  dc.name = "link";
  dc.a = 0;
  dc.b = 1;
  dc.length = 1.25;
  const double beta = 0.25;
  const double dt = 1.0 / 64.0;
  CHECK(distance_violation(dc, bodies) == 0.25);
  const Row row = distance_row(dc, bodies, beta, dt, 42);
  CHECK(row.label == "link");
  CHECK(row.id == 42u);
  CHECK(row.body_a == 0);
  CHECK(row.body_b == 1);
  CHECK(row.j_a == row6(-1, 0, 0, 0, 0, 0));
  CHECK(row.j_b == row6(1, 0, 0, 0, 0, 0));
  CHECK(row.upsilon == 0.0);
  CHECK(row.upsilon_push == -4.0);
  CHECK(row.cmin == -kInf);
  CHECK(row.cmax == kInf);

  // The same link compressed, l = 1.75 m: C = −0.25 m, upsilon_push = +4 m/s (pushed apart),
  // and j_c unchanged (n is still from a to b).
  dc.length = 1.75;
  const Row pushed = distance_row(dc, bodies, beta, dt, 42);
  CHECK(pushed.j_a == row.j_a);
  CHECK(pushed.j_b == row.j_b);
  CHECK(pushed.upsilon_push == 4.0);
  // β = 0: the row keeps j_c and asks for no correction.
  CHECK(distance_row(dc, bodies, 0.0, dt, 42).upsilon_push == 0.0);
}

TEST_CASE("distance row: anchors off the centres give the angular parts, a world end no block",
          "[rows][distance][eq5.2.1][eq5.2.3]") {
  // Body a at the origin, not turned, anchor_a = (0, 0.5, 0): p_a = (0, 0.5, 0), r_a = (0, 0.5, 0).
  // Body b at (2, 1, 0) turned 90° about z, R (x, y, z) = (−y, x, z), anchor_b = (−0.5, 0.5, 0):
  // r_b = R anchor_b = (−0.5, −0.5, 0), p_b = (1.5, 0.5, 0).
  //   p_b − p_a = (1.5, 0, 0): n = (1, 0, 0), |p_b − p_a| = 1.5 m, and with l = 1 m, C = 0.5 m;
  //   r_a × n = (0, 0.5, 0) × (1, 0, 0) = (0, 0, −0.5), so −(r_a × n) = (0, 0, 0.5);
  //   r_b × n = (−0.5, −0.5, 0) × (1, 0, 0) = (0, 0, 0.5);
  //   j_a = [−1 0 0  0 0 0.5],  j_b = [1 0 0  0 0 0.5];
  //   upsilon_push = −β C / Δt = −0.2 · 0.5 m / 0.01 s = −10 m/s.
  // The signs by kinematics: a turning at omega about +z moves its anchor by omega ẑ × r_a =
  // omega (−0.5, 0, 0), away from b, so the distance grows at 0.5 omega; b turning at omega moves
  // its anchor by omega ẑ × r_b = omega (0.5, −0.5, 0), along +n, away from a: 0.5 omega again.
  const Quat quarter_turn(Eigen::AngleAxisd(kPi / 2.0, Vec3::UnitZ()));
  std::vector<Body> bodies = {body_at(Vec3::Zero()), body_at(Vec3(2.0, 1.0, 0.0), quarter_turn)};
  DistanceConstraint dc;
  dc.a = 0;
  dc.b = 1;
  dc.anchor_a = Vec3(0.0, 0.5, 0.0);
  dc.anchor_b = Vec3(-0.5, 0.5, 0.0);
  dc.length = 1.0;
  const double beta = 0.2;
  const double dt = 0.01;
  const Row row = distance_row(dc, bodies, beta, dt, 7);
  INFO("j_a = " << row.j_a << ", j_b = " << row.j_b << ", upsilon_push = " << row.upsilon_push
                << " m/s, tolerance " << kTurnTolerance);
  CHECK((row.j_a - row6(-1, 0, 0, 0, 0, 0.5)).lpNorm<Eigen::Infinity>() <= kTurnTolerance);
  CHECK((row.j_b - row6(1, 0, 0, 0, 0, 0.5)).lpNorm<Eigen::Infinity>() <= kTurnTolerance);
  CHECK(row.upsilon_push == Approx(-10.0).epsilon(kTurnTolerance));

  // End a on the world at the same point (anchor_a is then a world point), or on a static body:
  // no block for that end (5.3), the same j_b and push.
  for (const bool on_world : {true, false}) {
    CAPTURE(on_world);
    DistanceConstraint fixed = dc;
    std::vector<Body> fixed_bodies = bodies;
    if (on_world) {
      fixed.a = -1;
    } else {
      fixed_bodies[0].is_static = true;
    }
    const Row end = distance_row(fixed, fixed_bodies, beta, dt, 7);
    CHECK(end.body_a == -1);
    CHECK(end.j_a == Row6::Zero());
    CHECK(end.body_b == 1);
    CHECK((end.j_b - row6(1, 0, 0, 0, 0, 0.5)).lpNorm<Eigen::Infinity>() <= kTurnTolerance);
    CHECK(end.upsilon_push == Approx(-10.0).epsilon(kTurnTolerance));
  }
}
