// The system of a step (6.1) and its equation (6.2.9): A = J Minv Jᵀ, b = υ/Δt − J (v1/Δt + Minv
// fext) and v2 = v1 + Δt Minv (Jᵀ λ + fext) (12.3.1), on point masses joined along x, every value
// worked by hand in the comments. Every number is a dyadic rational (a sum of powers of two: 1/64
// s, 2 kg, 0.5 kg, …) and the values that are not are multiplied by zeros, so each operation on
// the way is exact and the results are compared with ==.
#include <catch2/catch.hpp>
#include <initializer_list>
#include <vector>

#include "cbps/body/body.hpp"
#include "cbps/rows/distance.hpp"
#include "cbps/rows/row.hpp"
#include "cbps/step/simulation.hpp"
#include "cbps/system/system.hpp"
#include "fixture.hpp"

using namespace cbps;

namespace {

VecX vec(std::initializer_list<double> values) {
  VecX v(static_cast<Eigen::Index>(values.size()));
  Eigen::Index k = 0;
  for (const double x : values) v(k++) = x;
  return v;
}

}  // namespace

TEST_CASE("compute_A, compute_b and compute_v2 on two masses joined along x, worked by hand",
          "[system][eq6.2.9][eq12.3.1]") {
  // Body a (m_a = 2 kg) and body b (m_b = 0.5 kg), one distance row along x through their
  // centres (5.2.1: j_a = [−1 0 0  0 0 0], j_b = [1 0 0  0 0 0]), columns [v_a ω_a v_b ω_b]:
  //   J    = [−1 0 0 0 0 0  1 0 0 0 0 0]
  //   Minv = diag(1/m_a E₃, I_a⁻¹, 1/m_b E₃, I_b⁻¹), I_a⁻¹ = 4 E₃, I_b⁻¹ = 8 E₃ (kg⁻¹ m⁻²)
  //   A    = J Minv Jᵀ = (−1)² / m_a + 1² / m_b = 0.5 + 2 = 2.5 kg⁻¹ (the inertias do not enter:
  //          the row has no angular part).
  SpMatRow J(1, 12);
  J.insert(0, 0) = -1.0;
  J.insert(0, 6) = 1.0;
  const VecX minv_diagonal = vec({0.5, 0.5, 0.5, 4, 4, 4, 2, 2, 2, 8, 8, 8});
  const SpMat Minv = SpMat(MatX(minv_diagonal.asDiagonal()).sparseView());
  const SpMat A = compute_A(J, Minv);
  REQUIRE(A.rows() == 1);
  REQUIRE(A.cols() == 1);
  CHECK(A.coeff(0, 0) == 2.5);

  // v1: a moves at (1, 0.25, 0) m/s, b at (−0.5, 0, 0.75) m/s, neither turns; J v1 = −1.5 m/s
  // (closing). fext: 2 N along x and the weight m_a g = (0, −20, 0) N (g = 10 m/s²) on a, with a
  // torque of 1 N m about z; 3 N along x and (0, −5, 0) N on b. Δt = 1/64 s, υ = −4 m/s.
  //   v1/Δt + Minv fext, x entries: a: 1 · 64 + 2 / 2 = 65, b: −0.5 · 64 + 3 / 0.5 = −26 m/s²
  //   J (v1/Δt + Minv fext) = −26 − 65 = −91 m/s²,  υ/Δt = −4 · 64 = −256 m/s²
  //   b = υ/Δt − J (v1/Δt + Minv fext) = −256 + 91 = −165 m/s².
  const VecX v1 = vec({1, 0.25, 0, 0, 0, 0, -0.5, 0, 0.75, 0, 0, 0});
  const VecX fext = vec({2, -20, 0, 0, 0, 1, 3, -5, 0, 0, 0, 0});
  const double dt = 1.0 / 64.0;
  const VecX upsilon = vec({-4.0});
  const VecX b = compute_b(upsilon, J, v1, Minv, fext, dt);
  REQUIRE(b.size() == 1);
  CHECK(b(0) == -165.0);

  // The row is unbounded, so λ = b / A = −165 / 2.5 = −66 N. Then Jᵀ λ = (+66 N on a, −66 N on
  // b) along x, and v2 = v1 + Δt Minv (Jᵀ λ + fext):
  //   a: v_x = 1 + (1/64)(1/2)(66 + 2) = 1.53125,  v_y = 0.25 + (1/64)(1/2)(−20) = 0.09375,
  //      ω_z = (1/64) · 4 · 1 = 0.0625;
  //   b: v_x = −0.5 + (1/64) · 2 · (−66 + 3) = −2.46875,  v_y = (1/64) · 2 · (−5) = −0.15625,
  //      v_z = 0.75;
  // and J v2 = −2.46875 − 1.53125 = −4 m/s = υ: the velocity the row asked for (12.3).
  const VecX lambda = vec({-66.0});
  CHECK(A.coeff(0, 0) * lambda(0) == b(0));
  const VecX v2 = compute_v2(v1, Minv, J, lambda, fext, dt);
  const VecX expected = vec({1.53125, 0.09375, 0, 0, 0, 0.0625, -2.46875, -0.15625, 0.75, 0, 0, 0});
  INFO("v2 = " << v2.transpose());
  CHECK(v2 == expected);
  CHECK(VecX(J * v2) == upsilon);
}

TEST_CASE("assemble_system: two masses hung from the world along x, J, Minv, A, b and v2 by hand",
          "[system][eq6.1][eq6.2.9][eq12.3.1][eq8.1]") {
  // The world point (0, 0, 0) — link 0, l = 1 m — body a (2 kg sphere at (1, 0, 0)) — link 1,
  // l = 1 m — body b (0.5 kg sphere at (2.25, 0, 0)). Link 0 is at its length (C = 0); link 1
  // is stretched by C = 0.25 m, so with β = 0.25 and Δt = 1/64 s its push is
  // −β C / Δt = −4 m/s (5.2.3), and link 0's is 0. Both rows lie along x through the centres:
  //   J = [ 1 0 0 0 0 0  0 0 0 0 0 0 ]   (the world is end a of link 0: no block)
  //       [−1 0 0 0 0 0  1 0 0 0 0 0 ]
  //   A = J Minv Jᵀ = [ 1/m_a      −1/m_a      ] = [ 0.5  −0.5 ] kg⁻¹
  //                   [ −1/m_a  1/m_a + 1/m_b ]   [ −0.5   2.5 ]
  // Gravity (0, −10, 0) m/s², applied forces 2 N (a) and 3 N (b) along x: fext = f + m g =
  // (2, −20, 0 | 0 0 0) and (3, −5, 0 | 0 0 0) (6.1.3). v_a = (1, 0.25, 0), v_b = (−0.5, 0, 0.75)
  // m/s. As in the test above, v1/Δt + Minv fext has x entries 65 (a) and −26 (b) m/s², so
  //   b_0 = 0/Δt − 65 = −65,  b_1 = −4 · 64 − (−26 − 65) = −165 m/s².
  std::vector<Body> bodies(2);
  set_mass(bodies[0], 2.0);
  set_mass(bodies[1], 0.5);
  bodies[0].x = Vec3(1.0, 0.0, 0.0);
  bodies[1].x = Vec3(2.25, 0.0, 0.0);
  bodies[0].set_velocity(Vec3(1.0, 0.25, 0.0), Vec3::Zero());
  bodies[1].set_velocity(Vec3(-0.5, 0.0, 0.75), Vec3::Zero());
  bodies[0].f = Vec3(2.0, 0.0, 0.0);
  bodies[1].f = Vec3(3.0, 0.0, 0.0);
  DistanceConstraint to_world;
  to_world.a = -1;
  to_world.b = 0;
  to_world.length = 1.0;
  DistanceConstraint link;
  link.a = 0;
  link.b = 1;
  link.length = 1.0;
  const double beta = 0.25;
  const double dt = 1.0 / 64.0;
  const std::vector<Row> rows = {distance_row(to_world, bodies, beta, dt, 0),
                                 distance_row(link, bodies, beta, dt, 1)};
  const Vec3 gravity(0.0, -10.0, 0.0);
  const System sys = assemble_system(bodies, rows, gravity, dt, PushMode::Original);

  MatX J_expected = MatX::Zero(2, 12);
  J_expected(0, 0) = 1.0;
  J_expected(1, 0) = -1.0;
  J_expected(1, 6) = 1.0;
  CHECK(MatX(sys.J) == J_expected);
  // Minv's linear blocks are 1/m exactly; the angular ones, I⁻¹ = (2/5 m r²)⁻¹ of a solid sphere,
  // are rounded, but J has no angular part, so they reach neither A nor b nor v2.
  for (const int k : {0, 1, 2}) {
    CHECK(sys.Minv.coeff(k, k) == 0.5);
    CHECK(sys.Minv.coeff(6 + k, 6 + k) == 2.0);
  }
  CHECK(sys.v1 == (VecX(12) << 1, 0.25, 0, 0, 0, 0, -0.5, 0, 0.75, 0, 0, 0).finished());
  CHECK(sys.fext == (VecX(12) << 2, -20, 0, 0, 0, 0, 3, -5, 0, 0, 0, 0).finished());
  CHECK(sys.upsilon == (VecX(2) << 0.0, -4.0).finished());
  CHECK(MatX(sys.A) == (MatX(2, 2) << 0.5, -0.5, -0.5, 2.5).finished());
  CHECK(sys.b == (VecX(2) << -65.0, -165.0).finished());

  // A λ = b: the first row gives λ_0 − λ_1 = −130, the second −0.5 λ_0 + 2.5 λ_1 = −165, so
  // 2 λ_1 = −165 − 65 = −230: λ = (−245, −115) N. Then Jᵀ λ has x entries −245 + 115 = −130 N
  // (a) and −115 N (b), and
  //   a: v_x = 1 + (1/64)(1/2)(−130 + 2) = 0,  v_y = 0.25 + (1/64)(1/2)(−20) = 0.09375;
  //   b: v_x = −0.5 + (1/64) · 2 · (−115 + 3) = −4,  v_y = (1/64) · 2 · (−5) = −0.15625, v_z =
  //   0.75;
  // J v2 = (0, −4 − 0) = υ: a holds its distance to the world point, b closes at 4 m/s.
  const VecX lambda = (VecX(2) << -245.0, -115.0).finished();
  CHECK(VecX(MatX(sys.A) * lambda) == sys.b);
  const VecX v2 = compute_v2(sys, lambda);
  INFO("v2 = " << v2.transpose());
  CHECK(v2 == (VecX(12) << 0, 0.09375, 0, 0, 0, 0, -4, -0.15625, 0.75, 0, 0, 0).finished());
  CHECK(VecX(sys.J * v2) == sys.upsilon);

  // The improved push (8.1): the velocity system leaves the push out of υ and keeps it apart,
  // so b_1 = 0 − (−91) = 91 m/s²; A and J are the same.
  const System velocity = assemble_system(bodies, rows, gravity, dt, PushMode::Improved);
  CHECK(velocity.upsilon == (VecX(2) << 0.0, 0.0).finished());
  CHECK(velocity.upsilon_push == (VecX(2) << 0.0, -4.0).finished());
  CHECK(velocity.b == (VecX(2) << -65.0, 91.0).finished());
  CHECK(MatX(velocity.A) == MatX(sys.A));
}

TEST_CASE(
    "compute_A on a stepped pyramid: J Minv Jt as Eigen's sparse products form it, exactly "
    "symmetric",
    "[system]") {
  // The base-5 pyramid after 10 PGS steps: contact and friction rows on rotated boxes (Minv's
  // blocks full 3×3 inverse inertias). The reference is the general product J (Minv Jᵀ), an
  // independent formation; they may differ by rounding only.
  Simulation sim(test::contact_scene("pyramid", {{"base", "5"}}, "pgs"));
  for (int s = 0; s < 10; ++s) sim.step();
  const System sys = sim.build_system();
  REQUIRE(sys.rows() > 100);
  const SpMat MinvJt = sys.Minv * sys.J.transpose();
  const SpMat expected = sys.J * MinvJt;
  const SpMat& A = sys.A;
  CHECK(A.nonZeros() <= expected.nonZeros());
  const double size = MatX(expected).cwiseAbs().maxCoeff();
  CHECK((MatX(A) - MatX(expected)).cwiseAbs().maxCoeff() <= 1e-14 * size);
  const SpMat At = A.transpose();
  CHECK((MatX(A) - MatX(At)).cwiseAbs().maxCoeff() == 0.0);
  // Minv not block diagonal by body: the general products, unchanged.
  SpMat coupled = sys.Minv;
  coupled.coeffRef(0, 6) = 1e-3;
  coupled.coeffRef(6, 0) = 1e-3;
  const SpMat general = sys.J * SpMat(coupled * sys.J.transpose());
  CHECK((MatX(compute_A(sys.J, coupled)) - MatX(general)).cwiseAbs().maxCoeff() == 0.0);
}
