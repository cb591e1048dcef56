// Lemke's method (standard and boxed LCP) against problems with known solutions and against every
// external Siconos problem.
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "cbps/base/error.hpp"
#include "cbps/io/siconos.hpp"
#include "cbps/solvers/exact/lemke.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/system/boxed_problem.hpp"
#include "fixture.hpp"

using namespace cbps;
using test::dat_files;
using test::kSiconosDir;
namespace fs = std::filesystem;

namespace {

/// The tolerance Solved promises (lcp.hpp), relative to max(1, ‖q‖∞, max |M_ij|).
constexpr double kSolvedTolerance = kLcpSolvedTolerance;

/// The test's own check of the boxed conditions, written independently of lcp_residual:
/// the largest violation of lb ≤ z ≤ ub and of the sign of w = M z + q at each bound, with
/// w_i weighted by the distance of z_i from each bound (the natural map, row by row).
double independent_violation(
    const MatX& M, const VecX& q, const VecX& lb, const VecX& ub, const VecX& z) {
  const VecX w = M * z + q;
  double v = 0.0;
  for (Eigen::Index i = 0; i < z.size(); ++i) {
    v = std::max({v, lb(i) - z(i), z(i) - ub(i)});
    // w_i > 0 pushes z_i to lb_i: the violation is how far z_i stays above lb_i, at most w_i.
    if (w(i) > 0) v = std::max(v, std::min(w(i), z(i) - lb(i)));
    // w_i < 0 pushes z_i to ub_i.
    if (w(i) < 0) v = std::max(v, std::min(-w(i), ub(i) - z(i)));
  }
  return v;
}

double scale_of(const MatX& M, const VecX& q) {
  return std::max({1.0, q.cwiseAbs().maxCoeff(), M.cwiseAbs().maxCoeff()});
}

/// A random non-symmetric, strictly row-diagonally-dominant matrix with positive diagonal: a
/// P-matrix, so every LCP with it has exactly one solution.
MatX random_p_matrix(int n, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  MatX M(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) M(i, j) = u(rng);
  for (int i = 0; i < n; ++i)
    M(i, i) = M.row(i).cwiseAbs().sum() - std::abs(M(i, i)) + 0.5 + std::abs(u(rng));
  return M;
}

MatX random_spd(int n, std::mt19937& rng) {
  std::normal_distribution<double> n01;
  MatX B(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) B(i, j) = n01(rng);
  return B * B.transpose() + 0.1 * MatX::Identity(n, n);
}

/// All principal minors positive (n small): M is a P-matrix.
bool is_p_matrix(const MatX& M) {
  const int n = static_cast<int>(M.rows());
  if (n > 14) return false;
  for (unsigned mask = 1; mask < (1u << n); ++mask) {
    std::vector<int> idx;
    for (int i = 0; i < n; ++i)
      if (mask & (1u << i)) idx.push_back(i);
    MatX sub(idx.size(), idx.size());
    for (std::size_t a = 0; a < idx.size(); ++a)
      for (std::size_t b = 0; b < idx.size(); ++b) sub(a, b) = M(idx[a], idx[b]);
    if (!(sub.determinant() > 0)) return false;
  }
  return true;
}

/// M + Mᵀ positive semidefinite: M is copositive-plus, so Lemke solves every feasible LCP.
bool is_positive_semidefinite(const MatX& M) {
  const MatX S = 0.5 * (M + M.transpose());
  const double least = Eigen::SelfAdjointEigenSolver<MatX>(S).eigenvalues().minCoeff();
  return least >= -1e-12 * std::max(1.0, S.cwiseAbs().maxCoeff());
}

/// Brute force over the 2ⁿ complementary index sets (n small): true if one nonsingular basic
/// system gives a solution. A sound "a solution exists"; false only means "none found this way".
bool enumeration_finds_solution(const MatX& M, const VecX& q) {
  const int n = static_cast<int>(q.size());
  if (n > 14) return false;
  const VecX lb = VecX::Zero(n), ub = VecX::Constant(n, kInf);
  for (unsigned mask = 0; mask < (1u << n); ++mask) {
    std::vector<int> idx;
    for (int i = 0; i < n; ++i)
      if (mask & (1u << i)) idx.push_back(i);
    VecX z = VecX::Zero(n);
    if (!idx.empty()) {
      MatX sub(idx.size(), idx.size());
      VecX rhs(idx.size());
      for (std::size_t a = 0; a < idx.size(); ++a) {
        rhs(a) = -q(idx[a]);
        for (std::size_t b = 0; b < idx.size(); ++b) sub(a, b) = M(idx[a], idx[b]);
      }
      const Eigen::FullPivLU<MatX> lu(sub);
      if (!lu.isInvertible()) continue;
      const VecX x = lu.solve(rhs);
      for (std::size_t a = 0; a < idx.size(); ++a) z(idx[a]) = x(a);
    }
    if (independent_violation(M, q, lb, ub, z) <= 1e-10 * scale_of(M, q)) return true;
  }
  return false;
}

}  // namespace

TEST_CASE("Lemke finds the unique solution of LCPs with P-matrices built around it", "[lcp]") {
  std::mt19937 rng(20150601);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 1 + trial % 15;
    const MatX M = random_p_matrix(n, rng);
    // z*, w* complementary; about one row in six degenerate (z*_i = w*_i = 0).
    VecX z_star = VecX::Zero(n), w_star = VecX::Zero(n);
    for (int i = 0; i < n; ++i) {
      const double kind = u(rng);
      if (kind < 0.45)
        z_star(i) = 0.1 + 2 * u(rng);
      else if (kind < 0.83)
        w_star(i) = 0.1 + 2 * u(rng);
    }
    const VecX q = w_star - M * z_star;
    const LcpResult r = solve_lemke(M, q);
    CAPTURE(trial, n, r.message);
    REQUIRE(r.solved());
    const double scale = scale_of(M, q);
    CHECK((r.z - z_star).lpNorm<Eigen::Infinity>() <= 1e-9 * scale);
    CHECK((r.w - w_star).lpNorm<Eigen::Infinity>() <= 1e-9 * scale);
    CHECK(independent_violation(M, q, VecX::Zero(n), VecX::Constant(n, kInf), r.z) <=
          kSolvedTolerance * scale);
  }
}

TEST_CASE("Lemke with q ≥ 0 returns z = 0 without pivoting", "[lcp]") {
  const MatX M = (MatX(2, 2) << 1, 2, 3, -4).finished();
  const VecX q = (VecX(2) << 0.0, 1.0).finished();
  const LcpResult r = solve_lemke(M, q);
  CHECK(r.solved());
  CHECK(r.pivots == 0);
  CHECK(r.z.isZero(0));
}

TEST_CASE("Lemke reports ray termination honestly on LCPs without a solution", "[lcp]") {
  SECTION("w = −z − 1 ≥ 0 is impossible for z ≥ 0") {
    const LcpResult r = solve_lemke(MatX::Constant(1, 1, -1.0), VecX::Constant(1, -1.0));
    INFO(r.message);
    CHECK(r.status == LcpResult::Status::NoSolution);
  }
  SECTION("w₁ + w₂ = −2 for every z: infeasible, M positive semidefinite") {
    const MatX M = (MatX(2, 2) << 1, -1, -1, 1).finished();
    const LcpResult r = solve_lemke(M, VecX::Constant(2, -1.0));
    INFO(r.message);
    CHECK(r.status == LcpResult::Status::NoSolution);
  }
}

TEST_CASE("boxed Lemke finds solutions built with rows at lb, at ub, between and free (6.2)",
          "[lcp][eq6.2.9]") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 100; ++trial) {
    const int n = 1 + trial % 12;
    const MatX M = random_spd(n, rng);
    VecX lb(n), ub(n), z_star(n), w_star = VecX::Zero(n);
    for (int i = 0; i < n; ++i) {
      lb(i) = -0.5 - u(rng);
      ub(i) = 0.5 + u(rng);
      const int kind = static_cast<int>(7 * u(rng));
      switch (kind) {
        case 0:  // at lb, pushed against it
          z_star(i) = lb(i);
          w_star(i) = 0.1 + u(rng);
          break;
        case 1:  // at ub
          z_star(i) = ub(i);
          w_star(i) = -0.1 - u(rng);
          break;
        case 2:  // free row of a bilateral constraint
          lb(i) = -kInf;
          ub(i) = kInf;
          z_star(i) = 2 * u(rng) - 1;
          break;
        case 3:  // contact: lb = 0, ub = +∞, at its bound
          lb(i) = 0;
          ub(i) = kInf;
          z_star(i) = 0;
          w_star(i) = u(rng);
          break;
        case 4:  // only an upper bound, active
          lb(i) = -kInf;
          z_star(i) = ub(i);
          w_star(i) = -u(rng);
          break;
        case 5:  // fixed: lb = ub, w free
          ub(i) = lb(i);
          z_star(i) = lb(i);
          w_star(i) = 2 * u(rng) - 1;
          break;
        default:  // strictly between
          z_star(i) = lb(i) + (ub(i) - lb(i)) * (0.1 + 0.8 * u(rng));
      }
    }
    const VecX q = w_star - M * z_star;
    const LcpResult r = solve_boxed_lemke(M, q, lb, ub);
    CAPTURE(trial, n, r.message);
    REQUIRE(r.solved());
    const double scale = scale_of(M, q);
    // M is positive definite: the solution is unique.
    CHECK((r.z - z_star).lpNorm<Eigen::Infinity>() <= 1e-9 * scale);
    CHECK(independent_violation(M, q, lb, ub, r.z) <= kSolvedTolerance * scale);
  }
}

TEST_CASE("every Siconos LCP is either solved correctly or reported unsolved", "[lcp][siconos]") {
  for (const fs::path& file : dat_files(kSiconosDir / "lcp")) {
    CAPTURE(file.filename().string());
    StoredLcp p;
    try {
      p = read_siconos(file.string(), false);
    } catch (const InputError& e) {
      // Only the sparse-block files may be refused.
      INFO(e.what());
      CHECK(std::string(e.what()).find("storage type 1") != std::string::npos);
      WARN(file.filename().string() << ": not read (" << e.what() << ")");
      continue;
    }
    const int n = static_cast<int>(p.q.size());
    const LcpResult r = solve_lemke(p.M, p.q);
    const double scale = scale_of(p.M, p.q);
    const double violation = independent_violation(p.M, p.q, p.lb, p.ub, r.z);
    const bool p_matrix = is_p_matrix(p.M);
    const bool psd = is_positive_semidefinite(p.M);
    const bool exists = enumeration_finds_solution(p.M, p.q);
    WARN(file.filename().string() << " (n = " << n << (p_matrix ? ", P-matrix" : "")
                                  << (psd ? ", M + Mᵀ ⪰ 0" : "")
                                  << (exists ? ", enumeration finds a solution" : "") << "): "
                                  << to_string(r.status) << ", " << r.pivots << " pivots, residual "
                                  << r.residual << " (relative " << r.relative_residual
                                  << ", independent " << violation / scale << "); " << r.message);
    if (r.solved()) CHECK(violation <= kSolvedTolerance * scale);
    // Lemke is guaranteed for P-matrices, and for copositive-plus M when a solution exists.
    if (p_matrix || (psd && exists)) CHECK(r.solved());
    // The files' own remarks: CPS 4.1.14 "set of solution is z_1 + z_2 = 1"; Pang's "isolated
    // solution" (by its name).
    const std::string name = file.stem().string();
    if (name == "lcp_CPS_1" || name == "lcp_Pang_isolated_sol") CHECK(r.solved());
    // CPS 4 read by columns is the KKT system of a convex QP with a feasible constraint.
    if (name == "lcp_CPS_4") CHECK(r.solved());
    // A row with q_i < 0 and M_ij ≤ 0 for all j has w_i < 0 for every z ≥ 0: no solution.
    bool infeasible_row = false;
    for (int i = 0; i < n; ++i)
      infeasible_row = infeasible_row || (p.q(i) < 0 && p.M.row(i).maxCoeff() <= 0);
    if (infeasible_row) CHECK(r.status == LcpResult::Status::NoSolution);
    if (!r.solved() && exists)
      WARN(name << ": a solution exists (found by enumeration) but Lemke did not find it: "
                << r.message);
  }
}

TEST_CASE("every Siconos relay problem is solved by boxed Lemke", "[lcp][siconos]") {
  for (const fs::path& file : dat_files(kSiconosDir / "relay")) {
    CAPTURE(file.filename().string());
    REQUIRE(read_siconos(file.string(), SiconosKind::Auto).boxed);  // by content
    const StoredLcp p = read_siconos(file.string(), true);
    REQUIRE(p.boxed);
    const LcpResult r = solve_boxed_lemke(p.M, p.q, p.lb, p.ub);
    const double scale = scale_of(p.M, p.q);
    const double violation = independent_violation(p.M, p.q, p.lb, p.ub, r.z);
    WARN(file.filename().string() << " (n = " << p.q.size() << "): " << to_string(r.status) << ", "
                                  << r.pivots << " pivots, residual " << r.residual << " (relative "
                                  << r.relative_residual << ", independent " << violation / scale
                                  << "); " << r.message);
    if (r.solved()) CHECK(violation <= kSolvedTolerance * scale);
    // All bounds finite: a variational inequality on a compact box always has a solution, and
    // with M + Mᵀ ⪰ 0 Lemke's method on the transformed LCP must find one.
    const bool finite_box = p.lb.allFinite() && p.ub.allFinite();
    if (finite_box && is_positive_semidefinite(p.M)) CHECK(r.solved());
  }
}

TEST_CASE("lemke pivots each row in its own units: compliances 1e12 apart", "[lcp][tolerance]") {
  // A = diag(1e4, 1e-8) kg⁻¹ with b = A (1/3, 1) N: each row pushed to λ_k = b_k / A_kk. Pivoting
  // on A as it is, Lemke returned λ_2 = 0 after 2 pivots and called it solved by its own check
  // (relative to max |A_ij| = 1e4), a unit-free residual of 1; on D A D (D = 1 / sqrt A_kk) it
  // is exact. The boxed form too (cmax = 10 N on both rows: the same answer, inside the box).
  const SpMat A = (VecX(2) << 1e4, 1e-8).finished().asDiagonal().toDenseMatrix().sparseView();
  const VecX b = (VecX(2) << 1e4 / 3.0, 1e-8).finished();
  for (const double top : {kInf, 10.0}) {
    const BoxedProblem problem{A, b, VecX::Zero(2), VecX::Constant(2, top)};
    VecX lambda;
    SolverOptions o;
    o.method = Method::Lemke;
    const SolverSummary s = solve(problem, lambda, o);
    INFO("cmax " << top << ": " << s.message);
    CHECK(s.termination == Termination::Direct);
    CHECK(lambda(0) == Approx(1.0 / 3.0).epsilon(1e-14));
    CHECK(lambda(1) == Approx(1.0).epsilon(1e-14));
  }
}
