// `cbps lcp` against its contract (docs/cli-contract.md): a `cbps matrices` folder solved
// by every solver to the same lambda, Siconos LCP and relay files, exit codes 0/1/2, errors
// naming the file, and --out written only when solved.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "cbps/io/matrix_market.hpp"
#include "cbps/io/stored_problem.hpp"
#include "cbps/system/cone_problem.hpp"
#include "fixture.hpp"

namespace fs = std::filesystem;

using namespace cbps;
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

namespace {

/// Every method name of the solver grammar, written out here (not read from cbps), each with a
/// spec that runs it; one more spec per parameter kind (:OMEGA, order=, a method's own key).
/// A method added to the grammar without a line here fails "the unknown-name message lists
/// exactly these".
const std::vector<std::pair<std::string, std::string>> kEveryMethod = {
    {"pgs", "pgs"},
    {"psor:OMEGA", "psor:1.3"},
    {"sgs[:OMEGA]", "sgs"},
    {"jacobi[:OMEGA]", "jacobi:0.5"},
    {"block-pgs", "block-pgs"},
    {"matrix-free", "matrix-free"},
    {"pgs-nesterov[:OMEGA]", "pgs-nesterov"},
    {"apgd", "apgd"},
    {"nncg", "nncg"},
    {"pgs-sm", "pgs-sm"},
    {"admm", "admm"},
    {"rbgs[:OMEGA]", "rbgs"},
    {"shock[:OMEGA]", "shock"},
    {"direct", "direct"},
    {"active-set", "active-set"},
    {"lemke", "lemke"},
    {"nsgs", "nsgs"},
};
/// The peers' names (solvers/peers/peers.hpp), listed after cbps's own; they are judged, not
/// required to agree, in tests/solvers/test_peers.cpp and test_cli_peers.cpp.
const std::vector<std::string> kPeerNames = {"siconos:lemke",
                                             "siconos:pgs",
                                             "siconos:enum",
                                             "siconos:avi",
                                             "siconos:fc3d-nsgs",
                                             "siconos:fc3d-nsn-ac",
                                             "siconos:fc3d-prox",
                                             "siconos:fc3d-admm",
                                             "bullet:dantzig",
                                             "bullet:lemke",
                                             "bullet:pgs"};
const std::vector<std::string> kWithParameters = {"apgd:restart=off",
                                                  "nsgs:local=1",
                                                  "pgs:order=random",
                                                  "pgs:order=reverse:warm=off",
                                                  "sgs:1.2",
                                                  "pgs-nesterov:restart=off",
                                                  "admm:rho=2",
                                                  "shock:level_sweeps=2",
                                                  "pgs-sm:sweeps=2"};

/// The names between "(valid: " and the closing parenthesis of an error message.
std::vector<std::string> valid_names(const std::string& err) {
  const auto from = err.find("(valid: ");
  const auto to = err.find(')', from);
  std::vector<std::string> names;
  if (from == std::string::npos || to == std::string::npos) return names;
  std::istringstream list(err.substr(from + 8, to - from - 8));
  std::string name;
  while (std::getline(list, name, ',')) names.push_back(name.substr(name.find_first_not_of(' ')));
  return names;
}

}  // namespace

TEST_CASE("cbps lcp runs every method of the solver grammar, with its parameters",
          "[cli][lcp][methods]") {
  const fs::path dir = scratch_dir("lcp_every_method");
  // A chain (distance rows: unbounded, A definite) and a ball in a V (two contact rows, push
  // only, A definite): lambda is unique on both, so every method must find the same one. The
  // references are Lemke's pivoting and the direct path, independent of each other and of the
  // sweeps.
  for (const char* scene : {"chain --param n=5 --step 3", "v-corner --step 5"}) {
    CAPTURE(scene);
    const fs::path m = dir / std::string(scene).substr(0, std::string(scene).find(' '));
    REQUIRE(run_cli("matrices " + std::string(scene) + " --out " + m.string()).code == 0);
    std::vector<std::string> specs;
    for (const auto& [name, spec] : kEveryMethod) specs.push_back(spec);
    specs.insert(specs.end(), kWithParameters.begin(), kWithParameters.end());
    std::vector<double> lemke, direct;
    for (const char* reference : {"lemke", "direct"}) {
      const CliResult r = run_cli("lcp " + m.string() + " --json --solver " + reference);
      REQUIRE(r.code == 0);
      (std::string(reference) == "lemke" ? lemke : direct) =
          lambda_of(nlohmann::json::parse(r.out));
    }
    REQUIRE(lemke.size() == direct.size());
    double largest = 1.0;
    for (std::size_t k = 0; k < lemke.size(); ++k) {
      CHECK(std::abs(lemke[k] - direct[k]) <= 1e-9 * std::max(1.0, std::abs(lemke[k])));
      largest = std::max(largest, std::abs(lemke[k]));
    }
    for (const std::string& spec : specs) {
      CAPTURE(spec);
      const CliResult r = run_cli("lcp " + m.string() + " --json --solver " + spec);
      INFO(r.out << r.err);
      REQUIRE(r.code == 0);
      const nlohmann::json j = nlohmann::json::parse(r.out);
      CHECK(j.at("status") == "solved");
      CHECK(j.at("solver") == spec);
      CHECK(j.at("residual").get<double>() <= 1e-9 * j.at("scale").get<double>());
      const std::vector<double> lambda = lambda_of(j);
      REQUIRE(lambda.size() == lemke.size());
      // Residual <= 1e-10 N on a definite A of smallest eigenvalue >= 1e-2 kg^-1 puts lambda
      // within 1e-8 N of the solution.
      for (std::size_t k = 0; k < lambda.size(); ++k)
        CHECK(std::abs(lambda[k] - lemke[k]) <= 1e-7 * largest);
    }
  }
  SECTION("--iterations bounds the sweeps of every iterative method") {
    const fs::path m = dir / "chain";
    for (const char* spec : {"pgs", "apgd", "psor:1.3", "admm"}) {
      CAPTURE(spec);
      const CliResult r = run_cli("lcp " + m.string() + " --json --iterations 3 --solver " + spec);
      CHECK(r.code == 1);
      const nlohmann::json j = nlohmann::json::parse(r.out);
      CHECK(j.at("status") == "failed");
      CHECK(j.at("iterations") == 3);
    }
  }
}

TEST_CASE("cbps lcp refuses the methods that read J on a Siconos file (exit 2, why)",
          "[cli][lcp][methods]") {
  for (const char* spec : {"matrix-free", "shock", "shock:level_sweeps=2"}) {
    CAPTURE(spec);
    const CliResult r =
        run_cli("lcp " + siconos("relay/relay_4x4.dat") + " --solver " + spec + " --json");
    CHECK(r.code == 2);
    CHECK(r.out.empty());
    CHECK(r.err.rfind("cbps: --solver " + std::string(spec), 0) == 0);
    CHECK(r.err.find("a Siconos file carries no J and Minv") != std::string::npos);
    CHECK(r.err.find("J.mtx and Minv.mtx") != std::string::npos);
  }
  // A bad parameter is the grammar's message, exit 2.
  const CliResult bad = run_cli("lcp " + siconos("relay/relay_4x4.dat") + " --solver psor:3");
  CHECK(bad.code == 2);
  CHECK(bad.err.find("relaxation factor '3' must be a number in (0, 2)") != std::string::npos);
}

TEST_CASE("one list of solver names: --help and every unknown-name message",
          "[cli][lcp][methods]") {
  std::vector<std::string> every;
  for (const auto& [name, spec] : kEveryMethod) every.push_back(name);
  every.insert(every.end(), kPeerNames.begin(), kPeerNames.end());
  std::vector<std::string> with_tao = every;
  with_tao.push_back("tao:TYPE");

  const fs::path dir = scratch_dir("lcp_one_list");
  const fs::path m = dir / "chain";
  REQUIRE(run_cli("matrices chain --param n=3 --out " + m.string()).code == 0);
  // The commands that take tao:TYPE list it; `run` steps a scene, which TAO does not.
  const std::vector<std::pair<std::string, std::vector<std::string>>> commands = {
      {"lcp " + m.string() + " --solver nope", with_tao},
      {"converge " + m.string() + " --no-plot --solvers pgs,nope", with_tao},
      {"profile " + dir.string() + " --solvers pgs,nope --out " + (dir / "p").string(), with_tao},
      {"run chain --steps 1 --solver nope", every},
  };
  for (const auto& [command, names] : commands) {
    CAPTURE(command);
    const CliResult r = run_cli(command);
    INFO(r.err);
    CHECK(r.code == 2);
    CHECK(r.err.find("'nope': unknown solver") != std::string::npos);
    CHECK(valid_names(r.err) == names);
  }
  // --help of every command that names a method lists every name with what it is.
  for (const char* command : {"lcp", "converge", "profile", "run"}) {
    CAPTURE(command);
    const CliResult r = run_cli(std::string(command) + " --help");
    REQUIRE(r.code == 0);
    for (const auto& [name, spec] : kEveryMethod) {
      CAPTURE(name);
      CHECK(r.out.find("\n  " + name.substr(0, name.find_first_of(":[")) + " ") !=
            std::string::npos);
    }
  }
}

TEST_CASE("cbps lcp: Lemke's words agree with the status", "[cli][lcp][lemke]") {
  // The case: a 200-link chain with mass ratio 1000. Lemke's pivoting ends in a ray
  // termination whose last point already passes the residual check (residual 1.9e-11 N against
  // 1e-9 x scale 20): the run is solved, and nothing it prints may say "no solution".
  const fs::path dir = scratch_dir("lcp_lemke_words");
  const fs::path m = dir / "m";
  REQUIRE(
      run_cli("matrices chain --param n=200 --param mass_ratio=1000 --step 1 --out " + m.string())
          .code == 0);
  const CliResult j = run_cli("lcp " + m.string() + " --solver lemke --json");
  INFO(j.out << j.err);
  REQUIRE(j.code == 0);
  const nlohmann::json result = nlohmann::json::parse(j.out);
  CHECK(result.at("status") == "solved");
  CHECK(result.at("message").get<std::string>().find("no solution") == std::string::npos);
  CHECK(result.at("message").get<std::string>().find("solved") != std::string::npos);
  const CliResult text = run_cli("lcp " + m.string() + " --solver lemke");
  INFO(text.out);
  REQUIRE(text.code == 0);
  CHECK(text.out.find("lemke: solved") != std::string::npos);
  CHECK(text.out.find("no solution") == std::string::npos);
  // And where there is none, it says so: status no_solution, the ray named.
  const CliResult none =
      run_cli("lcp " + siconos("lcp/lcp_Pang_isolated_sol_perturbed.dat") + " --json");
  CHECK(none.code == 1);
  const nlohmann::json n = nlohmann::json::parse(none.out);
  CHECK(n.at("status") == "no_solution");
  CHECK(n.at("message").get<std::string>().find("no solution found") != std::string::npos);
}

TEST_CASE("cbps lcp: a folder with J and Minv is solved in body space, and says why",
          "[cli][lcp][space]") {
  // A pyramid of 28 boxes (588 rows, enough for the interior point: 500 and more) whose folder
  // keeps A, b, cmin, cmax, J and Minv but not v1, fext and dt.
  const fs::path dir = scratch_dir("lcp_space");
  const fs::path m = dir / "m";
  REQUIRE(run_cli("matrices pyramid --param base=7 --step 1 --out " + m.string()).code == 0);
  for (const char* name : {"v1.mtx", "fext.mtx", "dt.txt"}) fs::remove(m / name);
  const CliResult body = run_cli("lcp " + m.string() + " --solver direct --json");
  INFO(body.out << body.err);
  REQUIRE(body.code == 0);
  const nlohmann::json b = nlohmann::json::parse(body.out);
  REQUIRE(b.at("rows").get<long>() >= 500);
  CHECK(b.at("status") == "solved");
  CHECK(b.at("space") == "body");
  CHECK(b.at("space_reason") == "body: J and Minv present");
  // matrix-free needs only J and Minv too.
  CHECK(run_cli("lcp " + m.string() + " --solver matrix-free --iterations 5").code == 1);

  // Without J.mtx the same problem is solved in row space, and the reason names the file.
  fs::remove(m / "J.mtx");
  const CliResult row = run_cli("lcp " + m.string() + " --solver direct --json");
  INFO(row.out << row.err);
  REQUIRE(row.code == 0);
  const nlohmann::json r = nlohmann::json::parse(row.out);
  CHECK(r.at("space") == "row");
  CHECK(r.at("space_reason") == "row: no J.mtx in the folder");
  const CliResult text = run_cli("lcp " + m.string() + " --solver direct");
  CHECK(text.out.find("space row: no J.mtx in the folder") != std::string::npos);
  // Both found the same forces where they are unique: w = A lambda - b agrees; compare the
  // residuals only (A is singular: four contacts per face).
  CHECK(r.at("residual").get<double>() <= 1e-9 * r.at("scale").get<double>());
  const CliResult mf = run_cli("lcp " + m.string() + " --solver matrix-free");
  CHECK(mf.code == 2);
  CHECK(mf.err.find("no J.mtx in the folder") != std::string::npos);
}

TEST_CASE("lemke is a method wherever a method is named: run and converge", "[cli][lcp][lemke]") {
  const fs::path dir = scratch_dir("lemke_everywhere");
  // A chain of 3 links: its A is definite, so Lemke's pivoting solves every step.
  const CliResult run = run_cli("run chain --param n=3 --steps 3 --solver lemke --json");
  INFO(run.out << run.err);
  REQUIRE(run.code == 0);
  const nlohmann::json r = nlohmann::json::parse(run.out);
  CHECK(r.at("solver").at("method") == "lemke");
  CHECK(r.at("iterations_total").get<long>() > 0);

  const fs::path m = dir / "m";
  REQUIRE(run_cli("matrices chain --param n=5 --step 3 --out " + m.string()).code == 0);
  const CliResult converge =
      run_cli("converge " + m.string() + " --solvers lemke,pgs --no-plot --quiet --out " +
              (dir / "c").string());
  INFO(converge.err);
  CHECK(converge.code == 0);
  CHECK(slurp(dir / "c" / "convergence.csv").find("\nlemke,") != std::string::npos);
}

TEST_CASE("cbps lcp takes a folder's row kinds and manifolds from its labels.json",
          "[cli][lcp][methods]") {
  // A `cbps matrices` folder labels each row (docs/outputs.md): contacts_first and block PGS
  // read the kinds and manifolds from it, as `cbps profile` and `cbps converge` do. Without
  // labels.json the rows have no kind (contacts_first refused, exit 2) and block PGS takes
  // every row alone, which sweeps differently: the residual after the same 20 sweeps tells the
  // two apart.
  const fs::path dir = scratch_dir("lcp_labels");
  const fs::path m = dir / "stack";
  REQUIRE(
      run_cli("matrices stack --param n=3 --param columns=2 --step 30 --quiet --out " + m.string())
          .code == 0);
  const auto solve = [&](const std::string& spec) {
    const CliResult r = run_cli("lcp " + m.string() + " --json --iterations 20 --solver " + spec);
    INFO(r.out << r.err);
    REQUIRE(r.code <= 1);
    return nlohmann::json::parse(r.out);
  };
  const auto contacts_first = solve("pgs:contacts_first=on");
  CHECK(contacts_first.at("solver") == "pgs:contacts_first=on");
  CHECK(contacts_first.at("iterations").get<int>() >= 1);
  const double manifolds = solve("block-pgs").at("residual").get<double>();
  fs::rename(m / "labels.json", dir / "labels.json");
  const CliResult refused = run_cli("lcp " + m.string() + " --solver pgs:contacts_first=on");
  CHECK(refused.code == 2);
  CHECK(refused.err.find("labels.json") != std::string::npos);
  const double alone = solve("block-pgs").at("residual").get<double>();
  CAPTURE(manifolds, alone);
  CHECK(manifolds != alone);
  fs::remove_all(dir);
}

TEST_CASE("cbps lcp and converge read an FCLIB file: nsgs, direct, --cone, the cone object",
          "[cli][lcp][fclib]") {
  const std::string file =
      std::string(CBPS_DATA_DIR) + "/fclib/Boxes_Stack_local_problem_test.hdf5";
  // The default on cones with a symmetric W is the exact path (issue 50, item 8: lcp --help,
  // the README and the contract say so; it was nsgs).
  const CliResult by_default = run_cli("lcp " + file + " --json");
  INFO(by_default.err);
  CHECK(by_default.code == 0);
  CHECK(nlohmann::json::parse(by_default.out).at("solver") == "direct");
  for (const char* law : {"coulomb", "ccp"}) {
    CAPTURE(law);
    const CliResult r = run_cli("lcp " + file + " --json --solver nsgs --iterations 300 --cone " +
                                std::string(law));
    INFO(r.err);
    CHECK(r.code == 1);  // 300 sweeps are far from 1e-9 of the scale: not solved, said so
    const nlohmann::json j = nlohmann::json::parse(r.out);
    CHECK(j.at("solver") == "nsgs");
    CHECK(j.at("status") == "failed");
    CHECK(j.at("rows") == 144);
    CHECK(j.at("lambda").size() == 144);
    const nlohmann::json& cone = j.at("cone");
    CHECK(cone.at("law") == law);
    CHECK(cone.at("contacts") == 48);
    CHECK(cone.at("natural_map").get<double>() == j.at("residual").get<double>());
    for (const char* key : {"signorini", "violation", "dissipation", "fclib_merit"})
      CHECK(cone.at(key).get<double>() >= 0.0);
  }
  const CliResult text = run_cli("lcp " + file + " --iterations 30000 --solver nsgs");
  CHECK(text.out.find("(FCLIB file)") != std::string::npos);
  CHECK(text.out.find("cone law coulomb, 48 contacts") != std::string::npos);

  // The exact path on the same file, both laws: solved, lambda in the file's row order (r),
  // the residual verified against the scale.
  for (const char* law : {"coulomb", "ccp"}) {
    CAPTURE(law);
    const CliResult r =
        run_cli("lcp " + file + " --json --solver direct --cone " + std::string(law));
    INFO(r.err);
    CHECK(r.code == 0);
    const nlohmann::json j = nlohmann::json::parse(r.out);
    CHECK(j.at("solver") == "direct");
    CHECK(j.at("status") == "solved");
    CHECK(j.at("lambda").size() == 144);
    CHECK(j.at("residual").get<double>() <= 1e-10);
    CHECK(j.at("wall_time_s").get<double>() >= 0.0);
    CHECK(j.at("cone").at("law") == law);
  }

  // Siconos' own solvers of this very problem (the file came from a Siconos simulation), judged
  // by cbps: PROX answers to cbps's criterion on it; NSGS's 300 iterations do not. Whatever
  // each returns, the verdict is cbps's residual of that lambda, the peer's word beside it.
  for (const char* peer : {"siconos:fc3d-prox", "siconos:fc3d-nsgs"}) {
    CAPTURE(peer);
    const CliResult r = run_cli("lcp " + file + " --json --iterations 300 --solver " + peer);
    INFO(r.err);
    const bool prox = std::string(peer) == "siconos:fc3d-prox";
    CHECK(r.code == (prox ? 0 : 1));
    const nlohmann::json j = nlohmann::json::parse(r.out);
    CHECK(j.at("status") == (prox ? "solved" : "failed"));
    CHECK(j.at("lambda").size() == 144);
    const double residual = j.at("residual").get<double>();
    CHECK((residual <= 1e-9 * j.at("scale").get<double>()) == prox);
    CHECK(j.at("cone").at("natural_map").get<double>() == residual);
    CHECK(j.at("peer").at("status") == (prox ? "info 0" : "info 1"));
  }
  const CliResult relaxed = run_cli("lcp " + file + " --cone ccp --solver siconos:fc3d-prox");
  CHECK(relaxed.code == 2);
  CHECK(relaxed.err.find("Coulomb's law") != std::string::npos);

  const CliResult boxed = run_cli("lcp " + file + " --solver pgs");
  CHECK(boxed.code == 2);
  CHECK(boxed.err.find("friction cones") != std::string::npos);
  const CliResult bad_law = run_cli("lcp " + file + " --cone elliptic");
  CHECK(bad_law.code == 2);
  CHECK(bad_law.err.find("coulomb or ccp") != std::string::npos);
  const fs::path dir = scratch_dir("lcp_fclib");
  const fs::path m = dir / "chain";
  REQUIRE(run_cli("matrices chain --param n=3 --out " + m.string()).code == 0);
  // converge on the file: the direct path on cones is the reference; nsgs's milestones and the
  // cone law in the summary; --cone on a scene is refused.
  const CliResult converge = run_cli("converge " + file +
                                     " --solvers nsgs,direct --iterations 2000 --no-plot --json "
                                     "--quiet --cone ccp");
  INFO(converge.err);
  REQUIRE(converge.code == 0);
  const nlohmann::json c = nlohmann::json::parse(converge.out);
  CHECK(c.at("cone").at("law") == "ccp");
  CHECK(c.at("cone").at("contacts") == 48);
  CHECK(c.at("reference").at("termination") == "direct solve");
  CHECK(c.at("reference").at("residual").get<double>() <= 1e-10);
  REQUIRE(c.at("solvers").size() == 2);
  CHECK(c.at("solvers")[0].at("solver") == "nsgs");
  CHECK(c.at("solvers")[0].at("reached").at("1e-10").is_null());  // 2000 sweeps: far from it
  CHECK(!c.at("solvers")[1].at("reached").at("1e-10").is_null());
  const CliResult boxed_converge = run_cli("converge " + file + " --solvers pgs --no-plot");
  CHECK(boxed_converge.code == 2);
  CHECK(boxed_converge.err.find("friction cones") != std::string::npos);
  const CliResult scene_cone = run_cli("converge stack --cone ccp --no-plot");
  CHECK(scene_cone.code == 2);
  CHECK(scene_cone.err.find("--param cone=LAW") != std::string::npos);
  const CliResult run = run_cli("run " + file);
  CHECK(run.code == 2);
  CHECK(run.err.find("not a scene") != std::string::npos);
  const CliResult no_cones = run_cli("lcp " + m.string() + " --cone ccp");
  CHECK(no_cones.code == 2);
  CHECK(no_cones.err.find("no contacts in friction cones") != std::string::npos);
}

TEST_CASE("a folder on cones with a non-symmetric A: direct by default, and it meets the law",
          "[cli][lcp][cones]") {
  // Issue 51, item 1: direct on cones takes any A (past the relaxation's interior point on A's
  // symmetric part, its stages solve Coulomb's law on A itself). A is made non-symmetric by
  // hand, J and Minv removed so that A alone is the problem; the answer is judged here by the
  // natural map of Coulomb's law on that A, from the JSON's lambda alone.
  const auto dir = scratch_dir("lcp_cones_asymmetric");
  const fs::path folder = dir / "slide";
  REQUIRE(run_cli("matrices slide --param friction=cone --step 5 --quiet --out " + folder.string())
              .code == 0);
  fs::remove(folder / "J.mtx");
  fs::remove(folder / "Minv.mtx");
  SpMat A = read_matrix_market_sparse((folder / "A.mtx").string());
  A.coeffRef(1, 0) += 1e-3 * A.coeff(0, 0);  // max |A - A^T| far above round-off
  write_matrix_market((folder / "A.mtx").string(), A, "A made non-symmetric by the test");
  const CliResult by_default = run_cli("lcp " + folder.string() + " --json");
  INFO(by_default.err);
  REQUIRE(!by_default.out.empty());
  const nlohmann::json j = nlohmann::json::parse(by_default.out);
  CHECK(j.at("solver") == "direct");
  CHECK(j.at("status") == "solved");
  CHECK(by_default.code == 0);
  const StoredProblem p = read_problem(folder.string());
  REQUIRE(!p.cones.empty());
  const std::vector<double> values = lambda_of(j);
  const VecX lambda = Eigen::Map<const VecX>(values.data(), Eigen::Index(values.size()));
  REQUIRE(lambda.size() == p.rows());
  const VecX w = p.A * lambda - p.b;
  CHECK(natural_map_residual(w, lambda, p.cmin, p.cmax, p.cones) <= 1e-9);
}
