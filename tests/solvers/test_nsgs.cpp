// NSGS on friction cones (solvers/cone/nsgs.hpp): PGS itself without cones, one contact's
// answers worked out by hand, Coulomb's law on a sliding box (friction = mu times the normal
// force, against the motion), the relaxation's lift-off, and the refusal of boxed methods.
#include <catch2/catch.hpp>
#include <cmath>

#include "cbps/base/error.hpp"
#include "cbps/solvers/cone/nsgs.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/system/boxed_problem.hpp"
#include "cbps/system/cone_problem.hpp"
#include "fixture.hpp"

using namespace cbps;
using test::system_of;

namespace {

/// Every contact of a step's system in a cone: its normal row and the two friction rows after
/// it, with coefficient mu.
ConeContacts cones_of(const System& sys, double mu, ConeLaw law) {
  ConeContacts cones;
  cones.law = law;
  for (long k = 0; k + 2 < static_cast<long>(sys.kind.size()); ++k) {
    const auto at = [&](long i) { return sys.kind[static_cast<std::size_t>(i)]; };
    if (at(k) == RowKind::Contact && at(k + 1) == RowKind::Friction &&
        at(k + 2) == RowKind::Friction)
      cones.normal.push_back(static_cast<int>(k));
  }
  cones.mu = VecX::Constant(cones.contacts(), mu);
  return cones;
}

SolverOptions nsgs_options(int sweeps, double tolerance) {
  SolverOptions o;
  o.method = Method::Nsgs;
  o.max_iterations = sweeps;
  o.tolerance = tolerance;
  return o;
}

}  // namespace

TEST_CASE("nsgs without cones is the paper's PGS (7.1.1), sweep for sweep", "[nsgs]") {
  const System sys = system_of("stack", {{"n", "4"}}, 3);
  SolverOptions pgs = nsgs_options(25, 0.0);
  pgs.method = Method::Pgs;
  VecX by_pgs, by_nsgs;
  solve(sys.problem(), by_pgs, pgs);
  solve(sys.problem(), by_nsgs, nsgs_options(25, 0.0));
  REQUIRE(by_pgs.size() == sys.rows());
  CHECK((by_pgs - by_nsgs).lpNorm<Eigen::Infinity>() == 0.0);
}

TEST_CASE("nsgs finds one contact's answers worked out by hand", "[nsgs]") {
  // A W that couples the normal and a tangent, W = I + 0.3 e eᵀ with e = (1, 1, 0)/√2, and
  // b = W r* for r* = (1, 0.2, −0.1), inside the cone of mu = 0.5: at r* the velocity
  // u = W r* − b is 0, so r* is the sticking answer of both laws (and the only one: W is
  // positive definite).
  Mat3 W = Mat3::Identity();
  const Vec3 e = Vec3(1.0, 1.0, 0.0).normalized();
  W += 0.3 * e * e.transpose();
  SpMat A = W.sparseView();
  const Vec3 stick(1.0, 0.2, -0.1);
  const VecX b = W * stick;
  const VecX cmin = (VecX(3) << 0.0, -kInf, -kInf).finished();
  const VecX cmax = VecX::Constant(3, kInf);
  ConeContacts cones;
  cones.normal = {0};
  cones.mu = VecX::Constant(1, 0.5);
  BoxedProblem problem{A, b, cmin, cmax};
  problem.cones = &cones;
  for (const ConeLaw law : {ConeLaw::Coulomb, ConeLaw::Ccp}) {
    cones.law = law;
    VecX lambda;
    const SolverSummary s = solve(problem, lambda, nsgs_options(1000, 1e-14));
    CHECK(s.termination == Termination::ResidualTolerance);
    CHECK((lambda - stick).lpNorm<Eigen::Infinity>() <= 1e-12);
  }
}

TEST_CASE("nsgs on a sliding box: Coulomb's friction is mu times the normal force, opposing",
          "[nsgs]") {
  // The slide scene: a box moving at 2 m/s along x on a plane, four contacts. Every contact
  // slides the same way, so Coulomb's law (r_t = −mu r_n u_t / ‖u_t‖, u_n = 0) gives, summed,
  // friction −mu Σ r_n along x and none along the other tangent: a property of the law, checked
  // on sums NSGS never forms.
  const double mu = 0.3;
  const System sys = system_of("slide", {{"mu", "0.3"}}, 2);
  ConeContacts cones = cones_of(sys, mu, ConeLaw::Coulomb);
  REQUIRE(cones.contacts() == 4);
  BoxedProblem problem = sys.problem();
  problem.cones = &cones;
  VecX lambda;
  const SolverSummary s = solve(problem, lambda, nsgs_options(20000, 1e-10));
  INFO(s.message);
  CHECK(s.termination == Termination::ResidualTolerance);
  const VecX w = sys.A * lambda - sys.b;
  double normal = 0.0;
  Eigen::Vector2d friction_t = Eigen::Vector2d::Zero();  // one plane: one tangent basis
  for (const int n : cones.normal) {
    normal += lambda(n);
    CHECK(std::abs(w(n)) <= 1e-9);  // in contact: u_n = 0
    const double u_t = std::hypot(w(n + 1), w(n + 2));
    REQUIRE(u_t > 1e-3);  // sliding
    // Friction along −u_t with magnitude mu r_n.
    CHECK(lambda(n + 1) == Approx(-mu * lambda(n) * w(n + 1) / u_t).margin(1e-9));
    CHECK(lambda(n + 2) == Approx(-mu * lambda(n) * w(n + 2) / u_t).margin(1e-9));
    friction_t += Eigen::Vector2d(lambda(n + 1), lambda(n + 2));
  }
  CHECK(normal > 0.0);
  CHECK(friction_t.norm() == Approx(mu * normal).epsilon(1e-9));

  // The relaxation (CCP) slides with u_n = mu ‖u_t‖ > 0: the box lifts off while it slides.
  cones.law = ConeLaw::Ccp;
  VecX relaxed;
  solve(problem, relaxed, nsgs_options(20000, 1e-10));
  const VecX v = sys.A * relaxed - sys.b;
  for (const int n : cones.normal) {
    const double u_t = std::hypot(v(n + 1), v(n + 2));
    CHECK(v(n) == Approx(mu * u_t).margin(1e-9));
    CHECK(v(n) > 1e-3);
  }
}

TEST_CASE("the boxed methods refuse a problem with cones, naming nsgs", "[nsgs]") {
  const System sys = system_of("stack", {{"n", "2"}}, 3);
  const ConeContacts cones = cones_of(sys, 0.5, ConeLaw::Coulomb);
  REQUIRE(cones.contacts() > 0);
  BoxedProblem problem = sys.problem();
  problem.cones = &cones;
  for (const Method m : {Method::Pgs, Method::ActiveSet, Method::Apgd, Method::Lemke}) {
    SolverOptions o;
    o.method = m;
    VecX lambda;
    CHECK_THROWS_AS(solve(problem, lambda, o), InputError);
    CHECK_THROWS_WITH(solve(problem, lambda, o), Catch::Contains("nsgs"));
  }
}
