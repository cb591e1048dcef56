// The reader of Siconos' frictional-contact dumps (io/siconos_fc3d.hpp): the layout as Siconos'
// writers define it, checked on Siconos' own files (tests/data/siconos-fc3d) where two files hold
// one problem in two forms, and bad input named by file and line.
#include <catch2/catch.hpp>
#include <filesystem>
#include <sstream>
#include <string>

#include "cbps/base/error.hpp"
#include "cbps/io/siconos_fc3d.hpp"
#include "cbps/io/stored_problem.hpp"
#include "fixture.hpp"

using namespace cbps;
using test::kFc3dDir;
using test::kSiconosDir;
namespace fs = std::filesystem;

namespace {

StoredProblem parse(const std::string& text) {
  std::istringstream in(text);
  return parse_siconos_fc3d(in, "test.dat");
}

std::string failure(const std::string& text) {
  try {
    parse(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

StoredProblem file(const char* name) { return read_problem((kFc3dDir / name).string()); }

double max_abs(const SpMat& M) { return M.nonZeros() ? M.coeffs().cwiseAbs().maxCoeff() : 0.0; }

}  // namespace

TEST_CASE("a dense W is read column by column, as Siconos stores it", "[siconos-fc3d]") {
  // Entry (i, j) is number i + 3 j of the file (NumericsMatrix's matrix0[i + j size0]).
  const StoredProblem p = parse("3 1 0 3 3 3 3  1 2 3 4 5 6 7 8 9  -1 2 3  0.5\n");
  CHECK(p.A.coeff(1, 0) == 2.0);
  CHECK(p.A.coeff(0, 1) == 4.0);
  CHECK(p.A.coeff(2, 1) == 6.0);
  CHECK(p.b == (VecX(3) << 1, -2, -3).finished());  // b = −q
  REQUIRE(p.cones.contacts() == 1);
  CHECK(p.cones.normal[0] == 0);
  CHECK(p.cones.mu(0) == 0.5);
  CHECK(p.cmin(0) == 0.0);
  CHECK(p.cmin(1) == -kInf);
  CHECK(!p.has_jacobian());
}

TEST_CASE("a sparse-block W is read block by block, each block column by column",
          "[siconos-fc3d]") {
  // Two block rows and columns of 3; blocks (0,0), (0,1), (1,1) hold 1..9, 10..18, 19..27.
  std::ostringstream text;
  text << "3 2 1 6 6  3  2 2  3 6  3 6  3 3  0 2 3  0 1 1\n";
  for (int b = 0; b < 3; ++b) {
    text << b;
    for (int k = 1; k <= 9; ++k) text << ' ' << 9 * b + k;
    text << '\n';
  }
  text << "0 0 0 0 0 0  0.1 0.2\n";
  const StoredProblem p = parse(text.str());
  CHECK(p.A.coeff(1, 0) == 2.0);
  CHECK(p.A.coeff(0, 1) == 4.0);
  CHECK(p.A.coeff(0, 4) == 13.0);
  CHECK(p.A.coeff(2, 3) == 12.0);
  CHECK(p.A.coeff(5, 4) == 24.0);
  CHECK(p.A.coeff(3, 0) == 0.0);
  CHECK(p.cones.mu(1) == 0.2);
  CHECK(p.cones.normal[1] == 3);
}

TEST_CASE("Siconos' twin files read as one problem", "[siconos-fc3d]") {
  // The same local problem written dense and sparse-block by Siconos.
  const StoredProblem dense = file("FC3D_Example1.dat");
  const StoredProblem blocks = file("FC3D_Example1_SBM.dat");
  CHECK(dense.rows() == 9);
  CHECK(max_abs(dense.A - blocks.A) == 0.0);
  CHECK(dense.b == blocks.b);
  CHECK(dense.cones.mu == blocks.cones.mu);
  // A global problem twice: its H is non-square, so the dense form's column order shows.
  const StoredProblem g = file("GFC3D_Example0.dat");
  const StoredProblem g_sbm = file("GFC3D_Example0_SBM.dat");
  CHECK(g.rows() == 3);
  CHECK(max_abs(g.A - g_sbm.A) <= 1e-15);
  CHECK((g.b - g_sbm.b).lpNorm<Eigen::Infinity>() <= 1e-15);
}

TEST_CASE("a global dump with v eliminated is Siconos' own condensed problem", "[siconos-fc3d]") {
  // GFC3D_TwoRods1-condensed.dat is Siconos' W = Hᵀ M⁻¹ H and q = Hᵀ M⁻¹ f + w of
  // GFC3D_TwoRods1.dat; their blocks are printed with 7 significant digits, so they agree to
  // that rounding, not to the bit.
  const StoredProblem global = file("GFC3D_TwoRods1.dat");
  const StoredProblem condensed = file("GFC3D_TwoRods1-condensed.dat");
  REQUIRE(global.rows() == 9);
  REQUIRE(condensed.rows() == 9);
  CHECK(max_abs(global.A - condensed.A) <= 1e-6 * max_abs(condensed.A));
  CHECK((global.b - condensed.b).lpNorm<Eigen::Infinity>() <=
        1e-12 * condensed.b.lpNorm<Eigen::Infinity>());
  CHECK(global.cones.mu == condensed.cones.mu);
  // M couples 27 rows (a rod's finite elements): no rigid bodies' J and M⁻¹ to keep.
  CHECK(!global.has_jacobian());
  // Rigid bodies' M (GFC3D_Example0: 6-row blocks) keep J = Hᵀ and M⁻¹.
  CHECK(file("GFC3D_Example0.dat").has_jacobian());
}

TEST_CASE("read_problem tells friction-contact dumps from LCP files", "[siconos-fc3d]") {
  for (const fs::path& f : test::dat_files(kFc3dDir)) {
    if (f.filename().string().rfind("FrictionContactProblem", 0) == 0) continue;  // 2-D
    INFO(f.string());
    CHECK(looks_like_siconos_fc3d(f.string()));
    const StoredProblem p = read_problem(f.string());
    CHECK(p.cones.contacts() * 3 == p.rows());
  }
  for (const char* folder : {"lcp", "relay"})
    for (const fs::path& f : test::dat_files(kSiconosDir / folder)) {
      INFO(f.string());
      CHECK(!looks_like_siconos_fc3d(f.string()));
      if (f.filename().string().find("_block") != std::string::npos) continue;  // storage 1
      CHECK(read_problem(f.string()).cones.empty());
    }
  // Told what it is, the reader does not guess.
  CHECK(read_problem((kFc3dDir / "Rover4396.dat").string(), SiconosKind::FrictionContact)
            .cones.contacts() == 2);
}

TEST_CASE("what the friction-contact reader refuses, by name and line", "[siconos-fc3d]") {
  CHECK(failure("2 1 0 2 2 2 2 1 0 0 1 0 0 0.5") ==
        "test.dat: line 1: d = 2: a 2-D friction-contact problem; cbps reads 3-D contact (d = 3)");
  CHECK(failure("5 1 0").find("rolling-friction problem") != std::string::npos);
  const std::string rolling = failure("3 1 0 3 3 3 3 1 0 0 0 1 0 0 0 1 0 0 0 0.5\n0.1\n");
  CHECK(rolling ==
        "test.dat: line 2: 1 numbers after mu, one per contact: a rolling-friction "
        "problem (Siconos' RollingFrictionContactProblem, its rolling coefficients), "
        "which cbps does not solve");
  CHECK(failure("3 1 2 3 3").find("storage type 2 (CSparse's text form") != std::string::npos);
  CHECK(failure("3 1 0 3 3 3 3 1 0 0 0 1 0 0 0 1 0 0 0 -0.5") ==
        "test.dat: line 1: mu[0] = -0.5 < 0");
  CHECK(failure("3 1 0 3 3 3 3 1 0 0 0 1 0 0 0 1 0 0 0\n") ==
        "test.dat: line 1: end of file where mu[0] was expected");
  CHECK(failure("3 1 0 3 3 3 2") ==
        "test.dat: line 1: W (M if global) columns (again) = 2, not 3 as its header says");
  CHECK(failure("3 1 0 3 3 3 3 1 0 0 0 1 0 nan 0 1 0 0 0 0.5").find("is not finite") !=
        std::string::npos);
  // The legacy flag may end a file; anything else may not.
  CHECK(parse("3 1 0 3 3 3 3 1 0 0 0 1 0 0 0 1 0 0 0 0.5 1").rows() == 3);
  CHECK(failure("3 1 0 3 3 3 3 1 0 0 0 1 0 0 0 1 0 0 0 0.5 7 8").find("'7' and 1 more tokens") !=
        std::string::npos);
  // A sparse-block structure that does not hold together.
  CHECK(failure("3 1 1 3 3  1  1 1  3  3  2 1  0 1  0  5 1 0 0 0 1 0 0 0 1  0 0 0  0.3")
            .find("block number 5 where block 0 was expected") != std::string::npos);
  CHECK(failure("3 1 1 3 3  1  1 1  4  3").find("row sizes[0] = 4 does not increase") !=
        std::string::npos);
  // A header claiming more than the file holds fails before anything that size is allocated.
  CHECK(failure("3 300000 0 900000 900000 900000 900000 1 2").find("needs") != std::string::npos);
  // A local W of the wrong size.
  CHECK(failure("3 2 0 3 3 3 3 1 0 0 0 1 0 0 0 1 0 0 0 0.5 0.5")
            .find("a local problem of nc = 2 "
                  "contacts has a 6 x 6 W") != std::string::npos);
}

TEST_CASE("a global dump whose elimination overflows is refused, naming M", "[siconos-fc3d]") {
  // M = 1e-300 I (positive definite), H = 1e300 I: H^T M^-1 H = 1e900 overflows.
  const std::string text =
      "3 1  0 3 3 3 3  1e-300 0 0 0 1e-300 0 0 0 1e-300  0 3 3 3 3  1e300 0 0 0 1e300 0 0 0 1e300"
      "  0 0 0  0 0 0  0.5";
  CHECK(failure(text).find("overflows") != std::string::npos);
}
