// Block PGS (block_pgs_sweep): 7.1.1 over blocks of rows, each solved by boxed Lemke.
#include <catch2/catch.hpp>
#include <random>
#include <string>
#include <vector>

#include "cbps/scene/builtin.hpp"
#include "cbps/solvers/compared/pgs_block.hpp"
#include "cbps/solvers/exact/direct.hpp"
#include "cbps/solvers/paper/pgs.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/step/simulation.hpp"
#include "cbps/system/boxed_problem.hpp"
#include "cbps/system/system.hpp"
#include "fixture.hpp"

using namespace cbps;
using test::construct;
using test::Constructed;
using test::scale_of;

TEST_CASE("block PGS with blocks of one row is PGS (7.1.1), iterate for iterate", "[direct][pgs]") {
  std::mt19937 rng(11);
  const Constructed p = construct(30, 40, rng);
  const std::vector<int> singles(30, -1);
  VecX a = VecX::Zero(30), b = VecX::Zero(30);
  for (int sweep = 0; sweep < 25; ++sweep) {
    pgs_sweep(BoxedProblem{p.A, p.b, p.lo, p.hi}, a);
    block_pgs_sweep(BoxedProblem{p.A, p.b, p.lo, p.hi, nullptr, nullptr, &singles}, b);
    REQUIRE((a - b).lpNorm<Eigen::Infinity>() == 0.0);  // the same arithmetic, in the same order
  }
}

TEST_CASE("block PGS finds the constructed solution, one block of every row is Lemke's answer",
          "[direct][pgs]") {
  std::mt19937 rng(12);
  for (int trial = 0; trial < 50; ++trial) {
    CAPTURE(trial);
    const Constructed p = construct(24, 30, rng);  // positive definite: lambda* is unique
    const double scale = scale_of(p.A, p.b);
    std::vector<int> blocks(24);
    for (int i = 0; i < 24; ++i) blocks[static_cast<std::size_t>(i)] = i / 4;  // 6 blocks of 4
    SolverOptions options;
    options.method = Method::BlockPgs;
    options.max_iterations = 2000;
    options.tolerance = 1e-10 * scale;
    options.block_regularization = 0.0;
    VecX lambda = VecX::Zero(24);
    const SolverSummary s =
        solve(BoxedProblem{p.A, p.b, p.lo, p.hi, nullptr, nullptr, &blocks}, lambda, options);
    CAPTURE(s.message);
    CHECK(s.termination == Termination::ResidualTolerance);
    CHECK((lambda - p.lambda_star).lpNorm<Eigen::Infinity>() <= 1e-6);
    CHECK(s.message.find("row by row") == std::string::npos);  // Lemke solved every block

    const std::vector<int> one(24, 0);
    VecX whole = VecX::Zero(24);
    block_pgs_sweep(BoxedProblem{p.A, p.b, p.lo, p.hi, nullptr, nullptr, &one}, whole, 1.0, 0.0);
    CHECK(natural_map_residual(BoxedProblem{p.A, p.b, p.lo, p.hi}, whole) <= 1e-9 * scale);
  }
}

TEST_CASE("block PGS on a resting stack reaches the direct path's v2 (7.1.1, 6.2)",
          "[direct][pgs][contact]") {
  // 5 boxes: 5 manifolds of 4 points, 12 rows each, every block of rank 6. From lambda = 0,
  // 400 block sweeps against row-by-row PGS with as many sweeps; the direct path is the
  // reference for the unique v2 (6.2).
  Scene scene = make_builtin_scene("stack", {{"n", "5"}});
  const Simulation sim(scene);
  const System sys = sim.build_system();
  REQUIRE(sys.rows() == 60);
  VecX exact = VecX::Zero(sys.rows());
  REQUIRE(solve_direct(sys.problem(), exact).termination == Termination::Direct);
  const VecX v2 = compute_v2(sys.v1, sys.Minv, sys.J, exact, sys.fext, sys.dt);
  const auto error_after = [&](Method method) {
    SolverOptions options;
    options.method = method;
    options.max_iterations = 400;
    VecX lambda = VecX::Zero(sys.rows());
    solve(sys.problem(), lambda, options);  // the problem's blocks: one per contact manifold
    return (compute_v2(sys, lambda) - v2).lpNorm<Eigen::Infinity>();
  };
  const double block = error_after(Method::BlockPgs);
  const double rows = error_after(Method::Pgs);
  INFO("max |v2 - v2_direct| after 400 sweeps: block PGS " << block << " m/s, PGS " << rows
                                                           << " m/s");
  CHECK(block < 1e-6);
  CHECK(block < 0.01 * rows);
}
