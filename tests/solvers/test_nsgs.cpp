// NSGS on friction cones (solvers/cone/nsgs.hpp): PGS itself without cones, one contact's
// answers worked out by hand, and the refusal of boxed methods. Coulomb's law on a sliding box
// is checked for nsgs and direct together (tests/solvers/test_cone_direct.cpp).
#include <catch2/catch.hpp>
#include <cmath>

#include "cbps/base/error.hpp"
#include "cbps/solvers/cone/nsgs.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/system/boxed_problem.hpp"
#include "cbps/system/cone_problem.hpp"
#include "fixture.hpp"

using namespace cbps;
using test::cones_of;
using test::system_of;

namespace {

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
  FrictionContacts cones;
  cones.normal = {0};
  cones.mu = VecX::Constant(1, 0.5);
  BoxedProblem problem{A, b, cmin, cmax};
  problem.cones = &cones;
  for (const FrictionLaw law : {FrictionLaw::CoulombCone, FrictionLaw::Relaxation}) {
    cones.law = law;
    VecX lambda;
    const SolverSummary s = solve(problem, lambda, nsgs_options(1000, 1e-14));
    CHECK(s.termination == Termination::ResidualTolerance);
    CHECK((lambda - stick).lpNorm<Eigen::Infinity>() <= 1e-12);
  }
}

TEST_CASE("the boxed methods refuse a problem with cones, naming nsgs", "[nsgs]") {
  const System sys = system_of("stack", {{"n", "2"}}, 3);
  const FrictionContacts cones = cones_of(sys, 0.5, FrictionLaw::CoulombCone);
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
