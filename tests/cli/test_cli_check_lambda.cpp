// `cbps check PROBLEM --lambda FILE`: a lambda off the exact answer by a chosen amount has, in
// cbps's verdict, the residual the analysis gives, with the rows that carry it named.
//
// The v-corner (12.2): a sphere (m = 1 kg, radius 0.1 m) in a V of planes tilted 45° and 30°, its
// two contact normals 75° apart. Each contact row k has J_k = (n_k, r × n_k) = (n_k, 0), so
// A = J Minv Jᵀ = [[1, cos 75°], [cos 75°, 1]] / m: A_kk = 1/m and the unit-free step ρ_k = m.
#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>

#include "cbps/base/error.hpp"
#include "cbps/io/matrix_market.hpp"
#include "fixture.hpp"

using namespace cbps;
using test::CliResult;
using test::run_cli;
using test::scratch_dir;
namespace fs = std::filesystem;

namespace {

const double kCos75 = std::cos(75.0 * std::numbers::pi / 180.0);
const double kSin75 = std::sin(75.0 * std::numbers::pi / 180.0);

void write_lambda(const fs::path& path, const VecX& lambda) {
  std::string text = "# lambda, N, one row a line\n";
  for (Eigen::Index k = 0; k < lambda.size(); ++k) text += number_text(lambda(k), 17) + "\n";
  test::write_file(path, text);
}

nlohmann::json check_json_of(const std::string& args, int code) {
  const CliResult r = run_cli("check " + args + " --json");
  INFO(r.err);
  REQUIRE(r.code == code);
  return nlohmann::json::parse(r.out);
}

}  // namespace

TEST_CASE("cbps check: a v-corner lambda off by delta on one row has the residual delta",
          "[cli][check]") {
  const fs::path dir = scratch_dir("check_v_corner");
  const std::string m = (dir / "m").string();
  REQUIRE(run_cli("matrices v-corner --step 5 --out " + m).code == 0);
  const MatX A = MatX(read_matrix_market_sparse(m + "/A.mtx"));
  const VecX b = read_matrix_market_vector(m + "/b.mtx");
  REQUIRE(A(0, 1) == Approx(kCos75).epsilon(1e-12));
  // Both contacts press (lambda* > 0): the exact answer solves A lambda* = b, here by Eigen's LU.
  const VecX exact = A.partialPivLu().solve(b);
  REQUIRE(exact.minCoeff() > 1.0);

  SECTION("the exact answer is solved, both rows between their bounds") {
    write_lambda(dir / "exact.txt", exact);
    const nlohmann::json j = check_json_of(m + " --lambda " + (dir / "exact.txt").string(), 0);
    CHECK(j["solved"] == true);
    CHECK(j["unit_free"]["relative"].get<double>() <= 1e-15);
    CHECK(j["statuses"]["between"] == 2);
    CHECK(j["exact"]["lambda_distance"].get<double>() <= 1e-14);
  }
  SECTION("lambda_0 + delta: row 0's term is delta, row 1's cos 75° delta") {
    const double delta = 1e-3;
    VecX lambda = exact;
    lambda(0) += delta;
    write_lambda(dir / "off.txt", lambda);
    const nlohmann::json j = check_json_of(m + " --lambda " + (dir / "off.txt").string(), 1);
    // w = A lambda − b = delta A e_0; both rows stay between their bounds, so each term is
    // |ρ_k w_k| = delta |A_k0| / A_kk: delta and cos 75° delta.
    CHECK(j["solved"] == false);
    CHECK(j["unit_free"]["residual"].get<double>() == Approx(delta).epsilon(1e-12));
    const nlohmann::json& worst = j["worst"];
    REQUIRE(worst.size() == 2);
    CHECK(worst[0]["label"] == "contact left-ball point 0");
    CHECK(worst[0]["status"] == "between");
    CHECK(worst[0]["residual"].get<double>() == Approx(delta).epsilon(1e-12));
    CHECK(worst[1]["label"] == "contact right-ball point 0");
    CHECK(worst[1]["residual"].get<double>() == Approx(kCos75 * delta).epsilon(1e-10));
    // The scale S = max(‖lambda‖∞, max_k ρ_k |b_k|) with ρ_k = m = 1 kg.
    const double scale = std::max(lambda.lpNorm<Eigen::Infinity>(), b.lpNorm<Eigen::Infinity>());
    CHECK(j["unit_free"]["scale"].get<double>() == Approx(scale).epsilon(1e-14));
    // From the exact answer: |w − w*| = delta max(1, cos 75°) (m = 1), |lambda − lambda*| =
    // delta, |J^T (lambda − lambda*)| = delta |n_0|∞ = delta cos 45° (the left plane's normal).
    const nlohmann::json& e = j["exact"];
    CHECK(e["available"] == true);
    CHECK(e["w_distance"].get<double>() == Approx(delta).epsilon(1e-10));
    CHECK(e["lambda_distance"].get<double>() == Approx(delta).epsilon(1e-10));
    CHECK(e["force_distance"].get<double>() == Approx(delta * std::sqrt(0.5)).epsilon(1e-10));
    // The text names the same row.
    const CliResult text = run_cli("check " + m + " --lambda " + (dir / "off.txt").string());
    CHECK(text.code == 1);
    CHECK(text.out.find("not solved") != std::string::npos);
    CHECK(text.out.find("between  contact left-ball point 0") != std::string::npos);
  }
  SECTION("lambda_1 = 0: row 1 at cmin with a negative w, its term delta-free") {
    VecX lambda = exact;
    lambda(1) = 0.0;
    write_lambda(dir / "open.txt", lambda);
    const nlohmann::json j =
        check_json_of(m + " --lambda " + (dir / "open.txt").string() + " --no-exact", 1);
    CHECK(j["statuses"]["at cmin"] == 1);
    CHECK(j["exact"].is_null());
    // Row 1: w_1 = A_10 lambda_0 − b_1 < 0 at its lower bound 0: term |0 − max(0 − w_1, 0)|.
    const double w1 = A(1, 0) * exact(0) - b(1);
    REQUIRE(w1 < 0.0);
    CHECK(j["worst"][0]["label"] == "contact right-ball point 0");
    CHECK(j["worst"][0]["status"] == "at cmin");
    CHECK(j["worst"][0]["residual"].get<double>() == Approx(-w1).epsilon(1e-12));
  }
}

TEST_CASE("cbps check: a cone contact's normal off by delta gives the closed-form natural map",
          "[cli][check]") {
  const fs::path dir = scratch_dir("check_v_corner_cone");
  const std::string m = (dir / "m").string();
  const double mu = 0.5;
  REQUIRE(
      run_cli("matrices v-corner --param mu=0.5 --param friction=cone --step 0 --out " + m).code ==
      0);
  // At rest (step 0) the frictionless equilibrium is an exact answer under the cone: the normal
  // rows' 2×2 system A_nn r_n = b_n, no friction, and then u = 0 at both contacts.
  const MatX A = MatX(read_matrix_market_sparse(m + "/A.mtx"));
  const VecX b = read_matrix_market_vector(m + "/b.mtx");
  REQUIRE(A.rows() == 6);
  Eigen::Matrix2d A_nn;
  A_nn << A(0, 0), A(0, 3), A(3, 0), A(3, 3);
  const Eigen::Vector2d r_n = A_nn.partialPivLu().solve(Eigen::Vector2d(b(0), b(3)));
  VecX lambda = VecX::Zero(6);
  lambda(0) = r_n(0);
  lambda(3) = r_n(1);
  REQUIRE((A * lambda - b).lpNorm<Eigen::Infinity>() <= 1e-14);
  const double delta = 1e-3;
  lambda(0) += delta;
  write_lambda(dir / "off.txt", lambda);
  const nlohmann::json j = check_json_of(m + " --lambda " + (dir / "off.txt").string(), 1);
  // A row of friction at a sphere's contact has A_tt = 1/m + r²/I = 3.5/m (I = 0.4 m r²), so each
  // contact's step is ρ = m/3.5. Pushing r_n of the left contact by delta moves u by delta
  // A e_0: at the left contact u = (delta, 0, 0), at the right one u = delta (cos 75°, sin 75°
  // along a tangent); both stay sticking (r − ρ û inside the cone), so each term is ρ ‖û‖ with
  // De Saxcé's û = u + mu ‖u_t‖ e_n:
  //   left   delta / 3.5,    right   delta / 3.5 · sqrt((cos 75° + mu sin 75°)² + sin² 75°).
  const double right = delta / 3.5 * std::hypot(kCos75 + mu * kSin75, kSin75);
  CHECK(j["law"] == "coulomb");
  CHECK(j["contacts"] == 2);
  CHECK(j["unit_free"]["residual"].get<double>() == Approx(right).epsilon(1e-9));
  const nlohmann::json& worst = j["worst"];
  REQUIRE(worst.size() == 2);
  CHECK(worst[0]["label"] == "contact right-ball point 0");
  CHECK(worst[0]["contact"] == 1);
  CHECK(worst[0]["status"] == "sticking");
  CHECK(worst[0]["residual"].get<double>() == Approx(right).epsilon(1e-9));
  CHECK(worst[1]["label"] == "contact left-ball point 0");
  CHECK(worst[1]["residual"].get<double>() == Approx(delta / 3.5).epsilon(1e-9));
  CHECK(j["cone"]["fclib_merit"].get<double>() > 0.0);
  // Every answer of this problem leaves the ball at rest (w* = 0), so |w − w*| = delta max_k
  // |A_k0| = delta (A_00 = 1/m) whichever of them direct returns (the friction forces of a
  // sphere in a V are not unique).
  CHECK(j["exact"]["w_distance"].get<double>() == Approx(delta).epsilon(1e-8));
}

TEST_CASE("cbps check: bad lambda files exit 2 naming the file", "[cli][check]") {
  const fs::path dir = scratch_dir("check_bad");
  const std::string m = (dir / "m").string();
  REQUIRE(run_cli("matrices v-corner --step 5 --out " + m).code == 0);
  const auto refused =
      [&](const std::string& name, const std::string& text, const std::string& says) {
        const fs::path path = dir / name;
        test::write_file(path, text);
        const CliResult r = run_cli("check " + m + " --lambda " + path.string());
        CAPTURE(name, r.err);
        CHECK(r.code == 2);
        CHECK(r.out.empty());
        CHECK(r.err.find(says) != std::string::npos);
      };
  refused("short.txt", "1\n", "lambda has 1 entries; the problem has 2 rows");
  refused("nan.txt", "1\nnan\n", "nan.txt: line 2: 'nan' is not finite");
  refused("word.txt", "1\n2 3\n", "word.txt: line 2: expected one number");
  refused("inf.mtx",
          "%%MatrixMarket matrix array real general\n2 1\n1\ninf\n",
          "inf.mtx: entry 2 is not finite");
  const CliResult missing = run_cli("check " + m + " --lambda " + (dir / "none.txt").string());
  CHECK(missing.code == 2);
  CHECK(missing.err.find("none.txt") != std::string::npos);
}

TEST_CASE("cbps check reads the folders of the recipe's C++ and Python engine examples",
          "[cli][check]") {
  // docs/check-any-engine.md: examples/engine_step.cpp (a ball on the ground in Coulomb's cone
  // and a ball hanging on a string, its lambda m g each, plus --error E on the contact's normal)
  // and examples/engine_step.py (a box on four corners, the engine's own sweeps).
  const fs::path dir = scratch_dir("check_engine_examples");
  SECTION("C++: the exact lambda is solved; E on the normal row leaves the term E / 3.5") {
    const std::string exact = (dir / "exact").string();
    REQUIRE(std::system(
                (std::string(CBPS_ENGINE_STEP_EXAMPLE) + " " + exact + " > /dev/null").c_str()) ==
            0);
    const nlohmann::json j = check_json_of(exact + " --lambda " + exact + "/lambda_engine.txt", 0);
    CHECK(j["unit_free"]["relative"].get<double>() <= 1e-15);
    CHECK(j["statuses"]["sticking"] == 1);
    CHECK(j["statuses"]["free"] == 1);
    // E on r_n: u = (E/m, 0, 0) at the contact, whose step is ρ = 1 / max(1/m, 1/m + R²/I) =
    // m / 3.5 (I = 0.4 m R²); r − ρ u stays inside the cone, so the term is ρ E / m = E / 3.5.
    const double error = 0.01;
    const std::string off = (dir / "off").string();
    REQUIRE(std::system((std::string(CBPS_ENGINE_STEP_EXAMPLE) + " " + off + " --error 0.01" +
                         " > /dev/null")
                            .c_str()) == 0);
    const nlohmann::json k = check_json_of(off + " --lambda " + off + "/lambda_engine.txt", 1);
    CHECK(k["unit_free"]["residual"].get<double>() == Approx(error / 3.5).epsilon(1e-12));
    CHECK(k["worst"][0]["label"] == "contact ground-ball #0");
    CHECK(k["exact"]["force_distance"].get<double>() == Approx(error).epsilon(1e-9));
  }
  SECTION("Python: the engine's 10 sweeps are not solved, 2000 are") {
    const std::string python =
        fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : std::string("python3");
    const std::string script = std::string(CBPS_SOURCE_DIR) + "/examples/engine_step.py";
    const std::string few = (dir / "few").string(), many = (dir / "many").string();
    REQUIRE(std::system((python + " " + script + " " + few + " > /dev/null").c_str()) == 0);
    REQUIRE(std::system(
                (python + " " + script + " " + many + " --iterations 2000 > /dev/null").c_str()) ==
            0);
    const nlohmann::json f = check_json_of(few + " --lambda " + few + "/lambda_engine.txt", 1);
    CHECK(f["unit_free"]["relative"].get<double>() > 1e-9);
    CHECK(f["contacts"] == 4);
    const nlohmann::json m = check_json_of(many + " --lambda " + many + "/lambda_engine.txt", 0);
    // The box's friction forces are not unique (four corners, a rigid face): lambda differs
    // from direct's answer while the net force on the box, J^T lambda, is the same.
    CHECK(m["exact"]["force_distance"].get<double>() <= 1e-9);
  }
}

TEST_CASE("cbps check reads the field's own files: FCLIB (a non-symmetric W) and Siconos LCP",
          "[cli][check]") {
  const fs::path dir = scratch_dir("check_field_files");
  // Siconos' Capsules (286 contacts, W not symmetric): nsgs's answer to its floor is solved, the
  // same answer with one contact's normal pushed by 1e-3 N is not.
  const std::string capsules = (test::kFc3dDir / "Capsules-i125-1213.hdf5").string();
  const std::string sol = (dir / "capsules").string();
  REQUIRE(run_cli("lcp " + capsules +
                  " --solver nsgs --iterations 100000 --tolerance 1e-14 --out " + sol)
              .code == 0);
  const nlohmann::json j = check_json_of(capsules + " --lambda " + sol + "/lambda.mtx", 0);
  CHECK(j["contacts"] == 286);
  CHECK(j["exact"]["available"] == true);
  VecX lambda = read_matrix_market_vector(sol + "/lambda.mtx");
  lambda(0) += 1e-3;
  write_lambda(dir / "pushed.txt", lambda);
  const nlohmann::json k =
      check_json_of(capsules + " --lambda " + (dir / "pushed.txt").string() + " --no-exact", 1);
  CHECK(k["worst"][0]["residual"].get<double>() > 1e-4);
  // A Siconos LCP: Lemke's answer (not direct's) is solved.
  const std::string lcp = (test::kSiconosDir / "lcp" / "lcp_deudeu.dat").string();
  const std::string lemke = (dir / "lemke").string();
  REQUIRE(run_cli("lcp " + lcp + " --solver lemke --out " + lemke).code == 0);
  const nlohmann::json l = check_json_of(lcp + " --lambda " + lemke + "/lambda.mtx", 0);
  CHECK(l["rows"] == 2);
  CHECK(l["exact"]["w_distance"].get<double>() <= 1e-12);
}
