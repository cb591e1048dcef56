// `cbps lcp` against its contract (docs/cli-contract.md): a `cbps matrices` folder solved
// by every solver to the same lambda, Siconos LCP and relay files, exit codes 0/1/2, errors
// naming the file, and --out written only when solved.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "fixture.hpp"

namespace fs = std::filesystem;

using namespace cbps::test;

namespace {

std::string siconos(const std::string& relative) {
  return std::string(CBPS_DATA_DIR) + "/siconos/" + relative;
}

std::vector<double> lambda_of(const nlohmann::json& j) {
  std::vector<double> v;
  for (const auto& x : j.at("lambda")) v.push_back(x.get<double>());
  return v;
}

}  // namespace

TEST_CASE("cbps lcp: lemke, pgs and direct agree on a chain's system (A positive definite)",
          "[cli][lcp]") {
  const fs::path dir = scratch_dir("lcp_chain");
  const fs::path m = dir / "m";
  const CliResult made = run_cli("matrices chain --param n=5 --step 3 --out " + m.string());
  INFO(made.err);
  REQUIRE(made.code == 0);
  std::vector<std::vector<double>> lambdas;
  for (const char* solver : {"lemke", "pgs", "direct"}) {
    CAPTURE(solver);
    const CliResult r = run_cli("lcp " + m.string() + " --json --solver " + solver);
    INFO(r.out << r.err);
    REQUIRE(r.code == 0);
    const nlohmann::json j = nlohmann::json::parse(r.out);
    CHECK(j.at("status") == "solved");
    CHECK(j.at("solver") == solver);
    CHECK(j.at("residual").get<double>() <= 1e-9 * j.at("scale").get<double>());
    CHECK(j.at("rows").get<long>() > 0);
    lambdas.push_back(lambda_of(j));
    CHECK(lambdas.back().size() == j.at("rows").get<std::size_t>());
  }
  // The default for a folder (a symmetric A = J Minv Jᵀ) is the exact path.
  const CliResult d = run_cli("lcp " + m.string() + " --json");
  REQUIRE(d.code == 0);
  CHECK(nlohmann::json::parse(d.out).at("solver") == "direct");
  double largest = 0.0;
  for (double x : lambdas[0]) largest = std::max(largest, std::abs(x));
  for (std::size_t s = 1; s < lambdas.size(); ++s) {
    REQUIRE(lambdas[s].size() == lambdas[0].size());
    for (std::size_t k = 0; k < lambdas[0].size(); ++k) {
      CAPTURE(s, k);
      CHECK(std::abs(lambdas[s][k] - lambdas[0][k]) <= 1e-8 * std::max(1.0, largest));
    }
  }
}

TEST_CASE("cbps lcp: Siconos files, solved, no solution, relay", "[cli][lcp]") {
  SECTION("lcp_CPS_1 is solved") {
    const CliResult r = run_cli("lcp " + siconos("lcp/lcp_CPS_1.dat") + " --json");
    INFO(r.out << r.err);
    CHECK(r.code == 0);
    const nlohmann::json j = nlohmann::json::parse(r.out);
    CHECK(j.at("status") == "solved");
    CHECK(j.at("solver") == "lemke");
    CHECK(j.at("rows") == 2);
  }
  SECTION("the perturbed Pang problem has no solution: exit 1") {
    const CliResult r =
        run_cli("lcp " + siconos("lcp/lcp_Pang_isolated_sol_perturbed.dat") + " --json");
    INFO(r.out << r.err);
    CHECK(r.code == 1);
    CHECK(nlohmann::json::parse(r.out).at("status") == "no_solution");
  }
  SECTION("a relay file is solved by the boxed Lemke method") {
    const CliResult r = run_cli("lcp " + siconos("relay/relay_2x2.dat") + " --json");
    INFO(r.out << r.err);
    CHECK(r.code == 0);
    CHECK(nlohmann::json::parse(r.out).at("status") == "solved");
  }
  SECTION("text output names the status and residual") {
    const CliResult r = run_cli("lcp " + siconos("lcp/lcp_CPS_1.dat"));
    CHECK(r.code == 0);
    CHECK(r.out.find("solved") != std::string::npos);
    CHECK(r.out.find("residual") != std::string::npos);
  }
  SECTION("direct solves a symmetric bounded (relay) problem") {
    const CliResult r =
        run_cli("lcp " + siconos("relay/relay_4x4.dat") + " --solver direct --json");
    INFO(r.err);
    CHECK(r.code == 0);
    CHECK(nlohmann::json::parse(r.out).at("status") == "solved");
  }
  SECTION("direct refuses a non-symmetric matrix with exit 2 and suggests lemke") {
    const CliResult r = run_cli("lcp " + siconos("lcp/lcp_CPS_2.dat") + " --solver direct");
    CHECK(r.code == 2);
    CHECK(r.err.find("symmetric") != std::string::npos);
    CHECK(r.err.find("lemke") != std::string::npos);
  }
}

TEST_CASE("cbps lcp: bad input exits 2 naming the file", "[cli][lcp]") {
  const fs::path dir = scratch_dir("lcp_bad");
  SECTION("a missing file") {
    const std::string path = (dir / "missing.dat").string();
    const CliResult r = run_cli("lcp " + path);
    CHECK(r.code == 2);
    CHECK(r.err.rfind("cbps: ", 0) == 0);
    CHECK(r.err.find(path) != std::string::npos);
  }
  SECTION("a malformed .dat file") {
    const fs::path path = dir / "bad.dat";
    std::ofstream(path) << "2\n0\n2 2\n2 2\n1 0\n0 oops\n-1 -1\n";
    const CliResult r = run_cli("lcp " + path.string());
    CHECK(r.code == 2);
    CHECK(r.err.rfind("cbps: ", 0) == 0);
    CHECK(r.err.find(path.string() + ": line 6") != std::string::npos);
  }
  SECTION("a matrices folder with a malformed b.mtx") {
    const fs::path m = dir / "m";
    REQUIRE(run_cli("matrices chain --param n=2 --out " + m.string()).code == 0);
    std::ofstream(m / "b.mtx") << "%%MatrixMarket matrix array real general\n1 1\nnan\n";
    const CliResult r = run_cli("lcp " + m.string());
    CHECK(r.code == 2);
    CHECK(r.err.find((m / "b.mtx").string() + ": line 3") != std::string::npos);
  }
}

TEST_CASE("cbps lcp --out writes result.json and lambda.mtx only when solved", "[cli][lcp]") {
  const fs::path dir = scratch_dir("lcp_out");
  const fs::path good = dir / "good";
  const CliResult r = run_cli("lcp " + siconos("lcp/lcp_CPS_1.dat") + " --out " + good.string());
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(fs::exists(good / "result.json"));
  CHECK(fs::exists(good / "lambda.mtx"));
  const nlohmann::json j = nlohmann::json::parse(slurp(good / "result.json"));
  CHECK(j.at("status") == "solved");

  const fs::path bad = dir / "bad";
  const CliResult n = run_cli("lcp " + siconos("lcp/lcp_Pang_isolated_sol_perturbed.dat") +
                              " --out " + bad.string());
  CHECK(n.code == 1);
  CHECK_FALSE(fs::exists(bad));
  for (const auto& e : fs::directory_iterator(dir)) {
    CAPTURE(e.path().string());
    CHECK(e.path().filename().string().find(".tmp") == std::string::npos);
  }
}
