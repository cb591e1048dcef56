// A step's problem with A = J Minv Jᵀ left out (issue 32, "leave out what the solver does not
// read"): the problem's functions (times_A, diagonal_of_A, scale_of, the natural map, islands)
// against the same problem with A formed by compute_A, the direct path's answer against its
// answer on A formed, solve() forming A for the methods that read it, and a simulation stepped
// by the direct path against the same simulation forced to form A.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "cbps/solvers/exact/direct.hpp"
#include "cbps/solvers/islands.hpp"
#include "cbps/solvers/paper/coulomb.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/step/simulation.hpp"
#include "cbps/system/boxed_problem.hpp"
#include "cbps/system/system.hpp"
#include "fixture.hpp"

using namespace cbps;

namespace {

double inf_norm(const VecX& v) { return v.size() > 0 ? v.lpNorm<Eigen::Infinity>() : 0.0; }

/// A step's system twice: as the step assembles it with A formed, and with A left out (the
/// same J, Minv, b and bounds; its A empty).
struct TwoForms {
  System formed;
  System left_out;
  TwoForms(const std::string& name, const std::map<std::string, std::string>& values, int steps)
      : formed(test::system_of(name, values, steps)), left_out(formed) {
    left_out.A.resize(0, 0);
  }
};

struct Case {
  std::string name;
  std::map<std::string, std::string> values;
  int steps;
};

// A pyramid (one island, friction boxes), a stack of three columns (three islands), the chain
// (distance rows alone, no bounded row) and the pyramid under Coulomb's friction.
const std::vector<Case> kCases = {
    {"pyramid", {{"base", "6"}}, 30},
    {"stack", {{"columns", "3"}, {"n", "4"}}, 30},
    {"chain", {{"n", "8"}}, 10},
    {"pyramid", {{"base", "4"}, {"friction", "coulomb"}}, 20},
};

}  // namespace

TEST_CASE("A left out: the problem's products, diagonal, scale and islands are A's",
          "[direct][system]") {
  const Case c = GENERATE(from_range(kCases));
  const TwoForms two(c.name, c.values, c.steps);
  const BoxedProblem formed = two.formed.problem();
  const BoxedProblem left_out = two.left_out.problem();
  INFO(c.name << ": " << formed.rows() << " rows");
  REQUIRE(formed.rows() > 0);
  REQUIRE(formed.A_formed());
  REQUIRE_FALSE(left_out.A_formed());
  const SpMat& A = two.formed.A;
  const double size = MatX(A).cwiseAbs().maxCoeff();
  VecX x(formed.rows());
  for (Eigen::Index k = 0; k < x.size(); ++k) x(k) = std::cos(0.7 * double(k)) * 100.0;  // N
  // J (Minv (Jᵀ x)) against A x: the same sums in another order, so to rounding.
  CHECK(inf_norm(times_A(left_out, x) - A * x) <= 1e-13 * size * inf_norm(x) * 12);
  CHECK(inf_norm(diagonal_of_A(left_out) - VecX(A.diagonal())) <= 1e-14 * size);
  CHECK(scale_of(left_out) == Approx(scale_of(formed)).epsilon(1e-13));
  CHECK(scale_of(left_out, 1e-3) == Approx(scale_of(formed, 1e-3)).epsilon(1e-13));
  CHECK(natural_map_residual(left_out, x) ==
        Approx(natural_map_residual(formed, x)).epsilon(1e-12));
  // The bound |J| |Minv| |J|ᵀ 1 is at least ‖A‖∞ (triangle inequality), and on a step's rows
  // (unit normals, lever arms of the bodies' size) within a small factor of it.
  const double bound = max_abs_row_sum(left_out), row_sum = max_abs_row_sum(A);
  CHECK(bound >= row_sum * (1.0 - 1e-14));
  CHECK(bound <= 10.0 * row_sum);
  CHECK(find_islands(left_out) == find_islands(A));
  // A formed from J and Minv is the step's A itself.
  CHECK(MatX(formed_A(left_out)) == MatX(A));
}

TEST_CASE("A left out: the direct path gives the answer it gives with A formed",
          "[direct][interior]") {
  const Case c = GENERATE(from_range(kCases));
  const double cfm = GENERATE(0.0, 1e-6);  // kg⁻¹
  const TwoForms two(c.name, c.values, c.steps);
  const BoxedProblem formed = two.formed.problem();
  const BoxedProblem left_out = two.left_out.problem();
  SolverOptions options = SolverSettings{}.options();
  options.method = Method::Direct;
  options.cfm = cfm;
  const int interior_from = GENERATE(0, 100000);  // the interior point, or the active set
  options.direct.interior_from_rows = interior_from;
  VecX with_A, without_A;
  const SolverSummary s_formed = solve_coulomb(formed, two.formed.coulomb(), with_A, options);
  const SolverSummary s_left = solve_coulomb(left_out, two.left_out.coulomb(), without_A, options);
  INFO(c.name << ", cfm " << cfm << ", interior from " << interior_from
              << " rows\nformed: " << s_formed.message << "\nleft out: " << s_left.message);
  REQUIRE(s_formed.termination == Termination::Direct);
  CHECK(s_left.termination == Termination::Direct);
  CHECK(s_left.route == s_formed.route);
  const double scale = scale_of(formed, cfm);
  // Its own residual, computed on A formed (the one the caller would check it with).
  const double residual = coulomb_residual(formed, two.formed.coulomb(), without_A, cfm);
  CHECK(residual <= 1e-10 * scale);
  // w and Jᵀλ are unique where λ need not be (a degenerate contact set): as body against row
  // space in test_direct_interior.cpp.
  const SpMat& A = two.formed.A;
  CHECK(inf_norm(A * (without_A - with_A) + cfm * (without_A - with_A)) <= 1e-7 * scale);
  const VecX f = two.formed.J.transpose() * with_A;
  CHECK(inf_norm(two.formed.J.transpose() * without_A - f) <= 1e-7 * std::max(1.0, inf_norm(f)));
}

TEST_CASE("A left out: solve() forms A for a method that reads it", "[solver][system]") {
  const TwoForms two("stack", {{"columns", "3"}, {"n", "4"}}, 30);
  const Method method = GENERATE(Method::Pgs, Method::Lemke, Method::ActiveSet, Method::Nncg);
  SolverOptions options = SolverSettings{}.options();
  options.method = method;
  options.max_iterations = 50;
  VecX with_A, without_A;
  const SolverSummary a = solve(two.formed.problem(), with_A, options);
  const SolverSummary b = solve(two.left_out.problem(), without_A, options);
  INFO(to_string(method) << ": " << a.message << " / " << b.message);
  CHECK(a.termination == b.termination);
  CHECK(a.iterations == b.iterations);
  CHECK(without_A == with_A);  // the same A, the same arithmetic
  // matrix-free reads J and Minv alone: the same answer either way, A never formed.
  options.method = Method::MatrixFree;
  VecX mf_A, mf_left;
  solve(two.formed.problem(), mf_A, options);
  solve(two.left_out.problem(), mf_left, options);
  CHECK(mf_left == mf_A);
}

TEST_CASE("A left out: a scene stepped by the direct path moves as with A formed",
          "[direct][simulation]") {
  const std::string push = GENERATE("original", "improved");
  // Base 10: over 500 rows (below, the direct path's active set factors A: it is formed).
  const std::map<std::string, std::string> values = {{"base", "10"}, {"push", push}};
  Simulation plain(test::contact_scene("pyramid", values, "direct"));
  Simulation observed(test::contact_scene("pyramid", values, "direct"));
  long observed_rows = 0;
  observed.set_observer([&](const System& sys, const VecX&, const VecX&) {
    observed_rows += sys.A.rows();  // an observer sees A formed
  });
  CHECK_FALSE(plain.forms_A(500));
  CHECK(plain.forms_A(499));
  CHECK(observed.forms_A(500));
  for (int s = 0; s < 60; ++s) {
    plain.step();
    observed.step();
  }
  CHECK(observed_rows > 0);
  const auto& stages = plain.stages();
  CHECK(std::find(stages.begin(), stages.end(), "assembly (6.1, 6.2.9 without A)") != stages.end());
  const auto& formed_stages = observed.stages();
  CHECK(std::find(formed_stages.begin(), formed_stages.end(), "assembly (6.1, 6.2.9)") !=
        formed_stages.end());
  // Both solve each step to 1e-10 of its scale; the answers' w agree to 1e-7 of it (above), so
  // the bodies (about 1 m, moving about 1e-3 m) agree far below a micrometre after 60 steps.
  double apart = 0.0;
  for (std::size_t i = 0; i < plain.scene().bodies.size(); ++i)
    apart = std::max(apart, (plain.scene().bodies[i].x - observed.scene().bodies[i].x).norm());
  CHECK(apart <= 1e-9);
  // PGS reads A: its steps form it.
  Simulation pgs(test::contact_scene("pyramid", values, "pgs"));
  CHECK(pgs.forms_A(500));
  Simulation matrix_free(test::contact_scene("pyramid", values, "matrix-free"));
  CHECK_FALSE(matrix_free.forms_A(10));
}
