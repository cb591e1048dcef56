// Contacts before friction: Gauss-Seidel sweeps (7.1.1) that visit every distance row, then every
// contact normal row (5.3), then every friction row (5.4), as Bullet's sequential-impulse solver
// does (SolverOptions::contacts_first, SweepOrder).
#include <algorithm>
#include <catch2/catch.hpp>
#include <map>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "cbps/solvers/paper/coulomb.hpp"
#include "cbps/solvers/paper/pgs.hpp"
#include "cbps/solvers/paper/pgs_matrix_free.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/system/system.hpp"
#include "fixture.hpp"

using namespace cbps;
using test::system_of;

namespace {
constexpr double kEps = 2.220446049250313e-16;
const std::vector<RowKind> kKinds = {RowKind::Distance,
                                     RowKind::Contact,
                                     RowKind::Friction,
                                     RowKind::Friction,
                                     RowKind::Contact,
                                     RowKind::Friction,
                                     RowKind::Friction,
                                     RowKind::Distance};
}  // namespace

TEST_CASE("contacts first: distance rows, then contact rows, then friction rows, each in order",
          "[contacts_first][eq7.1.1]") {
  std::mt19937_64 rng(7);
  std::vector<int> rows;
  sweep_order(RowOrder::Natural, kKinds, rng, rows);
  CHECK(rows == std::vector<int>{0, 7, 1, 4, 2, 3, 5, 6});
  sweep_order(RowOrder::Reverse, kKinds, rng, rows);
  CHECK(rows == std::vector<int>{7, 0, 4, 1, 6, 5, 3, 2});
  // Random: each group a permutation of its own rows, fresh every sweep.
  std::vector<std::vector<int>> seen;
  for (int sweep = 0; sweep < 20; ++sweep) {
    sweep_order(RowOrder::Random, kKinds, rng, rows);
    REQUIRE(rows.size() == kKinds.size());
    std::vector<int> distance(rows.begin(), rows.begin() + 2);
    std::vector<int> contact(rows.begin() + 2, rows.begin() + 4);
    std::vector<int> friction(rows.begin() + 4, rows.end());
    std::sort(distance.begin(), distance.end());
    std::sort(contact.begin(), contact.end());
    std::sort(friction.begin(), friction.end());
    CHECK(distance == std::vector<int>{0, 7});
    CHECK(contact == std::vector<int>{1, 4});
    CHECK(friction == std::vector<int>{2, 3, 5, 6});
    if (std::find(seen.begin(), seen.end(), rows) == seen.end()) seen.push_back(rows);
  }
  CHECK(seen.size() > 5);  // 2·2·24 = 96 orders possible; 20 sweeps find many of them
}

TEST_CASE(
    "contacts first: PGS and matrix-free sweep in that order and reach the direct path's "
    "answer (7.1.1, 6.2)",
    "[contacts_first][eq7.1.1][eq6.2]") {
  struct Case {
    std::string name;
    std::map<std::string, std::string> values;
    int steps;
  };
  const Case c = GENERATE(values<Case>({
      {"stack", {{"n", "3"}, {"mu", "0.5"}}, 10},
      {"stack", {{"n", "2"}, {"columns", "2"}, {"mu", "0.5"}}, 10},  // two islands
  }));
  const RowOrder order = GENERATE(RowOrder::Natural, RowOrder::Reverse, RowOrder::Random);
  CAPTURE(c.name, to_string(order));
  const System sys = system_of(c.name, c.values, c.steps);
  const BoxedProblem problem = sys.problem();
  REQUIRE(std::count(sys.kind.begin(), sys.kind.end(), RowKind::Friction) > 0);

  SolverOptions options;
  options.order = order;
  options.contacts_first = true;
  options.seed = 11;
  options.split_islands = false;  // sweep for sweep: the whole problem, one rng

  // One sweep of solve_pgs is one pgs_sweep in the grouped order (the same rng draws).
  std::mt19937_64 rng(options.seed);
  std::vector<int> rows;
  sweep_order(order, sys.kind, rng, rows);
  VecX by_hand = VecX::Zero(sys.rows());
  pgs_sweep(problem, by_hand, 1.0, rows);
  options.max_iterations = 1;
  VecX lambda = VecX::Zero(sys.rows());
  solve_pgs(problem, lambda, options);
  CHECK(lambda == by_hand);
  // ...which is not the ungrouped sweep (the friction rows see other normal forces).
  options.contacts_first = false;
  VecX interleaved = VecX::Zero(sys.rows());
  solve_pgs(problem, interleaved, options);
  CHECK(interleaved != lambda);
  options.contacts_first = true;

  // The matrix-free form gives the same iterates to round-off (40 sweeps).
  options.max_iterations = 40;
  VecX explicit_lambda = VecX::Zero(sys.rows()), free_lambda = explicit_lambda;
  options.method = Method::Pgs;
  solve(problem, explicit_lambda, options);
  options.method = Method::MatrixFree;
  solve(problem, free_lambda, options);
  const double scale = std::max(1.0, explicit_lambda.lpNorm<Eigen::Infinity>());
  // Each sweep rounds A lambda two ways: a few ulps per row, carried through 40 sweeps (as in
  // test_pgs_matrix_free.cpp).
  CHECK((explicit_lambda - free_lambda).lpNorm<Eigen::Infinity>() < 1e-12 * scale);

  // To a tolerance, through solve() with islands: w and v2 are the direct path's.
  SolverOptions direct;
  direct.method = Method::Direct;
  direct.tolerance = 0.0;  // to the rounding floor
  VecX reference = VecX::Zero(sys.rows());
  REQUIRE(solve(problem, reference, direct).termination == Termination::Direct);
  for (const Method method : {Method::Pgs, Method::MatrixFree}) {
    CAPTURE(to_string(method));
    options.method = method;
    options.split_islands = true;
    options.max_iterations = 200000;
    options.tolerance = 1e3 * kEps * scale_of(problem);
    lambda = VecX::Zero(sys.rows());
    const SolverSummary s = solve(problem, lambda, options);
    INFO(s.message);
    CHECK(s.termination == Termination::ResidualTolerance);
    const double w_error =
        (sys.A * lambda - sys.b - (sys.A * reference - sys.b)).lpNorm<Eigen::Infinity>();
    const double v2_error =
        (compute_v2(sys, lambda) - compute_v2(sys, reference)).lpNorm<Eigen::Infinity>();
    INFO("|w - w_direct| " << w_error << " m/s², |v2 - v2_direct| " << v2_error << " m/s");
    // |w - w*| ≤ k·tolerance with k from the every-solver test's measured ratio (≤ 1, so 10 is
    // loose); v2 = v1 + dt Minv (Jᵀ lambda + fext) moves by dt times that per unit of A.
    CHECK(w_error <= 10.0 * options.tolerance);
    CHECK(v2_error <= 10.0 * sys.dt * options.tolerance);
  }
}

TEST_CASE("contacts first needs the rows' kinds, and Coulomb friction keeps them",
          "[contacts_first]") {
  const System sys = system_of("stack", {{"n", "2"}, {"mu", "0.5"}, {"friction", "coulomb"}}, 5);
  SolverOptions options;
  options.contacts_first = true;
  options.max_iterations = 50;
  VecX lambda = VecX::Zero(sys.rows());
  const BoxedProblem stored{sys.A, sys.b, sys.cmin, sys.cmax};  // no kinds, as a stored problem
  CHECK_THROWS_AS(solve(stored, lambda, options), std::invalid_argument);
  // The Coulomb fixed point hands each boxed problem on with the kinds (solve_coulomb).
  const SolverSummary s = solve_coulomb(sys.problem(), sys.coulomb(), lambda, options);
  CHECK(s.ok());
  CHECK(s.iterations > 0);
}
