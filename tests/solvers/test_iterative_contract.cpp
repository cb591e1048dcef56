// The contract every iterative method keeps through solve() (solver.hpp): the iteration limit,
// after_sweep (called after each iteration with its count and a λ in the box; false stops), the
// residual and change tolerances, a warm start already within the tolerance taking no
// iteration, describe, and NaN in b ending NonFinite instead of iterating on. One test for all
// of all_methods() that sweep, so a method added there is held to it at once.
#include <algorithm>
#include <catch2/catch.hpp>
#include <iterator>
#include <limits>
#include <vector>

#include "cbps/solvers/methods.hpp"
#include "cbps/solvers/peers/peers.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/system/boxed_problem.hpp"
#include "cbps/system/system.hpp"
#include "fixture.hpp"
#include "methods_fixture.hpp"

using namespace cbps;
using test::in_box;
using test::system_of;

namespace {

/// cbps's own iterative methods; the peers (siconos:pgs, bullet:pgs) expose no sweep hook and
/// keep their own contract (test_peers.cpp).
std::vector<Method> iterative_methods() {
  std::vector<Method> methods;
  for (const Method m : all_methods())
    if (is_iterative(m) && !is_peer(m)) methods.push_back(m);
  return methods;
}

}  // namespace

TEST_CASE("every iterative method keeps the contract: limits, hook, tolerances, warm start, NaN",
          "[solver]") {
  const Method method = GENERATE(from_range(iterative_methods()));
  // The base-4 pyramid after 30 steps: 192 rows, bounded contact and friction rows, A singular.
  const System sys = system_of("pyramid", {{"base", "4"}}, 30);
  const BoxedProblem problem = sys.problem();
  INFO(to_string(method) << " on " << sys.rows() << " rows");
  SolverOptions options;
  options.method = method;
  // Projected Jacobi diverges here undamped (2 / L < 1 on a pyramid, as on the stack of
  // test_every_solver_agrees.cpp); 0.25 converges.
  if (method == Method::Jacobi) options.relaxation = 0.25;

  // The iteration limit.
  options.max_iterations = 7;
  VecX lambda = VecX::Zero(sys.rows());
  SolverSummary s = solve(problem, lambda, options);
  CHECK(s.iterations == 7);
  CHECK(s.termination == Termination::MaxIterations);
  // The matrix-free sweep forms w from u = W λ, its own way: equal to rounding.
  CHECK(s.residual == Approx(natural_map_residual(problem, lambda)).epsilon(1e-9));
  CHECK_FALSE(s.message.empty());

  // after_sweep: each iteration's count in order, λ in the box; false stops at once.
  int calls = 0;
  bool in_order = true, all_in_box = true;
  options.max_iterations = 1000;
  options.after_sweep = [&](int iteration, const VecX& l, double seconds) {
    ++calls;
    in_order = in_order && iteration == calls && seconds >= 0.0;
    all_in_box = all_in_box && in_box(problem, l);
    return iteration < 12;
  };
  lambda.setZero();
  s = solve(problem, lambda, options);
  CHECK(s.termination == Termination::Stopped);
  CHECK(s.iterations == 12);
  CHECK(calls == 12);
  CHECK(in_order);
  CHECK(all_in_box);
  options.after_sweep = nullptr;

  // The residual tolerance (1e-3 of the problem's scale: every method reaches it here), then a
  // warm start from that answer: already within it, no iteration.
  options.max_iterations = 100000;
  options.tolerance = 1e-3 * scale_of(problem);
  lambda.setZero();
  s = solve(problem, lambda, options);
  INFO(s.message);
  REQUIRE(s.termination == Termination::ResidualTolerance);
  CHECK(natural_map_residual(problem, lambda) <= options.tolerance);
  CHECK(s.iterations > 0);
  s = solve(problem, lambda, options);
  CHECK(s.termination == Termination::ResidualTolerance);
  CHECK(s.iterations == 0);

  // The change tolerance: stops once an iteration moves λ by at most it.
  options.tolerance = 0.0;
  options.delta_tolerance = 1e-3;
  lambda.setZero();
  s = solve(problem, lambda, options);
  CHECK(s.termination == Termination::DeltaTolerance);
  CHECK(s.delta <= 1e-3);
  options.delta_tolerance = 0.0;

  // describe = false: no message.
  options.describe = false;
  options.max_iterations = 3;
  lambda.setZero();
  CHECK(solve(problem, lambda, options).message.empty());
  options.describe = true;

  // NaN in b: NonFinite within a few iterations (the first sweep meets it), never a hang on the
  // full budget.
  VecX b = sys.b;
  b(1) = std::numeric_limits<double>::quiet_NaN();
  BoxedProblem bad{sys.A, b, sys.cmin, sys.cmax};
  bad.J = problem.J;  // the matrix-free sweep reads J and Minv
  bad.Minv = problem.Minv;
  bad.blocks = problem.blocks;
  options.max_iterations = 100000;
  options.tolerance = 1e-6;
  lambda.setZero();
  s = solve(bad, lambda, options);
  CHECK(s.termination == Termination::NonFinite);
  CHECK(s.iterations <= 2);
}
