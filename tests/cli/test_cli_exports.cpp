// What `cbps matrices`, `cbps explain` and `cbps lcp` show is the problem the step solved
// (issue "Trust", item 2): A is J Minv Jᵀ exactly, constraint-force mixing travels apart
// (cfm.txt), and Coulomb friction rows carry the bounds the step's lambda satisfies. (The solver
// tolerance reaching the direct path is tested in solvers/test_direct.cpp.)
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "cbps/io/matrix_market.hpp"
#include "fixture.hpp"

namespace fs = std::filesystem;
using namespace cbps;
using namespace cbps::test;

namespace {

/// The incline (incline_scene_json) with Coulomb friction, written to dir/incline.json.
std::string incline_scene(const fs::path& dir, double degrees) {
  const fs::path path = dir / "incline.json";
  write_file(path, incline_scene_json(degrees, "coulomb").dump(2));
  return path.string();
}

/// A JSON array of numbers, with cbps's "inf" and "-inf" strings read back.
VecX vector_of(const nlohmann::json& j) {
  VecX v(static_cast<Eigen::Index>(j.size()));
  for (std::size_t k = 0; k < j.size(); ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    if (j[k].is_string()) {
      v(i) = j[k] == "inf" ? kInf : j[k] == "-inf" ? -kInf : NAN;
    } else {
      v(i) = j[k].get<double>();
    }
  }
  return v;
}

}  // namespace

TEST_CASE("matrices and lcp with Coulomb friction: the bounds the step's lambda satisfies",
          "[cli][exports][coulomb]") {
  const fs::path dir = scratch_dir("exports_coulomb");
  const std::string scene = incline_scene(dir, 20.0);
  const fs::path m = dir / "m";
  const CliResult made = run_cli("matrices " + scene + " --out " + m.string());
  INFO(made.out << made.err);
  REQUIRE(made.code == 0);
  const VecX lambda = read_matrix_market_vector((m / "lambda.mtx").string());
  const VecX cmin = read_matrix_market_vector((m / "cmin.mtx").string());
  const VecX cmax = read_matrix_market_vector((m / "cmax.mtx").string());
  const auto labels = nlohmann::json::parse(slurp(m / "labels.json"));
  REQUIRE(labels.contains("coulomb"));
  const auto& rows = labels["coulomb"]["rows"];
  REQUIRE(rows.size() == 8);  // 4 contacts × 2 friction rows
  // At rest the contact forces carry the weight (6.2: J v2 = 0 with v1 = 0): the normal rows
  // sum to m g cos 20°, the friction rows to m g sin 20° along the slope (x).
  const double g = 9.81, a = 20.0 * kPi / 180.0;
  double normal_sum = 0.0;
  std::vector<int> normals;
  for (const auto& r : rows) {
    const int k = r["row"], n = r["normal_row"];
    CAPTURE(k, n);
    CHECK(r["mu"] == 0.5);
    // the written bounds are ±mu lambda_n of the final lambda, and lambda sits inside them up
    // to the fixed point's stopping rule (bounds move by ≤ 1e-12 max(1, ‖b‖∞) in the last round)
    CHECK(cmax(k) == Approx(0.5 * lambda(n)).epsilon(1e-12));
    CHECK(cmin(k) == Approx(-0.5 * lambda(n)).epsilon(1e-12));
    CHECK(cmax(k) > 0.5);
    CHECK(lambda(k) >= cmin(k) - 1e-9);
    CHECK(lambda(k) <= cmax(k) + 1e-9);
    if (std::find(normals.begin(), normals.end(), n) == normals.end()) {
      normals.push_back(n);
      normal_sum += lambda(n);
    }
  }
  REQUIRE(normals.size() == 4);
  CHECK(normal_sum == Approx(g * std::cos(a)).epsilon(1e-9));
  // Friction: J v2 = 0 makes the friction rows' impulses cancel gravity's slope component.
  const SpMat J = read_matrix_market_sparse((m / "J.mtx").string());
  VecX friction = VecX::Zero(lambda.size());
  for (const auto& r : rows) friction(r["row"].get<int>()) = lambda(r["row"].get<int>());
  const VecX force = SpMat(J.transpose()) * friction;  // on the box's 6 columns
  CHECK(force(0) == Approx(-g * std::sin(a)).epsilon(1e-9));
  CHECK(std::abs(force(2)) < 1e-9);

  // `cbps lcp` solves exactly that boxed problem and finds the same forces.
  const CliResult solved = run_cli("lcp " + m.string() + " --json");
  INFO(solved.out << solved.err);
  REQUIRE(solved.code == 0);
  const auto j = nlohmann::json::parse(solved.out);
  CHECK(j["status"] == "solved");
  const VecX lcp_lambda = vector_of(j["lambda"]);
  VecX lcp_friction = VecX::Zero(lambda.size());
  for (const auto& r : rows) lcp_friction(r["row"].get<int>()) = lcp_lambda(r["row"].get<int>());
  CHECK((SpMat(J.transpose()) * lcp_friction)(0) == Approx(-g * std::sin(a)).epsilon(1e-8));

  // `cbps explain --json` shows the same bounds, with the note, not zeros.
  const CliResult explained = run_cli("explain " + scene + " --json");
  REQUIRE(explained.code == 0);
  const auto e = nlohmann::json::parse(explained.out);
  const VecX e_lambda = vector_of(e["lambda"]["value"]);
  const VecX e_cmax = vector_of(e["cmax"]["value"]);
  CHECK(e["cmax"].contains("note"));
  for (const auto& r : rows) {
    const int k = r["row"], n = r["normal_row"];
    CHECK(e_cmax(k) == Approx(0.5 * e_lambda(n)).epsilon(1e-12));
    CHECK(e_cmax(k) > 0.5);
  }
}

TEST_CASE("matrices with Coulomb friction: a cube resting on an incline exports at any step",
          "[cli][exports][coulomb]") {
  // Issue 50, item 3: at step 20 the fixed point of the bounds waited for the bounds to stop
  // moving (the four normal forces of a resting cube are not unique), took 100 rounds and 1,792
  // factorizations, and wrote nothing. A sticking contact's lambda solves its own box at once.
  const fs::path dir = scratch_dir("exports_coulomb_steps");
  const std::string scene = incline_scene(dir, 20.0);
  const double g = 9.81, a = 20.0 * kPi / 180.0;
  for (const int step : {20, 60}) {
    CAPTURE(step);
    const std::string at = std::to_string(step);
    const fs::path m = dir / "m" / at;
    const CliResult made = run_cli("matrices " + scene + " --step " + at + " --out " + m.string());
    INFO(made.out << made.err);
    REQUIRE(made.code == 0);
    const VecX lambda = read_matrix_market_vector((m / "lambda.mtx").string());
    const VecX cmin = read_matrix_market_vector((m / "cmin.mtx").string());
    const VecX cmax = read_matrix_market_vector((m / "cmax.mtx").string());
    const auto labels = nlohmann::json::parse(slurp(m / "labels.json"));
    const auto& rows = labels["coulomb"]["rows"];
    REQUIRE(rows.size() == 8);
    double normal_sum = 0.0;
    std::vector<int> normals;
    for (const auto& r : rows) {
      const int k = r["row"], n = r["normal_row"];
      CHECK(cmax(k) == Approx(0.5 * lambda(n)).epsilon(1e-12));
      CHECK(cmin(k) == Approx(-0.5 * lambda(n)).epsilon(1e-12));
      CHECK(lambda(k) >= cmin(k) - 1e-9);
      CHECK(lambda(k) <= cmax(k) + 1e-9);
      if (std::find(normals.begin(), normals.end(), n) == normals.end()) {
        normals.push_back(n);
        normal_sum += lambda(n);
      }
    }
    // At rest, m g cos 20° on the four points (tan 20° = 0.36 < mu = 0.5: it sticks).
    CHECK(normal_sum == Approx(g * std::cos(a)).epsilon(1e-6));
    // And `cbps lcp` calls the written problem solved.
    const CliResult solved = run_cli("lcp " + m.string() + " --json");
    INFO(solved.out << solved.err);
    CHECK(solved.code == 0);
  }
}

TEST_CASE("matrices with cfm: A.mtx is J Minv J^T, eps apart in cfm.txt, lcp solves A + eps E",
          "[cli][exports][cfm]") {
  const fs::path dir = scratch_dir("exports_cfm");
  const fs::path m = dir / "m";
  const double eps = 1e-3;
  const CliResult made =
      run_cli("matrices chain --param n=4 --step 5 --cfm 1e-3 --out " + m.string());
  INFO(made.out << made.err);
  REQUIRE(made.code == 0);
  const SpMat J = read_matrix_market_sparse((m / "J.mtx").string());
  const SpMat Minv = read_matrix_market_sparse((m / "Minv.mtx").string());
  const SpMat A = read_matrix_market_sparse((m / "A.mtx").string());
  const MatX JMJ = MatX(J) * MatX(Minv) * MatX(J).transpose();
  CHECK((MatX(A) - JMJ).cwiseAbs().maxCoeff() <= 1e-12 * JMJ.cwiseAbs().maxCoeff());
  REQUIRE(fs::exists(m / "cfm.txt"));
  CHECK(std::stod(slurp(m / "cfm.txt")) == eps);
  CHECK(nlohmann::json::parse(slurp(m / "labels.json"))["cfm"] == eps);

  // lambda.mtx and `cbps lcp` both solve (A + eps E) lambda = b (all rows unbounded here).
  const VecX b = read_matrix_market_vector((m / "b.mtx").string());
  const VecX lambda = read_matrix_market_vector((m / "lambda.mtx").string());
  const MatX A_eps = JMJ + eps * MatX::Identity(JMJ.rows(), JMJ.cols());
  const VecX expected = A_eps.ldlt().solve(b);
  CHECK((lambda - expected).cwiseAbs().maxCoeff() <= 1e-9 * expected.cwiseAbs().maxCoeff());
  const CliResult solved = run_cli("lcp " + m.string() + " --json");
  INFO(solved.out << solved.err);
  REQUIRE(solved.code == 0);
  const auto j = nlohmann::json::parse(solved.out);
  CHECK(j["cfm"] == eps);
  const VecX lcp_lambda = vector_of(j["lambda"]);
  CHECK((lcp_lambda - expected).cwiseAbs().maxCoeff() <= 1e-9 * expected.cwiseAbs().maxCoeff());
  // Without cfm.txt the same folder is the problem of A alone: a different answer.
  fs::remove(m / "cfm.txt");
  const auto plain = nlohmann::json::parse(run_cli("lcp " + m.string() + " --json").out);
  CHECK(plain["cfm"] == 0.0);
  CHECK((vector_of(plain["lambda"]) - expected).cwiseAbs().maxCoeff() > 1e-6);

  // explain: A is J Minv J^T, eps shown apart.
  const auto e =
      nlohmann::json::parse(run_cli("explain chain --param n=4 --step 5 --cfm 1e-3 --json").out);
  CHECK(e["cfm"]["value"] == eps);
  const auto& rows = e["A"]["value"];
  for (std::size_t r = 0; r < rows.size(); ++r)
    CHECK(rows[r][r].get<double>() ==
          Approx(JMJ(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(r))).epsilon(1e-12));
}
