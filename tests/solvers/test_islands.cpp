// Islands of A (6.2.9): the connected blocks of A, found in order, and the islands of a scene.
#include <catch2/catch.hpp>
#include <utility>
#include <vector>

#include "cbps/solvers/islands.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/step/simulation.hpp"
#include "cbps/system/system.hpp"
#include "fixture.hpp"

using namespace cbps;
using test::contact_scene;

TEST_CASE("islands are the connected blocks of A, found in order of their first row", "[direct]") {
  // Rows {0, 3, 5}, {1, 4} and {2}: a permuted block diagonal.
  std::vector<Triplet> t;
  for (const auto& [i, j] : std::vector<std::pair<int, int>>{{0, 3}, {3, 5}, {1, 4}}) {
    t.emplace_back(i, j, 1.0);
    t.emplace_back(j, i, 1.0);
  }
  for (int i = 0; i < 6; ++i) t.emplace_back(i, i, 4.0);
  SpMat A(6, 6);
  A.setFromTriplets(t.begin(), t.end());
  const auto islands = find_islands(A);
  REQUIRE(islands.size() == 3);
  CHECK(islands[0] == std::vector<int>{0, 3, 5});
  CHECK(islands[1] == std::vector<int>{1, 4});
  CHECK(islands[2] == std::vector<int>{2});
}

TEST_CASE("separate columns of boxes are separate islands of A (6.2.9)", "[contact][eq6.2.9]") {
  // 3 columns of 3 boxes, 0.5 m apart: no contact joins two columns, and the ground has no
  // columns of its own, so A splits into one block per column.
  Simulation sim(contact_scene("stack", {{"n", "3"}, {"columns", "3"}}, "direct"));
  const System& sys = sim.assemble();
  const std::vector<std::vector<int>> islands = find_islands(sys.A);
  System left_out = sys;  // the islands through J and Minv alone (A left out) are the same
  left_out.A.resize(0, 0);
  CHECK(find_islands(left_out.problem()) == islands);
  CHECK(islands.size() == 3);
  for (const std::vector<int>& island : islands) CHECK(island.size() == 3 * 4 * 3);
  VecX lambda = VecX::Zero(sys.rows());
  const SolverSummary s = sim.solve_system(sys, lambda);
  INFO(s.message);
  CHECK(s.termination == Termination::Direct);
  // The active-set path solves them apart.
  SolverOptions apart;
  apart.method = Method::ActiveSet;
  VecX lambda_apart = VecX::Zero(sys.rows());
  const SolverSummary a = solve(sys.problem(), lambda_apart, apart);
  INFO(a.message);
  CHECK(a.islands == 3);
  CHECK(a.termination == Termination::Direct);
}
