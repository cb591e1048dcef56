// What each method needs of A, and that none returns a wrong answer silently (issue 28, item 3):
// the sweeps of 7.1.1 read A's rows for any A, the methods that minimise the QP of 6.2 refuse a
// non-symmetric A, matrix-free refuses J and Minv that are not A's, and the exact paths solve a
// problem with a row whose j_c is zero.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cbps/base/error.hpp"
#include "cbps/solvers/exact/active_set.hpp"
#include "cbps/solvers/exact/direct.hpp"
#include "cbps/solvers/paper/pgs.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/studies/solver_spec.hpp"
#include "cbps/system/boxed_problem.hpp"
#include "cbps/system/system.hpp"
#include "fixture.hpp"

using namespace cbps;

namespace {

SpMat sparse(const MatX& dense) { return dense.sparseView(0.0, 0.0); }

/// Two copies of A = [[2, 1], [0, 2]], b = [1, 1], lambda ≥ 0, one after the other (two islands).
/// By hand, both rows interior (w = 0): row 2 gives 2 lambda_2 = 1, row 1 2 lambda_1 + lambda_2 =
/// 1, so lambda = [1/4, 1/2] (both > 0, so w = 0 is the boxed LCP's solution). Aᵀ's problem has
/// [1/2, 1/4], which the sweeps returned when they read A's columns as its rows.
struct Upper {
  SpMat A;
  VecX b = VecX::Ones(4);
  VecX cmin = VecX::Zero(4);
  VecX cmax = VecX::Constant(4, kInf);
  VecX answer = (VecX(4) << 0.25, 0.5, 0.25, 0.5).finished();
  // J for the methods that read it (shock: its levels). Not A's factors: A is not symmetric.
  SpMatRow J;
  SpMat Minv;
  std::vector<int> blocks{0, 0, 1, 1};  // block-pgs: each copy one block
  Upper() {
    MatX dense = MatX::Zero(4, 4);
    dense.block(0, 0, 2, 2) << 2, 1, 0, 2;
    dense.block(2, 2, 2, 2) << 2, 1, 0, 2;
    A = sparse(dense);
    MatX j = MatX::Zero(4, 12);  // rows on one body each: two bodies, two rows each
    j(0, 0) = j(1, 1) = j(2, 6) = j(3, 7) = 1.0;
    J = j.sparseView();
    Minv = sparse(MatX::Identity(12, 12));
  }
  BoxedProblem problem() const {
    BoxedProblem p{A, b, cmin, cmax, &J, &Minv, &blocks};
    return p;
  }
};

SolverOptions options_of(const std::string& spec) {
  const SolverSpec s = parse_solver_spec(spec);
  SolverOptions options;
  options.method = s.method;
  options.relaxation = s.relaxation;
  options.order = s.order;
  options.max_iterations = 2000;
  options.tolerance = 1e-14;
  // block-pgs: no δI on the blocks (its bias, O(δ), would hide the answer); each block here is
  // definite, so Lemke solves it as it is.
  options.block_regularization = 0.0;
  return options;
}

}  // namespace

TEST_CASE("max_asymmetry is max |A - A^T| over every entry, stored or not",
          "[solver][requirements]") {
  MatX dense(3, 3);
  dense << 4, 1, 0,  //
      1.5, 4, 2,     // A_10 = 1.5 against A_01 = 1: 0.5
      0, 2, 4;
  CHECK(max_asymmetry(sparse(dense)) == 0.5);
  dense(0, 2) = -3.0;  // its mirror A_20 = 0 is not stored: 3
  CHECK(max_asymmetry(sparse(dense)) == 3.0);
  dense(0, 2) = 0.0;
  dense(2, 0) = 2.5;  // the other way round: the lower entry has no mirror
  CHECK(max_asymmetry(sparse(dense)) == 2.5);
  dense(2, 0) = 0.0;
  dense(1, 0) = 1.0;
  CHECK(max_asymmetry(sparse(dense)) == 0.0);
  // Against the formed difference, on a random sparse non-symmetric matrix.
  MatX R = MatX::Random(30, 30);
  for (Eigen::Index i = 0; i < R.rows(); ++i)
    for (Eigen::Index k = 0; k < R.cols(); ++k)
      if ((i * 7 + k * 3) % 5 != 0) R(i, k) = 0.0;
  CHECK(max_asymmetry(sparse(R)) == (R - R.transpose()).cwiseAbs().maxCoeff());
}

TEST_CASE("every sweep of 7.1.1 reads A's rows: a non-symmetric A's solution, not A^T's",
          "[solver][requirements]") {
  const std::string spec = GENERATE(as<std::string>{},
                                    "pgs",
                                    "psor:1.3",
                                    "pgs:order=reverse",
                                    "pgs:order=random",
                                    "sgs",
                                    "jacobi",
                                    "jacobi:0.7",
                                    "rbgs",
                                    "block-pgs",
                                    "shock",
                                    "pgs-nesterov");
  const bool split = GENERATE(false, true);
  CAPTURE(spec, split);
  const Upper u;
  SolverOptions options = options_of(spec);
  options.split_islands = split;
  VecX lambda = VecX::Zero(4);
  const SolverSummary s = solve(u.problem(), lambda, options);
  CAPTURE(s.message);
  CHECK(s.termination == Termination::ResidualTolerance);
  CHECK((lambda - u.answer).lpNorm<Eigen::Infinity>() <= 1e-13);
}

TEST_CASE("the methods that minimise the QP of 6.2 refuse a non-symmetric A",
          "[solver][requirements]") {
  const std::string spec =
      GENERATE(as<std::string>{}, "apgd", "nncg", "pgs-sm", "admm", "direct", "active-set");
  CAPTURE(spec);
  const Upper u;
  VecX lambda = VecX::Zero(4);
  try {
    solve(u.problem(), lambda, options_of(spec));
    FAIL("no InputError");
  } catch (const InputError& e) {
    const std::string what = e.what();
    CAPTURE(what);
    CHECK(what.find("method '" + spec + "'") != std::string::npos);
    CHECK(what.find("max |A - A^T| = 1") != std::string::npos);  // |A_01 − A_10| = 1
    CHECK(what.find("lemke") != std::string::npos);
    CHECK(what.find("pgs") != std::string::npos);
  }
  // With CFM the A solved is A + eps E: still refused, through the same test.
  SolverOptions cfm = options_of(spec);
  cfm.cfm = 1e-6;
  CHECK_THROWS_AS(solve(u.problem(), lambda, cfm), InputError);
}

TEST_CASE("a symmetric A to round-off is swept by columns, exactly as before",
          "[solver][requirements]") {
  // A = J Minv Jᵀ from a step is symmetric only to round-off: the sweeps keep reading columns
  // (no Aᵀ formed), so their iterates are those of pgs_sweep on A itself.
  const System sys = test::system_of("pyramid", {{"base", "4"}}, 2);
  REQUIRE(max_asymmetry(sys.A) <= symmetry_tolerance(sys.A));
  SolverOptions options;
  options.max_iterations = 30;
  VecX by_solve = VecX::Zero(sys.rows());
  solve(sys.problem(), by_solve, options);
  VecX by_sweep = VecX::Zero(sys.rows());
  for (int k = 0; k < 30; ++k) pgs_sweep(sys.problem(), by_sweep);
  CHECK(by_solve == by_sweep);
}

TEST_CASE("cbps lcp --solver pgs solves Murty's lower-triangular problem, not its transpose",
          "[solver][requirements][cli]") {
  // The file lists M column by column, as Siconos reads it (io/siconos.hpp): M is upper
  // triangular, 1 on the diagonal and 2 above it; q = −1 (w = M z + q, A = M, b = 1). By hand:
  // row 6 has w_6 = z_6 − 1, so z_6 = 1; every earlier row k has w_k = z_k + 2 z_6 − 1 = 1 + z_k
  // > 0, so z_k = 0: z = e_6, as Lemke finds. (Mᵀ's problem has z = e_1, which the column sweep
  // returned, with residual 1 against M.)
  const std::string file = (test::kSiconosDir / "lcp" / "lcp_exp_murty.dat").string();
  for (const std::string solver : {"pgs", "jacobi"}) {
    CAPTURE(solver);
    const test::CliResult r = test::run_cli("lcp " + file + " --solver " + solver + " --json");
    CAPTURE(r.out, r.err);
    REQUIRE(r.code == 0);
    const auto j = nlohmann::json::parse(r.out);
    const std::vector<double> z = j["lambda"].get<std::vector<double>>();
    REQUIRE(z.size() == 6);
    for (std::size_t k = 0; k < 5; ++k) CHECK(z[k] == Approx(0.0).margin(1e-12));
    CHECK(z[5] == Approx(1.0).margin(1e-12));
    CHECK(j["status"] == "solved");
  }
  // The exact paths refuse it (they solve the QP of 6.2), exit 2.
  const test::CliResult direct = test::run_cli("lcp " + file + " --solver direct");
  CHECK(direct.code == 2);
}

TEST_CASE("matrix-free refuses J and Minv that are not A's factors", "[solver][requirements]") {
  const System sys = test::system_of("stack", {{"n", "3"}}, 3);
  REQUIRE(sys.rows() > 0);
  SolverOptions options;
  options.method = Method::MatrixFree;
  options.max_iterations = 50;
  VecX lambda = VecX::Zero(sys.rows());
  CHECK_NOTHROW(solve(sys.problem(), lambda, options));  // the step's own factors
  // Minv doubled: J (2 Minv) Jᵀ = 2 A. The sweep would solve that problem and report its
  // residual as if it were A's.
  const SpMat doubled = 2.0 * sys.Minv;
  const BoxedProblem wrong{sys.A, sys.b, sys.cmin, sys.cmax, &sys.J, &doubled};
  try {
    solve(wrong, lambda, options);
    FAIL("no InputError");
  } catch (const InputError& e) {
    const std::string what = e.what();
    CAPTURE(what);
    CHECK(what.find("matrix-free") != std::string::npos);
    // |A x − 2 A x| / |A| |x| is between 0 and 1 (A has entries of both signs) and far above
    // 1e-12: the message names it.
    CHECK(what.find("J Minv J^T") != std::string::npos);
  }
  // CFM in A (BoxedProblem::cfm) belongs to the factors' side too: A + eps E = J Minv Jᵀ + eps E.
  const SpMat mixed = with_cfm(sys.A, 1e-3);
  BoxedProblem with_eps{mixed, sys.b, sys.cmin, sys.cmax, &sys.J, &sys.Minv};
  CHECK_THROWS_AS(solve(with_eps, lambda, options), InputError);
  with_eps.cfm = 1e-3;
  CHECK_NOTHROW(solve(with_eps, lambda, options));
}

namespace {

/// A = [[2, 1, 0], [1, 2, 0], [0, 0, 0]] (= J Jᵀ for j_0 = (1, 1, 0, …), j_1 = (0, 1, 1, 0, …),
/// j_2 = 0 on one body with Minv = E), b = [1, 1, b_2], lambda ≥ 0, cmax_2 given.
/// By hand: rows 0, 1 interior, 2 l_0 + l_1 = 1 = l_0 + 2 l_1, so l_0 = l_1 = 1/3 (> 0); row 2
/// has w_2 = −b_2 whatever lambda is.
struct ZeroRow {
  SpMat A;
  VecX b;
  VecX cmin = VecX::Zero(3);
  VecX cmax;
  SpMatRow J;
  SpMat Minv = sparse(MatX::Identity(6, 6));
  ZeroRow(double b_2, double cmax_2) {
    MatX j = MatX::Zero(3, 6);
    j(0, 0) = j(0, 1) = j(1, 1) = j(1, 2) = 1.0;
    J = j.sparseView();
    A = sparse(j * j.transpose());
    b = (VecX(3) << 1.0, 1.0, b_2).finished();
    cmax = (VecX(3) << kInf, kInf, cmax_2).finished();
  }
  BoxedProblem problem(bool body) const {
    return body ? BoxedProblem{A, b, cmin, cmax, &J, &Minv} : BoxedProblem{A, b, cmin, cmax};
  }
};

}  // namespace

TEST_CASE("the exact paths solve a problem with a row whose j_c is zero",
          "[solver][requirements][direct]") {
  const std::string method = GENERATE(as<std::string>{}, "direct", "active-set");
  const bool body = GENERATE(false, true);      // with J and Minv (body space) or A alone
  const bool interior = GENERATE(false, true);  // direct: the interior point even when small
  CAPTURE(method, body, interior);
  SolverOptions options;
  options.method = method_of(method);
  if (interior) options.direct.interior_from_rows = 0;
  const double third = 1.0 / 3.0;
  struct Case {
    double b_2, cmax_2, lambda_2;  // the null row's b, its cmax, and its lambda by hand
  };
  // b_2 > 0: w_2 < 0, so lambda_2 = cmax_2 (the example); b_2 < 0: w_2 > 0, lambda_2 =
  // cmin_2 = 0; b_2 = 0: any point of [0, cmax_2] (the one nearest 0 is taken).
  for (const Case c : {Case{1.0, 5.0, 5.0}, Case{-1.0, 5.0, 0.0}, Case{0.0, 5.0, 0.0}}) {
    CAPTURE(c.b_2, c.cmax_2);
    const ZeroRow z(c.b_2, c.cmax_2);
    VecX lambda = VecX::Zero(3);
    const SolverSummary s = solve(z.problem(body), lambda, options);
    CAPTURE(s.message);
    CHECK(s.termination == Termination::Direct);
    CHECK(s.residual <= 1e-15);
    CHECK(lambda(0) == Approx(third).epsilon(1e-14));
    CHECK(lambda(1) == Approx(third).epsilon(1e-14));
    CHECK(lambda(2) == c.lambda_2);
  }
  // b_2 > 0 with cmax_2 = +inf: w_2 = −1 < 0 for every lambda, no solution. Reported, not thrown.
  const ZeroRow none(1.0, kInf);
  VecX lambda = VecX::Zero(3);
  const SolverSummary s = solve(none.problem(body), lambda, options);
  CAPTURE(s.message);
  CHECK(s.termination == Termination::NotConverged);
  CHECK(s.residual == 1.0);  // |lambda_2 − clamp(lambda_2 + 1)| = b_2
  CHECK(s.message.find("row 2 has no solution") != std::string::npos);
  CHECK(lambda(0) == Approx(third).epsilon(1e-14));
}
