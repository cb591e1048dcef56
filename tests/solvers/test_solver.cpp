// solve() over the methods and the variants people compare PGS (7.1.1) with: relaxation (PSOR),
// symmetric sweeps, row orders, damped Jacobi, matrix-free, block PGS; and constraint-force mixing,
// which every method solves the same way.
#include <algorithm>
#include <catch2/catch.hpp>
#include <string>

#include "cbps/rows/distance.hpp"
#include "cbps/scene/builtin.hpp"
#include "cbps/solvers/exact/direct.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/step/simulation.hpp"
#include "cbps/studies/solver_spec.hpp"
#include "cbps/system/system.hpp"
#include "fixture.hpp"

using namespace cbps;
using test::system_of;

namespace {

/// The direct path's lambda (6.2) and its v2, the unique reference.
VecX exact_lambda(const System& sys) {
  VecX lambda = VecX::Zero(sys.rows());
  const SolverSummary s = solve_direct(sys.problem(), lambda);
  // Verified, as `cbps lcp` verifies (its own 64 u stop may be out of reach on singular A).
  REQUIRE(s.residual <= 1e-9 * std::max(1.0, sys.b.lpNorm<Eigen::Infinity>()));
  return lambda;
}

}  // namespace

TEST_CASE("every variant converges to the direct path's answer (7.1.1, 6.2)",
          "[solver][variants]") {
  // A hanging chain of 20 links (A definite: lambda unique) and a resting 3-box stack with
  // contacts (4 per face, A singular: v2 unique; frictionless: with the paper's friction rows PGS
  // stalls near 1e-4 N on this system, docs/convergence.md).
  const std::string spec = GENERATE(as<std::string>{},
                                    "pgs",
                                    "psor:1.5",
                                    "psor:0.7",
                                    "sgs",
                                    "sgs:1.2",
                                    "jacobi:0.5",
                                    "pgs:order=reverse",
                                    "pgs:order=random",
                                    "matrix-free",
                                    "matrix-free:order=random",
                                    "block-pgs");
  CAPTURE(spec);
  const SolverSpec s = parse_solver_spec(spec);
  SolverOptions options;
  options.method = s.method;
  options.relaxation = s.relaxation;
  options.order = s.order;
  options.seed = 7;
  options.max_iterations = 20000;
  options.tolerance = 1e-9;
  for (const bool contact : {false, true}) {
    CAPTURE(contact);
    const System sys = contact ? system_of("stack", {{"n", "3"}, {"mu", "0"}}, 3)
                               : system_of("chain", {{"n", "20"}, {"mass_ratio", "5"}}, 10);
    const VecX exact = exact_lambda(sys);
    VecX lambda = VecX::Zero(sys.rows());
    const SolverSummary summary = solve(sys.problem(), lambda, options);
    CAPTURE(summary.message);
    if (s.method == Method::BlockPgs && contact) {
      // Its blocks carry delta = 1e-7 max A_jj: a floor of O(delta lambda) ~ 1e-6 N, not 1e-9.
      CHECK(summary.residual < 1e-5);
    } else {
      CHECK(summary.termination == Termination::ResidualTolerance);
    }
    const VecX v2 = compute_v2(sys.v1, sys.Minv, sys.J, lambda, sys.fext, sys.dt);
    const VecX v2_exact = compute_v2(sys.v1, sys.Minv, sys.J, exact, sys.fext, sys.dt);
    CHECK((v2 - v2_exact).lpNorm<Eigen::Infinity>() < 1e-6);
    if (!contact) CHECK((lambda - exact).lpNorm<Eigen::Infinity>() < 1e-6);
  }
}

TEST_CASE("cfm: the same row twice shares lambda, off A lambda = b by eps lambda",
          "[stress][cfm]") {
  // One pendulum row a, given twice: A = [[a + eps, a], [a, a + eps]], b = (b0, b0), so
  // lambda_1 = lambda_2 = b0 / (2 a + eps): unique, where without eps only the sum is.
  Scene s = make_builtin_scene("chain", {{"n", "1"}, {"link_length", "1"}});
  s.bodies[0].set_velocity(Vec3(0.5, 0.0, 0.0), Vec3::Zero());  // along the string: b0 ≠ 0
  const System single = Simulation(s).build_system();
  const double a = single.A.coeff(0, 0);
  const double b0 = single.b(0);
  REQUIRE(std::abs(b0) > 1.0);
  DistanceConstraint twin = s.distances.front();
  s.distances.push_back(twin);
  const double eps = 1e-3;
  const double share = b0 / (2 * a + eps);
  s.solver.cfm = eps;
  for (const char* method : {"pgs", "matrix-free", "direct"}) {
    INFO(method);
    s.solver.method = method_of(method);
    Simulation sim(s);
    const System& sys = sim.assemble();  // A formed but for matrix-free, which never reads A
    CHECK(sys.problem().A_formed() == (std::string(method) != "matrix-free"));
    // A stays J Minv Jᵀ: eps is the solver's, not the system's.
    const System formed = sim.build_system();
    CHECK(formed.A.coeff(0, 0) == Approx(a).epsilon(1e-14));
    CHECK(formed.A.coeff(0, 1) == Approx(a).epsilon(1e-14));
    VecX lambda = VecX::Zero(2);
    sim.solve_system(sys, lambda);
    // Gauss-Seidel evens the split out only at 1 − eps/a a sweep; its last row holds exactly,
    // a S + eps lambda_2 = b0, so the sum S is off by at most eps |lambda_2| / a.
    CHECK(lambda.sum() == Approx(2 * share).epsilon(2 * eps / a));
    if (std::string(method) == "direct") {
      CHECK(lambda(0) == Approx(share).epsilon(1e-10));
      CHECK(lambda(1) == Approx(share).epsilon(1e-10));
    }
    const double reported = sim.step().cfm_acceleration_error;
    CHECK(reported == Approx(eps * lambda.cwiseAbs().maxCoeff()).epsilon(1e-9));
  }
}
