// The exact path's Newton systems (src/solvers/exact/newton_system.hpp, private to the library):
// body space's factor of H = M + Jᵀ D⁻¹ J kept through rank-one updates as rows join or leave
// must solve exactly what a fresh factorization solves, its product A x = J Minv Jᵀ x must be
// A's, and a stored A that is not J Minv Jᵀ must not be solved in body space. Expected values:
// a dense LDLᵀ of (A + diag d) on the kept rows (Eigen, independent of CHOLMOD).
#include <Eigen/Cholesky>
#include <catch2/catch.hpp>
#include <vector>

#include "../src/solvers/exact/newton_system.hpp"
#include "cbps/step/simulation.hpp"
#include "cbps/system/system.hpp"
#include "fixture.hpp"

using namespace cbps;

namespace {

/// x = (A + diag d)⁻¹ r on the kept rows, 0 on the dropped ones, densely.
VecX dense_solve(const SpMat& A, const VecX& d, const std::vector<char>& dropped, const VecX& r) {
  std::vector<Eigen::Index> kept;
  for (Eigen::Index k = 0; k < A.rows(); ++k)
    if (!dropped[std::size_t(k)]) kept.push_back(k);
  const MatX dense = MatX(A);
  const Eigen::Index m = static_cast<Eigen::Index>(kept.size());
  MatX K(m, m);
  VecX rk(m);
  for (Eigen::Index i = 0; i < m; ++i) {
    rk(i) = r(kept[std::size_t(i)]);
    for (Eigen::Index j = 0; j < m; ++j)
      K(i, j) = dense(kept[std::size_t(i)], kept[std::size_t(j)]) +
                (i == j ? d(kept[std::size_t(i)]) : 0.0);
  }
  const VecX xk = K.ldlt().solve(rk);
  VecX x = VecX::Zero(A.rows());
  for (Eigen::Index i = 0; i < m; ++i) x(kept[std::size_t(i)]) = xk(i);
  return x;
}

/// A resting 3-column stack of 4 boxes, one PGS step in: contact and friction rows, A singular.
const System& stack_system() {
  static const System sys = [] {
    Simulation sim(test::contact_scene("stack", {{"n", "4"}, {"columns", "3"}}, "pgs"));
    sim.step();
    return sim.build_system();
  }();
  return sys;
}

}  // namespace

TEST_CASE("body space: a factor updated as rows leave and join solves what a fresh one solves",
          "[direct][newton]") {
  const System& sys = stack_system();
  const BoxedProblem problem = sys.problem();
  const Eigen::Index c = problem.rows();
  REQUIRE(c > 40);
  std::shared_ptr<NewtonSystem> updated = make_body_space(problem);
  REQUIRE(updated != nullptr);
  CHECK(std::string(updated->space()) == "body");

  // d: the proximal ε of the crossover, 1e-6 · max A_kk, on every row.
  const double eps = 1e-6 * VecX(problem.A.diagonal()).maxCoeff();
  const VecX d = VecX::Constant(c, eps);
  std::vector<char> dropped(std::size_t(c), 0);
  for (Eigen::Index k = 0; k < c; k += 3) dropped[std::size_t(k)] = 1;
  REQUIRE(updated->factor(d, dropped));
  // A few rows leave, a few join: updates (rows 1, 4, 7 leave; 0, 6 join).
  for (const int k : {1, 4, 7}) dropped[std::size_t(k)] = 1;
  for (const int k : {0, 6}) dropped[std::size_t(k)] = 0;
  REQUIRE(updated->factor(d, dropped));
  CHECK(updated->factorizations() == 1);
  CHECK(updated->updates() == 5);

  std::shared_ptr<NewtonSystem> fresh = make_body_space(problem);
  REQUIRE(fresh->factor(d, dropped));
  CHECK(fresh->updates() == 0);

  VecX r(c);
  for (Eigen::Index k = 0; k < c; ++k) r(k) = std::cos(0.7 * double(k));  // m/s²
  const VecX expected = dense_solve(problem.A, d, dropped, r);
  VecX x_updated, x_fresh;
  REQUIRE(updated->solve(d, dropped, r, x_updated));
  REQUIRE(fresh->solve(d, dropped, r, x_fresh));
  // (A + εI) on the kept rows has condition about max A_kk / ε = 1e6: with two refinements
  // both solves reach the dense answer to 1e-9 relative, far below what a wrong factor gives
  // (a row left in or out changes x by O(1) relative).
  const double scale = expected.lpNorm<Eigen::Infinity>();
  INFO("|x| " << scale);
  CHECK((x_updated - expected).lpNorm<Eigen::Infinity>() <= 1e-9 * scale);
  CHECK((x_fresh - expected).lpNorm<Eigen::Infinity>() <= 1e-9 * scale);
  for (Eigen::Index k = 0; k < c; ++k)
    if (dropped[std::size_t(k)]) CHECK(x_updated(k) == 0.0);

  // A changed weight on a kept row is no update: the factor is made anew.
  VecX d2 = d;
  d2(2) = 2.0 * eps;
  REQUIRE(updated->factor(d2, dropped));
  CHECK(updated->factorizations() == 2);
  REQUIRE(updated->solve(d2, dropped, r, x_updated));
  const VecX expected2 = dense_solve(problem.A, d2, dropped, r);
  CHECK((x_updated - expected2).lpNorm<Eigen::Infinity>() <= 1e-9 * scale);
}

TEST_CASE(
    "body space: A x as J (Minv (Jt x)) is A's product, and an A that is not J Minv Jt "
    "is refused",
    "[direct][newton]") {
  const System& sys = stack_system();
  const BoxedProblem problem = sys.problem();
  const Eigen::Index c = problem.rows();
  std::shared_ptr<NewtonSystem> body = make_body_space(problem);
  REQUIRE(body != nullptr);
  VecX x(c), y;
  for (Eigen::Index k = 0; k < c; ++k) x(k) = 1.0 + double(k % 7);  // N
  body->times_A(x, y);
  const VecX expected = problem.A * x;
  CHECK((y - expected).lpNorm<Eigen::Infinity>() <= 1e-12 * expected.lpNorm<Eigen::Infinity>());

  // One entry of A changed (symmetrically): the stored A no longer equals J Minv Jᵀ, so body
  // space would solve another problem; make_newton_system falls back to row space, on A.
  SpMat changed = problem.A;
  changed.coeffRef(0, 0) *= 1.5;
  const BoxedProblem other{changed, problem.b, problem.cmin, problem.cmax, problem.J, problem.Minv};
  CHECK(make_body_space(other) == nullptr);
  std::shared_ptr<NewtonSystem> row = make_newton_system(other);
  CHECK(std::string(row->space()) == "row");
  row->times_A(x, y);
  CHECK(y == changed * x);
}

TEST_CASE(
    "body space kept in an ExactMemory serves the next problem of J's pattern and solves what a "
    "fresh one solves",
    "[direct][newton]") {
  const System& sys = stack_system();
  const BoxedProblem problem = sys.problem();
  const Eigen::Index c = problem.rows();
  const std::shared_ptr<ExactMemory> memory = make_exact_memory();
  const std::shared_ptr<NewtonSystem> first = make_body_space(problem, memory.get());
  REQUIRE(first != nullptr);
  VecX d = VecX::Constant(c, 1e-3 * problem.A.diagonal().maxCoeff());
  std::vector<char> dropped(std::size_t(c), 0);
  REQUIRE(first->factor(d, dropped));
  // The next step's problem: the same pattern of J, other values (here Minv halved, so A too).
  const SpMat Minv2 = 0.5 * *problem.Minv;
  const SpMat A2 = 0.5 * problem.A;
  const BoxedProblem next{A2, problem.b, problem.cmin, problem.cmax, problem.J, &Minv2};
  const std::shared_ptr<NewtonSystem> kept = make_body_space(next, memory.get());
  CHECK(kept.get() == first.get());  // the same object: its pattern and analysis reused
  CHECK(kept->factorizations() == 0);
  for (Eigen::Index k = 0; k < c; k += 3) dropped[std::size_t(k)] = 1;
  VecX r(c), x;
  for (Eigen::Index k = 0; k < c; ++k) r(k) = std::sin(0.3 * double(k));  // m/s²
  REQUIRE(kept->factor(d, dropped));
  REQUIRE(kept->solve(d, dropped, r, x));
  const VecX expected = dense_solve(A2, d, dropped, r);
  CHECK((x - expected).lpNorm<Eigen::Infinity>() <= 1e-9 * expected.lpNorm<Eigen::Infinity>());
  // A J of another pattern (its last row left out) gets a body space of its own.
  const SpMatRow J3 = problem.J->topRows(c - 1);
  const SpMat A3 = problem.A.topLeftCorner(c - 1, c - 1);
  const VecX b3 = problem.b.head(c - 1), lo3 = problem.cmin.head(c - 1),
             hi3 = problem.cmax.head(c - 1);
  const BoxedProblem smaller{A3, b3, lo3, hi3, &J3, problem.Minv};
  const std::shared_ptr<NewtonSystem> other = make_body_space(smaller, memory.get());
  REQUIRE(other != nullptr);
  CHECK(other.get() != first.get());
}
