// FCLIB global problems (M v = H r + G l + f, Gᵀ v + b = 0, u = Hᵀ v + w; fclib.h) read by
// cbps with v eliminated: J = [Hᵀ; Gᵀ], A = J M⁻¹ Jᵀ, b = −[Hᵀ M⁻¹ f + w; Gᵀ M⁻¹ f + b]. The
// files are written by FCLIB's own writer; the expected matrices come from dense inverses here
// and from a cbps step's own system, and the answers are checked against the global problem's
// equations themselves.
extern "C" {  // fclib.h declares C functions without saying so
#include <fclib.h>
}
#include <hdf5.h>
#include <hdf5_hl.h>

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cbps/base/error.hpp"
#include "cbps/io/fclib_file.hpp"
#include "cbps/io/matrix_market.hpp"
#include "cbps/io/stored_problem.hpp"
#include "cbps/solvers/solver.hpp"
#include "fixture.hpp"

using namespace cbps;
namespace fs = std::filesystem;

namespace {

/// A matrix in FCLIB's compressed columns, owning its arrays.
struct Columns {
  explicit Columns(const MatX& D) {
    SpMat S = D.sparseView();
    S.makeCompressed();
    p.assign(S.outerIndexPtr(), S.outerIndexPtr() + S.cols() + 1);
    i.assign(S.innerIndexPtr(), S.innerIndexPtr() + S.nonZeros());
    x.assign(S.valuePtr(), S.valuePtr() + S.nonZeros());
    m = int(D.rows());
    n = int(D.cols());
  }
  fclib_matrix view() {
    return fclib_matrix{int(x.size()), m, n, p.data(), i.data(), x.data(), -1, nullptr};
  }
  std::vector<int> p, i;
  std::vector<double> x;
  int m = 0, n = 0;
};

/// Writes the global problem by FCLIB's writer to `file`; G and b only when G has columns.
void write_global(const std::string& file,
                  const MatX& M,
                  const MatX& H,
                  const MatX& G,
                  VecX f,
                  VecX w,
                  VecX b,
                  VecX mu) {
  Columns Mc(M), Hc(H), Gc(G);
  fclib_matrix Mv = Mc.view(), Hv = Hc.view(), Gv = Gc.view();
  fclib_global global{&Mv,
                      &Hv,
                      G.cols() > 0 ? &Gv : nullptr,
                      mu.data(),
                      f.data(),
                      G.cols() > 0 ? b.data() : nullptr,
                      w.data(),
                      3,
                      nullptr};
  REQUIRE(fclib_write_global(&global, file.c_str()) == 1);
}

/// An elastic chain's n × n mass matrix: tridiagonal, 4 on the diagonal, −1 beside it (one
/// block larger than a rigid body's).
MatX chain_mass(int n) {
  MatX M = MatX::Zero(n, n);
  for (int k = 0; k < n; ++k) {
    M(k, k) = 4.0;
    if (k + 1 < n) M(k, k + 1) = M(k + 1, k) = -1.0;
  }
  return M;
}

double relative(const MatX& got, const MatX& expected) {
  return (got - expected).cwiseAbs().maxCoeff() / std::max(1.0, expected.cwiseAbs().maxCoeff());
}

}  // namespace

TEST_CASE("an FCLIB global problem of rigid bodies reads as the step's own J, Minv, A and b",
          "[fclib]") {
  // A step of the stack in Coulomb's cone: every row a contact's, in threes.
  const System sys = test::system_of("stack", {{"n", "2"}, {"friction", "cone"}}, 5);
  const StoredProblem step = stored_problem(sys, 0.0);
  const long m = step.rows();
  REQUIRE(m > 0);
  REQUIRE(step.cones.contacts() * 3 == m);
  for (long i = 0; i < step.cones.contacts(); ++i)
    REQUIRE(step.cones.normal[std::size_t(i)] == 3 * i);
  // The global problem with M = Minv⁻¹, H = Jᵀ, any f, and w making the same b.
  const MatX Minv = MatX(step.Minv), M = Minv.inverse();
  const MatX J = MatX(SpMat(step.J));
  const VecX f = VecX::LinSpaced(M.rows(), -3.0, 5.0);
  const VecX w = -step.b - J * (Minv * f);
  const fs::path dir = test::scratch_dir("fclib_global_step");
  const std::string file = (dir / "step.hdf5").string();
  write_global(file, M, J.transpose(), MatX(M.rows(), 0), f, w, VecX(0), step.cones.mu);

  const StoredProblem p = read_problem(file);
  CHECK(p.fclib);
  REQUIRE(p.has_jacobian());  // M is block-diagonal: J and M⁻¹ kept
  CHECK(MatX(SpMat(p.J)) == J);
  CHECK(relative(MatX(p.Minv), Minv) < 1e-12);
  CHECK(relative(MatX(p.A), MatX(step.A)) < 1e-10);
  CHECK(relative(p.b, step.b) < 1e-10);
  CHECK(p.cones.normal == step.cones.normal);
  CHECK(p.cones.mu == step.cones.mu);
  CHECK(MatX(p.A) == MatX(p.A).transpose());
  // The exact path solves it; its u = J M⁻¹ (Jᵀ r + f) + w is the step's w = A λ − b.
  SolverOptions o;
  o.method = Method::Direct;
  VecX r;
  const SolverSummary s = solve(p.problem(), r, o);
  INFO(s.message);
  CHECK(s.termination == Termination::Direct);
  const VecX u = J * (Minv * (J.transpose() * r + f)) + w;
  CHECK(relative(u, MatX(step.A) * r - step.b) < 1e-9);
}

TEST_CASE("an FCLIB global problem with a coupled M and equality rows: A and b by elimination",
          "[fclib]") {
  // Sixteen unknowns coupled by a tridiagonal M (an elastic chain: one block larger than a
  // rigid body's), two contacts (H: 6 columns) and one equality (G).
  const int n = 16;
  const MatX M = chain_mass(n);
  MatX H = MatX::Zero(n, 6), G = MatX::Zero(n, 1);
  H(0, 0) = 1.0;  // contact 0: normal along unknown 0, tangents 1 and 2
  H(1, 1) = 1.0;
  H(2, 2) = 1.0;
  H(5, 3) = 1.0;  // contact 1 on unknowns 5, 6, 7, its normal tilted
  H(4, 3) = 0.5;
  H(6, 4) = 1.0;
  H(7, 5) = 1.0;
  G(3, 0) = 1.0;  // unknown 3 held: 0 = v_3 + b
  VecX f = VecX::Zero(n);
  f.head(8) << -9.81, 0.5, 0.0, 0.0, 1.0, -9.81, -0.2, 0.3;
  const VecX w = (VecX(6) << 0.01, 0.0, 0.0, -0.02, 0.0, 0.0).finished();
  const VecX b = (VecX(1) << 0.25).finished();
  const VecX mu = (VecX(2) << 0.5, 0.3).finished();
  const fs::path dir = test::scratch_dir("fclib_global_chain");
  const std::string file = (dir / "chain.hdf5").string();
  write_global(file, M, H, G, f, w, b, mu);

  const StoredProblem p = read_problem(file);
  CHECK(!p.has_jacobian());
  CHECK(p.without_jacobian.find("LDL^T of M") != std::string::npos);
  REQUIRE(p.rows() == 7);
  MatX J(7, n);
  J << H.transpose(), G.transpose();
  const MatX Minv = M.inverse();
  CHECK(relative(MatX(p.A), J * Minv * J.transpose()) < 1e-12);
  VecX expected_b(7);
  expected_b << -(H.transpose() * Minv * f + w), -(G.transpose() * Minv * f + b);
  CHECK(relative(p.b, expected_b) < 1e-12);
  CHECK(p.cmin(6) == -kInf);  // the equality row is free
  CHECK(p.cmax(6) == kInf);
  CHECK(p.cones.normal == std::vector<int>{0, 3});

  // Solved by cbps lcp, the answer meets the global problem's own equations.
  const test::CliResult run = test::run_cli("lcp " + file + " --solver direct --json");
  INFO(run.err);
  REQUIRE(run.code == 0);
  const auto j = nlohmann::json::parse(run.out);
  CHECK(j["status"] == "solved");
  VecX lambda(7);
  for (int k = 0; k < 7; ++k) lambda(k) = j["lambda"][std::size_t(k)].get<double>();
  const VecX v = Minv * (H * lambda.head(6) + G * lambda.tail(1) + f);
  CHECK(std::abs((G.transpose() * v + b)(0)) < 1e-9);  // Gᵀ v + b = 0
  const VecX u = H.transpose() * v + w;
  for (int c = 0; c < 2; ++c) {
    const double rn = lambda(3 * c), ut = u.segment<2>(3 * c + 1).norm();
    CHECK(lambda.segment<2>(3 * c + 1).norm() <= mu(c) * rn + 1e-9);  // r in the cone
    CHECK(std::abs(rn * (u(3 * c) + mu(c) * ut)) < 1e-9);             // De Saxcé's û_n ⊥ r_n
  }
}

TEST_CASE("an FCLIB global problem whose M is stored as one triangle reads as the symmetric M",
          "[fclib]") {
  // LMGC90 writes a finite-element M as its upper triangle (Siconos' LMGC_GFC3D_CubeH8). The
  // tridiagonal chain of the test above, stored as each triangle, reads as the full M; the
  // problem's notes and `cbps lcp` say so. An M with entries in both triangles that differ is
  // still refused.
  const int n = 16;
  const MatX M = chain_mass(n);
  MatX H = MatX::Zero(n, 6);
  for (int k = 0; k < 6; ++k) H(k + 2 * (k / 3), k) = 1.0;
  const VecX f = VecX::LinSpaced(n, -9.81, 1.0), w = VecX::Zero(6);
  const VecX mu = (VecX(2) << 0.5, 0.3).finished();
  const fs::path dir = test::scratch_dir("fclib_global_triangle");
  const MatX Minv = M.inverse();
  const MatX A = H.transpose() * Minv * H;
  const VecX b = -(H.transpose() * Minv * f + w);
  for (const bool upper : {true, false}) {
    const MatX half =
        upper ? MatX(M.triangularView<Eigen::Upper>()) : MatX(M.triangularView<Eigen::Lower>());
    const std::string file = (dir / (upper ? "upper.hdf5" : "lower.hdf5")).string();
    write_global(file, half, H, MatX(n, 0), f, w, VecX(0), mu);
    const StoredProblem p = read_problem(file);
    INFO((upper ? "upper" : "lower"));
    CHECK(relative(MatX(p.A), A) < 1e-12);
    CHECK(relative(p.b, b) < 1e-12);
    REQUIRE(p.notes.size() == 1);
    CHECK(p.notes[0].find(upper ? "upper triangle" : "lower triangle") != std::string::npos);
    const test::CliResult run = test::run_cli("lcp " + file + " --solver direct --json");
    INFO(run.err);
    REQUIRE(run.code == 0);
    const auto j = nlohmann::json::parse(run.out);
    CHECK(j["status"] == "solved");
    CHECK(j["read_notes"].size() == 1);
  }
  // Both triangles, M and Mᵀ different: refused as before, naming the dataset.
  MatX skew = M;
  skew(0, 1) = -2.0;
  const std::string file = (dir / "skew.hdf5").string();
  write_global(file, skew, H, MatX(n, 0), f, w, VecX(0), mu);
  try {
    read_problem(file);
    FAIL("an M with M_01 != M_10 was read");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).find("/fclib_global/M: not symmetric") != std::string::npos);
  }
  // Stored in full, nothing is noted.
  const std::string full = (dir / "full.hdf5").string();
  write_global(full, M, H, MatX(n, 0), f, w, VecX(0), mu);
  CHECK(read_problem(full).notes.empty());
}

TEST_CASE("a malformed FCLIB global problem is an InputError naming the dataset", "[fclib]") {
  const fs::path dir = test::scratch_dir("fclib_global_bad");
  const MatX H = MatX::Identity(3, 3);
  const VecX f = VecX::Zero(3), w = VecX::Zero(3), mu = VecX::Constant(1, 0.5);
  // M not symmetric: entries in both triangles that differ (one triangle alone reads as the
  // symmetric M it is half of: the test above).
  MatX M = 2.0 * MatX::Identity(3, 3);
  M(0, 1) = 1.0;
  M(1, 0) = 0.5;
  const std::string asymmetric = (dir / "asymmetric.hdf5").string();
  write_global(asymmetric, M, H, MatX(3, 0), f, w, VecX(0), mu);
  CHECK_THROWS_WITH(read_problem(asymmetric),
                    Catch::Contains(asymmetric) && Catch::Contains("/fclib_global/M") &&
                        Catch::Contains("not symmetric"));
  // M symmetric but indefinite.
  const std::string indefinite = (dir / "indefinite.hdf5").string();
  write_global(indefinite, -MatX::Identity(3, 3), H, MatX(3, 0), f, w, VecX(0), mu);
  CHECK_THROWS_WITH(read_problem(indefinite),
                    Catch::Contains("/fclib_global/M") && Catch::Contains("positive definite"));
  // f shorter than M (FCLIB's writer refuses what it can check, so the file is edited after).
  const std::string short_f = (dir / "short_f.hdf5").string();
  write_global(short_f, MatX::Identity(3, 3), H, MatX(3, 0), f, w, VecX(0), mu);
  const hid_t file = H5Fopen(short_f.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  REQUIRE(file >= 0);
  REQUIRE(H5Ldelete(file, "/fclib_global/vectors/f", H5P_DEFAULT) >= 0);
  const double two[] = {1.0, 2.0};
  const hsize_t size = 2;
  REQUIRE(H5LTmake_dataset_double(file, "/fclib_global/vectors/f", 1, &size, two) >= 0);
  H5Fclose(file);
  CHECK_THROWS_WITH(
      read_problem(short_f),
      Catch::Contains("/fclib_global/vectors/f") && Catch::Contains("2 entries, 3 expected"));
}

namespace {

/// fclib_delete_global frees what the problem holds but not the struct fclib_read_global
/// allocated (as for the local problem, test_fclib_file.cpp): both are freed here.
struct GlobalDeleter {
  void operator()(fclib_global* p) const {
    fclib_delete_global(p);
    std::free(p);
  }
};

MatX dense(const fclib_matrix& M) {
  REQUIRE(M.nz == -1);  // cbps writes compressed columns
  MatX D = MatX::Zero(M.m, M.n);
  for (int j = 0; j < M.n; ++j)
    for (int k = M.p[j]; k < M.p[j + 1]; ++k) D(M.i[k], j) += M.x[k];
  return D;
}

}  // namespace

TEST_CASE("matrices --fclib --global writes a global problem FCLIB reads and cbps reads back",
          "[fclib][cli]") {
  const fs::path dir = test::scratch_dir("fclib_global_write");
  const std::string file = (dir / "stack.hdf5").string();
  const test::CliResult written = test::run_cli(
      "matrices stack --param n=2 --param friction=cone --solver direct --step 5 --quiet --out " +
      (dir / "folder").string() + " --fclib " + file + " --global");
  INFO(written.err);
  REQUIRE(written.code == 0);
  const StoredProblem folder = read_problem((dir / "folder").string());
  const long m = folder.rows();
  // FCLIB's own reader: M = Minv⁻¹, H = Jᵀ, f = 0, w = −b, the solution's v, u, r consistent.
  std::unique_ptr<fclib_global, GlobalDeleter> theirs(fclib_read_global(file.c_str()));
  REQUIRE(theirs);
  CHECK(theirs->spacedim == 3);
  const MatX M = dense(*theirs->M), H = dense(*theirs->H);
  CHECK(relative(M.inverse(), MatX(folder.Minv)) < 1e-12);
  CHECK(H.transpose() == MatX(SpMat(folder.J)));
  CHECK(theirs->G == nullptr);  // every row a contact's
  const VecX w = Eigen::Map<const VecX>(theirs->w, m);
  CHECK(w == -folder.b);
  fclib_solution* solution = fclib_read_solution(file.c_str());
  REQUIRE(solution != nullptr);
  const VecX v = Eigen::Map<const VecX>(solution->v, M.rows());
  const VecX u = Eigen::Map<const VecX>(solution->u, m);
  const VecX r = Eigen::Map<const VecX>(solution->r, m);
  CHECK(relative(M * v, H * r) < 1e-10);              // M v = H r + f, f = 0
  CHECK(relative(u, H.transpose() * v + w) < 1e-12);  // u = Hᵀ v + w
  const VecX lambda = read_matrix_market_vector((dir / "folder" / "lambda.mtx").string());
  CHECK(r == lambda);
  fclib_delete_solutions(solution, 1);
  // cbps reads it back as the folder's problem.
  const StoredProblem back = read_problem(file);
  REQUIRE(back.has_jacobian());
  CHECK(relative(MatX(back.A), MatX(folder.A)) < 1e-12);
  CHECK(relative(back.b, folder.b) < 1e-12);
  // A scene without J's rigid blocks cannot be asked for; a cfm or boxed row is refused as for
  // the local problem (test_fclib_file.cpp). An existing file is never replaced.
  const test::CliResult again =
      test::run_cli("matrices stack --param n=2 --param friction=cone --quiet --out " +
                    (dir / "folder2").string() + " --fclib " + file + " --global");
  CHECK(again.code == 2);
  CHECK(fs::exists(file));
}
