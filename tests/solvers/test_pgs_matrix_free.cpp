// The matrix-free form of 7.1.1 (sequential impulses), which must give the explicit-A iterates to
// round-off: the two formulations are one method.
#include <algorithm>
#include <catch2/catch.hpp>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "cbps/solvers/paper/pgs.hpp"
#include "cbps/solvers/paper/pgs_matrix_free.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/system/boxed_problem.hpp"
#include "cbps/system/system.hpp"
#include "fixture.hpp"

using namespace cbps;
using test::system_of;

TEST_CASE("matrix-free PGS gives explicit-A PGS's iterates to round-off (7.1.1)",
          "[solver][variants][eq7.1.1]") {
  // Contacts with friction (paper bounds and Coulomb), a chain with an end-mass ratio, each in
  // natural and reverse order and with over-relaxation: 40 sweeps from lambda = 0, compared
  // after every sweep.
  struct Case {
    std::string name;
    std::map<std::string, std::string> values;
    int steps;
  };
  const Case c = GENERATE(values<Case>({
      {"chain", {{"n", "40"}, {"mass_ratio", "100"}}, 5},
      {"stack", {{"n", "4"}}, 3},
      {"pyramid", {{"base", "4"}}, 2},
      {"v-corner", {{"mu", "0.5"}}, 2},
  }));
  const RowOrder order = GENERATE(RowOrder::Natural, RowOrder::Reverse);
  const double omega = GENERATE(1.0, 1.3);
  CAPTURE(c.name, to_string(order), omega);
  const System sys = system_of(c.name, c.values, c.steps);
  REQUIRE(sys.rows() > 0);
  std::mt19937_64 rng(0);
  std::vector<int> rows;
  sweep_order(order, sys.rows(), rng, rows);
  const MatrixFreePgs matrix_free(sys.J, sys.Minv);
  VecX explicit_lambda = VecX::Zero(sys.rows()), free_lambda = explicit_lambda;
  VecX u = matrix_free.impulse(free_lambda);
  double worst = 0.0;
  for (int sweep = 0; sweep < 40; ++sweep) {
    pgs_sweep(sys.problem(), explicit_lambda, omega, rows);
    matrix_free.sweep(sys.b, sys.cmin, sys.cmax, free_lambda, u, omega, rows);
    const double scale = std::max(1.0, explicit_lambda.lpNorm<Eigen::Infinity>());
    worst = std::max(worst, (explicit_lambda - free_lambda).lpNorm<Eigen::Infinity>() / scale);
  }
  INFO("largest difference over 40 sweeps, relative to max |lambda|: " << worst);
  // Each sweep rounds A lambda two ways: a few ulps per row, carried through 40 sweeps.
  CHECK(worst < 1e-12);
  CHECK((u - matrix_free.impulse(free_lambda)).lpNorm<Eigen::Infinity>() <
        1e-9 * std::max(1.0, u.lpNorm<Eigen::Infinity>()));  // u = W lambda kept
  // The same residual with or without A.
  CHECK(matrix_free.residual(sys.b, sys.cmin, sys.cmax, free_lambda, u) ==
        Approx(natural_map_residual(sys.problem(), free_lambda)).epsilon(1e-8).margin(1e-12));
}
