// Coulomb's cone (system/cone_problem.hpp): the projection against Moreau's decomposition, and
// the natural map and the measures at one contact's answers worked out by hand.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "cbps/system/boxed_problem.hpp"
#include "cbps/system/cone_problem.hpp"

using namespace cbps;

namespace {

bool in_cone(const Vec3& r, double mu, double tol) {
  return std::hypot(r(1), r(2)) <= mu * r(0) + tol;
}

}  // namespace

TEST_CASE("project_onto_cone is Moreau's decomposition: x = P_K x + P_polar x, orthogonal",
          "[cone]") {
  // For a closed convex cone K, x − P_K(x) lies in the polar cone −K* and is orthogonal to
  // P_K(x) (Moreau 1962); K*_mu = {mu ‖u_t‖ ≤ u_n}. Both follow from the definition of the
  // projection, not from the formula under test.
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (const double mu : {0.0, 0.3, 1.0, 2.5}) {
    for (int trial = 0; trial < 2000; ++trial) {
      const Vec3 x(normal(rng), normal(rng), normal(rng));
      Vec3 p = x;
      project_onto_cone(mu, p);
      const Vec3 d = x - p;  // in −K*: mu ‖d_t‖ ≤ −d_n
      CHECK(in_cone(p, mu, 1e-14));
      CHECK(mu * std::hypot(d(1), d(2)) <= -d(0) + 1e-14);
      CHECK(std::abs(p.dot(d)) <= 1e-14);
      Vec3 again = p;
      project_onto_cone(mu, again);
      CHECK((again - p).norm() <= 1e-15);
    }
  }
}

TEST_CASE("the natural map vanishes at one contact's answers, worked out by hand", "[cone]") {
  // One contact with W = I: u = r + q, mu = 0.5.
  const double mu = 0.5;
  const auto map = [&](const Vec3& r, const Vec3& q, FrictionLaw law) {
    return cone_natural_map(r, r + q, mu, law).norm();
  };
  SECTION("sticking: u = 0, r = −q inside the cone (both laws)") {
    const Vec3 q(-1.0, 0.1, 0.0), r(1.0, -0.1, 0.0);
    CHECK(map(r, q, FrictionLaw::CoulombCone) <= 1e-15);
    CHECK(map(r, q, FrictionLaw::Relaxation) <= 1e-15);
  }
  SECTION("separating: r = 0, u = q in the dual cone") {
    const Vec3 q(1.0, 0.3, 0.0);
    CHECK(map(Vec3::Zero(), q, FrictionLaw::CoulombCone) == 0.0);
    CHECK(map(Vec3::Zero(), q, FrictionLaw::Relaxation) == 0.0);
  }
  SECTION("sliding: Coulomb keeps contact, the relaxation lifts off") {
    const Vec3 q(-1.0, 2.0, 0.0);
    // Coulomb: u_n = 0 so r_n = 1, r_t = −mu r_n along −u_t: r = (1, −0.5, 0), u = (0, 1.5, 0).
    const Vec3 coulomb(1.0, -0.5, 0.0);
    CHECK(map(coulomb, q, FrictionLaw::CoulombCone) <= 1e-15);
    CHECK(map(coulomb, q, FrictionLaw::Relaxation) > 0.1);
    // CCP: min ½‖r‖² + qᵀr over K is P_K(−q) = (1.6, −0.8, 0): u = (0.6, 1.2, 0), u_n = mu ‖u_t‖.
    const Vec3 ccp(1.6, -0.8, 0.0);
    CHECK(map(ccp, q, FrictionLaw::Relaxation) <= 1e-15);
    CHECK(map(ccp, q, FrictionLaw::CoulombCone) > 0.1);

    FrictionContacts cones;
    cones.normal = {0};
    cones.mu = VecX::Constant(1, mu);
    const VecX b = -q;  // w = A λ − b with A = I
    const ConeMeasures c = cone_measures(cones, coulomb, coulomb + q, b);
    CHECK(c.signorini <= 1e-15);  // Coulomb: r_n u_n = 1 · 0
    CHECK(c.violation == 0.0);
    CHECK(c.dissipation <= 1e-15);  // r_t · u_t = −0.75 = −mu r_n ‖u_t‖
    cones.law = FrictionLaw::Relaxation;
    const ConeMeasures r = cone_measures(cones, ccp, ccp + q, b);
    CHECK(r.natural_map <= 1e-15);
    CHECK(r.signorini == Approx(1.6 * 0.6));  // the relaxation's gap: lifted while sliding
    CHECK(r.dissipation <= 1e-15);            // −0.96 = −0.5 · 1.6 · 1.2
    CHECK(r.fclib_merit > 0.1);               // FCLIB's merit is Coulomb's: not zero here
  }
}

TEST_CASE("a problem's residual takes the cone law at its contacts and the box elsewhere",
          "[cone]") {
  // Rows 0-2 one contact (W = I, mu = 0.5), row 3 a box [0, 1] alone.
  SpMat A(4, 4);
  A.setIdentity();
  const VecX b = (VecX(4) << 1.0, -2.0, 0.0, 2.0).finished();  // q = −b = (−1, 2, 0), row 3 −2
  const VecX cmin = (VecX(4) << 0.0, -kInf, -kInf, 0.0).finished();
  const VecX cmax = (VecX(4) << kInf, kInf, kInf, 1.0).finished();
  FrictionContacts cones;
  cones.normal = {0};
  cones.mu = VecX::Constant(1, 0.5);
  BoxedProblem problem{A, b, cmin, cmax};
  problem.cones = &cones;
  const VecX solved = (VecX(4) << 1.0, -0.5, 0.0, 1.0).finished();  // row 3 at its cap
  CHECK(natural_map_residual(problem, solved) <= 1e-15);
  VecX off = solved;
  off(3) = 0.5;  // the box row wrong by 0.5 (w_3 = −1.5: it should sit at cmax)
  CHECK(natural_map_residual(problem, off) == Approx(0.5));
  problem.cones = nullptr;  // as three boxes the same lambda is no solution (w_1 = 1.5 ≠ 0)
  CHECK(natural_map_residual(problem, solved) > 1.0);
}

TEST_CASE("Siconos' error of one contact, by hand from Siconos 4.4's definition", "[cones]") {
  // fc3d_compute_error: sqrt(Σ ‖r − P_K(r − û)‖²) / max(‖q‖₂, ‖r‖₂, ‖u‖₂). W = 4 I,
  // q = −b = (−4, −8, 0), mu = 0.5, r = 0: u = q, û = (−4 + 0.5·8, −8, 0) = (0, −8, 0),
  // P_K((0, 8, 0)) = (4/1.25)(1, 0.5, 0) = (3.2, 1.6, 0), sum of squares 12.8; the divisor
  // max(sqrt 80, 0, sqrt 80): error sqrt(12.8 / 80) = 0.4.
  FrictionContacts cones;
  cones.normal = {0};
  cones.mu = VecX::Constant(1, 0.5);
  const VecX b = (VecX(3) << 4.0, 8.0, 0.0).finished();
  const VecX lambda = VecX::Zero(3);
  const ConeMeasures m = cone_measures(cones, lambda, -b, b);
  CHECK(m.siconos_error == Approx(0.4).epsilon(1e-14));
  // At the answer (1, 0.5, 0) (u = (0, −6, 0)): 0.
  const VecX answer = (VecX(3) << 1.0, 0.5, 0.0).finished();
  CHECK(cone_measures(cones, answer, 4.0 * answer - b, b).siconos_error <= 1e-16);
}
