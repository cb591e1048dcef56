// Red-black (multicolour) PGS (rbgs.hpp): the colouring is valid and a chain needs two colours,
// the rows of one colour are independent (the sweep is what a parallel engine computes), it
// reaches the direct path's w and v2 on real problems, and the solve contract.
#include <algorithm>
#include <catch2/catch.hpp>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "cbps/solvers/compared/rbgs.hpp"
#include "cbps/solvers/paper/pgs.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/system/boxed_problem.hpp"
#include "cbps/system/system.hpp"
#include "fixture.hpp"
#include "methods_fixture.hpp"

using namespace cbps;
using test::kEps;
using test::kSweepTolerance;
using test::kVelocityPerResidual;
using test::Problem;
using test::system_of;

namespace {

/// w against the residual: |w − w_direct|∞ / tolerance, measured 0.98 to 1.0 on the problems
/// below; 2^5 leaves more than ten times that.
constexpr double kWPerResidual = 32.0;

/// The problems of test_admm.cpp: a chain (tridiagonal A), the 10-box stack after 30 steps, a
/// base-3 pyramid after 30 steps.
const std::initializer_list<Problem> kProblems = {
    {"chain", {{"n", "20"}, {"mass_ratio", "10"}}, 10},
    {"stack", {{"n", "10"}}, 30},
    {"pyramid", {{"base", "3"}}, 30},
};

/// No two rows of one colour are coupled (A_ik ≠ 0, i ≠ k), and order/start list every row once,
/// grouped by colour.
void check_colouring(const SpMat& A, const RowColouring& g) {
  REQUIRE(g.colour.size() == std::size_t(A.rows()));
  int coupled_pairs_of_one_colour = 0;
  for (Eigen::Index k = 0; k < A.outerSize(); ++k)
    for (SpMat::InnerIterator it(A, k); it; ++it)
      if (it.row() != k && it.value() != 0.0 &&
          g.colour[std::size_t(it.row())] == g.colour[std::size_t(k)])
        ++coupled_pairs_of_one_colour;
  CHECK(coupled_pairs_of_one_colour == 0);
  REQUIRE(g.start.size() == std::size_t(g.colours) + 1);
  CHECK(g.start.back() == A.rows());
  std::vector<int> seen(g.order.size(), 0);
  for (int colour = 0; colour < g.colours; ++colour) {
    CHECK(g.start[std::size_t(colour)] < g.start[std::size_t(colour) + 1]);  // no empty colour
    for (int n = g.start[std::size_t(colour)]; n < g.start[std::size_t(colour) + 1]; ++n) {
      const int k = g.order[std::size_t(n)];
      CHECK(g.colour[std::size_t(k)] == colour);
      ++seen[std::size_t(k)];
    }
  }
  CHECK(std::all_of(seen.begin(), seen.end(), [](int count) { return count == 1; }));
}

}  // namespace

TEST_CASE("the greedy colouring leaves no two coupled rows in one colour, and a chain needs two",
          "[rbgs]") {
  // A chain's rows couple only to their neighbours (a link shares a body with the links before
  // and after it): A is tridiagonal with nonzero off-diagonals, so two colours, odd and even.
  const System chain = system_of("chain", {{"n", "20"}, {"mass_ratio", "10"}}, 10);
  const RowColouring g = colour_rows(chain.A);
  check_colouring(chain.A, g);
  CHECK(g.colours == 2);
  for (int k = 0; k < chain.rows(); ++k) CHECK(g.colour[std::size_t(k)] == k % 2);

  const Problem p = GENERATE(values<Problem>(kProblems));
  const System sys = system_of(p.name, p.values, p.steps);
  const RowColouring h = colour_rows(sys.A);
  INFO(p.name << ": " << sys.rows() << " rows, " << h.colours << " colours");
  check_colouring(sys.A, h);
  // At most 1 + the most neighbours of any row (greedy colouring's bound).
  int most_neighbours = 0;
  for (Eigen::Index k = 0; k < sys.A.outerSize(); ++k) {
    int neighbours = 0;
    for (SpMat::InnerIterator it(sys.A, k); it; ++it)
      if (it.row() != k && it.value() != 0.0) ++neighbours;
    most_neighbours = std::max(most_neighbours, neighbours);
  }
  CHECK(h.colours <= most_neighbours + 1);
}

TEST_CASE("the rows of one colour are independent: any order inside a colour, the same sweep",
          "[rbgs][eq7.1.1]") {
  // What makes the sweep parallel: a row of colour g reads only rows of other colours, so
  // updating the rows of g in reverse (or all at once) gives the same iterate, bit for bit.
  const System sys = system_of("pyramid", {{"base", "3"}}, 30);
  const BoxedProblem problem = sys.problem();
  const RowColouring g = colour_rows(sys.A);
  REQUIRE(g.colours > 2);
  std::vector<int> reversed_inside = g.order;
  for (int colour = 0; colour < g.colours; ++colour)
    std::reverse(reversed_inside.begin() + g.start[std::size_t(colour)],
                 reversed_inside.begin() + g.start[std::size_t(colour) + 1]);
  VecX forward = VecX::Zero(sys.rows()), backward = forward, natural = forward;
  for (int it = 0; it < 5; ++it) {
    pgs_sweep(problem, forward, 1.3, g.order);
    pgs_sweep(problem, backward, 1.3, reversed_inside);
    pgs_sweep(problem, natural, 1.3);
  }
  CHECK((forward - backward).lpNorm<Eigen::Infinity>() == 0.0);
  // And it is a different order from the natural one (so the test above could fail).
  CHECK((forward - natural).lpNorm<Eigen::Infinity>() > 0.0);

  // solve_rbgs is exactly these sweeps, with the relaxation of the options.
  SolverOptions options;
  options.max_iterations = 5;
  options.relaxation = 1.3;
  VecX solved = VecX::Zero(sys.rows());
  const SolverSummary s = solve_rbgs(problem, solved, options);
  CHECK((solved - forward).lpNorm<Eigen::Infinity>() == 0.0);
  INFO(s.message);
  CHECK(s.message.find(std::to_string(g.colours) + " colours") != std::string::npos);
}

TEST_CASE("red-black PGS reaches the direct path's w and v2 on a chain, a stack and a pyramid",
          "[rbgs][eq6.2][eq7.1.1][eq12.3.1]") {
  // The 3-box stack of test_every_solver_agrees.cpp (mu 0.5, step 10): on the 10-box stack of
  // kProblems neither PGS nor red-black PGS gets below 6.6e-6 N in 10^5 sweeps (nor 10^6),
  // b's component in A's null space (test_every_solver_agrees.cpp explains it).
  const Problem p = GENERATE(values<Problem>({
      {"chain", {{"n", "20"}, {"mass_ratio", "10"}}, 10},
      {"stack", {{"n", "3"}, {"mu", "0.5"}}, 10},
      {"pyramid", {{"base", "3"}}, 30},
  }));
  const System sys = system_of(p.name, p.values, p.steps);
  const BoxedProblem problem = sys.problem();
  SolverOptions options;
  options.max_iterations = 100000;
  options.tolerance = kSweepTolerance * kEps * scale_of(problem);
  // The reference: the direct path at tolerance 0. On the pyramid it reports NotConverged at a
  // residual of 5.5e-11 N (see test_admm.cpp), so its residual is what is required.
  const VecX reference = test::direct_solution(sys, options.tolerance, 16.0);
  VecX lambda = VecX::Zero(sys.rows());
  const SolverSummary s = solve_rbgs(problem, lambda, options);
  INFO(p.name << ", " << sys.rows() << " rows: " << s.message);
  REQUIRE(s.termination == Termination::ResidualTolerance);
  CHECK(natural_map_residual(problem, lambda) <= options.tolerance);
  const auto [w_error, v2_error] = test::difference(sys, lambda, reference);
  INFO("|w - w_direct| " << w_error << " m/s^2 (" << w_error / options.tolerance
                         << " tolerances), |v2 - v2_direct| " << v2_error << " m/s");
  CHECK(w_error <= kWPerResidual * options.tolerance);
  CHECK(v2_error <= kVelocityPerResidual * sys.dt * options.tolerance);
}
