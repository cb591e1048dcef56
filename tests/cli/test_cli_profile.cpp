// cbps profile: every solver on every problem of a library, performance profiles of the costs.
#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "fixture.hpp"

using cbps::test::run_cli;
using cbps::test::scratch_dir;
using cbps::test::slurp;
namespace fs = std::filesystem;

namespace {

constexpr const char* kTolerances[] = {"0.0001", "1e-08", "1e-10"};

/// A library of four small problems laid out as scripts/make_problem_library.py lays one out:
/// two `cbps matrices` folders (a chain: A definite; a two-box stack with friction: A singular)
/// and two Siconos files with the direct path's answer written by `cbps lcp`. Three are quick.
fs::path make_library(const fs::path& dir) {
  const fs::path lib = dir / "lib";
  fs::create_directories(lib / "siconos");
  REQUIRE(run_cli("matrices chain --param n=5 --step 20 --out " + (lib / "chain").string()).code ==
          0);
  REQUIRE(run_cli("matrices stack --param n=2 --step 10 --out " + (lib / "stack").string()).code ==
          0);
  nlohmann::json problems = nlohmann::json::array();
  problems.push_back({{"name", "chain"},
                      {"path", "chain"},
                      {"exact", "chain/lambda.mtx"},
                      {"definite", true},
                      {"quick", true}});
  problems.push_back({{"name", "stack"},
                      {"path", "stack"},
                      {"exact", "stack/lambda.mtx"},
                      {"definite", false},
                      {"quick", true}});
  for (const auto& [group, name, quick] :
       {std::tuple{"relay", "relay_4x4", false}, std::tuple{"lcp", "lcp_deudeu", true}}) {
    const fs::path file = lib / "siconos" / (std::string(name) + ".dat");
    fs::copy_file(fs::path(CBPS_DATA_DIR) / "siconos" / group / (std::string(name) + ".dat"), file);
    const fs::path direct = lib / "siconos" / (std::string(name) + ".direct");
    REQUIRE(
        run_cli("lcp " + file.string() + " --solver direct --tolerance 0 --out " + direct.string())
            .code == 0);
    problems.push_back({{"name", name},
                        {"path", "siconos/" + std::string(name) + ".dat"},
                        {"exact", "siconos/" + std::string(name) + ".direct/lambda.mtx"},
                        {"definite", true},
                        {"quick", quick}});
  }
  std::ofstream(lib / "library.json")
      << nlohmann::json{{"format", "cbps-problem-library/1"}, {"problems", problems}}.dump(2);
  return lib;
}

/// The cost of a measurement at a tolerance (time or sweeps), +inf when not reached.
double cost_of(const nlohmann::json& m, const std::string& tolerance, const std::string& measure) {
  const nlohmann::json& at = m["reached"][tolerance];
  if (at.is_null()) return std::numeric_limits<double>::infinity();
  return measure == "time" ? at["time_s"].get<double>() : at["iterations"].get<double>();
}

}  // namespace

TEST_CASE("cbps profile runs every solver on every problem and writes the documented files",
          "[cli][profile]") {
  const auto dir = scratch_dir("profile");
  const fs::path lib = make_library(dir);
  const fs::path out = dir / "p";
  const auto start = std::chrono::steady_clock::now();
  const auto r = run_cli("profile " + lib.string() +
                         " --solvers pgs,sgs,apgd,direct --budget-iterations 5000 --time-limit 1 "
                         "--quiet --out " +
                         out.string());
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(elapsed < 10.0);  // four problems of at most 24 rows, plot included
  for (const char* file : {"profile.json",
                           "profile.csv",
                           "summary.txt",
                           "profile.png",
                           "profile.svg",
                           "cbps-manifest.json"})
    CHECK(fs::exists(out / file));
  CHECK(r.out.find(slurp(out / "summary.txt")) == 0);  // the table on stdout is summary.txt

  const auto j = nlohmann::json::parse(slurp(out / "profile.json"));
  REQUIRE(j["problems"].size() == 4);
  REQUIRE(j["measurements"].size() == 16);
  std::map<std::string, std::map<std::string, nlohmann::json>> by;  // problem → solver → run
  for (const auto& m : j["measurements"]) {
    const std::string problem = m["problem"], solver = m["solver"];
    CAPTURE(problem, solver);
    by[problem][solver] = m;
    // The first sweep at 1e-10 is no earlier than at 1e-8, and that no earlier than at 1e-4.
    for (const std::string measure : {"time", "sweeps"}) {
      if (solver == "direct" && measure == "sweeps") continue;
      CHECK(cost_of(m, "0.0001", measure) <= cost_of(m, "1e-08", measure));
      CHECK(cost_of(m, "1e-08", measure) <= cost_of(m, "1e-10", measure));
    }
    if (!m["reached"]["1e-10"].is_null()) CHECK(m["status"] == "solved");
    // lambda* is unique only where A is definite: the error is reported there alone.
    CHECK(m["lambda_error"].is_null() == (problem == "stack"));
  }
  // The exact path: one solve, to 1e-10 on each problem, with a time and no sweeps.
  for (const auto& [problem, runs] : by) {
    CAPTURE(problem);
    const nlohmann::json& direct = runs.at("direct");
    CHECK(direct["status"] == "solved");
    CHECK(direct["reached"]["1e-10"]["iterations"].is_null());
    CHECK(direct["reached"]["1e-10"]["time_s"].get<double>() > 0.0);
    // PGS reaches 1e-10 on these small problems within 5000 sweeps.
    CHECK(runs.at("pgs")["status"] == "solved");
    if (problem != "stack") CHECK(runs.at("pgs")["lambda_error"].get<double>() < 1e-6);
  }

  // Each profile's rho(tau), recomputed here from the measurements: r = cost / best cost over
  // the profile's solvers (Dolan & More eq. 1); the sweep profiles leave the exact path out.
  REQUIRE(j["profiles"].size() == 6);
  for (const auto& profile : j["profiles"]) {
    const std::string measure = profile["measure"];
    char tolerance[16];
    std::snprintf(tolerance, sizeof tolerance, "%g", profile["tolerance"].get<double>());
    CAPTURE(measure, tolerance);
    std::vector<std::string> solvers = profile["solvers"];
    CHECK(solvers.size() == (measure == "time" ? 4u : 3u));
    for (const std::string& solver : solvers) {
      CAPTURE(solver);
      for (const double tau : {1.0, 2.0, 10.0}) {
        int within = 0;
        for (const auto& [problem, runs] : by) {
          double best = std::numeric_limits<double>::infinity();
          for (const std::string& other : solvers)
            best = std::min(best, cost_of(runs.at(other), tolerance, measure));
          const double cost = cost_of(runs.at(solver), tolerance, measure);
          if (std::isfinite(cost) && cost <= tau * best) ++within;
        }
        char key[16];
        std::snprintf(key, sizeof key, "%g", tau);
        CHECK(profile["rho"][solver][key].get<double>() == Approx(within / 4.0));
      }
    }
  }

  // profile.csv: one row per problem and solver.
  std::istringstream csv(slurp(out / "profile.csv"));
  std::string line;
  std::getline(csv, line);
  CHECK(line ==
        "problem,solver,rows,status,iterations,time_s,residual_relative,lambda_error,"
        "sweeps_to_0.0001,time_to_0.0001,sweeps_to_1e-08,time_to_1e-08,sweeps_to_1e-10,"
        "time_to_1e-10");
  int rows = 0;
  while (std::getline(csv, line)) ++rows;
  CHECK(rows == 16);

  // --quick: only the problems marked quick.
  const auto quick =
      run_cli("profile " + lib.string() + " --quick --solvers pgs --quiet --no-plot --json");
  REQUIRE(quick.code == 0);
  CHECK(nlohmann::json::parse(quick.out)["problems"].size() == 3);
}

TEST_CASE("cbps profile with a solver that fails everywhere gives it rho = 0", "[cli][profile]") {
  const auto dir = scratch_dir("profile_fail");
  const fs::path lib = make_library(dir);
  // One sweep of projected Jacobi damped to 0.1 moves lambda a tenth of the way: it cannot
  // reach a unit-free 1e-4 from lambda = 0 on any of these problems.
  const auto r = run_cli("profile " + lib.string() +
                         " --solvers jacobi:0.1,direct --budget-iterations 1 --quiet --no-plot "
                         "--json");
  INFO(r.err);
  REQUIRE(r.code == 0);
  const auto j = nlohmann::json::parse(r.out);
  for (const auto& m : j["measurements"])
    if (m["solver"] == "jacobi:0.1") {
      CAPTURE(m["problem"]);
      CHECK(m["status"] == "iteration budget");
      for (const char* t : kTolerances) CHECK(m["reached"][t].is_null());
    }
  for (const auto& profile : j["profiles"]) {
    CHECK(profile["rho"]["jacobi:0.1"]["10"].get<double>() == 0.0);
    CHECK(profile["rho"]["jacobi:0.1"]["inf"].get<double>() == 0.0);
    if (profile["measure"] == "time") CHECK(profile["rho"]["direct"]["1"].get<double>() == 1.0);
  }
}

TEST_CASE("cbps profile refuses bad input with exit 2, naming the file", "[cli][profile]") {
  const auto dir = scratch_dir("profile_bad");
  const fs::path out = dir / "out";
  SECTION("no library") {
    const auto r = run_cli("profile " + (dir / "none").string() + " --out " + out.string());
    CHECK(r.code == 2);
    CHECK(r.err.find((dir / "none").string()) != std::string::npos);
  }
  SECTION("not a library") {
    fs::create_directories(dir / "lib");
    std::ofstream(dir / "lib" / "library.json") << "{\"format\": \"something-else\"}";
    const auto r = run_cli("profile " + (dir / "lib").string() + " --out " + out.string());
    CHECK(r.code == 2);
    CHECK(r.err.find("library.json: /format") != std::string::npos);
  }
  SECTION("a bad solver spec") {
    const auto r = run_cli("profile " + (dir / "none").string() + " --solvers pgs,fastest");
    CHECK(r.code == 2);
    CHECK(r.err.find("fastest") != std::string::npos);
  }
  SECTION("a solver listed twice") {
    const auto r = run_cli("profile " + (dir / "none").string() + " --solvers pgs,jacobi,pgs");
    CHECK(r.code == 2);
    CHECK(r.err.find("--solvers 'pgs,jacobi,pgs': 'pgs' is listed twice") != std::string::npos);
  }
  SECTION("two specs for the same solver") {
    // psor with omega = 1 is PGS (7.1.1), and warm factors never act from lambda = 0: the
    // curves would coincide.
    for (const std::string list : {"pgs,psor:1", "pgs:warm=off,pgs"}) {
      const auto r = run_cli("profile " + (dir / "none").string() + " --solvers " + list);
      CHECK(r.code == 2);
      CHECK(r.err.find("is the same solver as") != std::string::npos);
    }
  }
  SECTION("specs that differ in a setting are not duplicates") {
    const auto r =
        run_cli("profile " + (dir / "none").string() + " --solvers pgs,psor:1.3,pgs:order=reverse");
    CHECK(r.code == 2);  // the missing library, not the list
    CHECK(r.err.find((dir / "none").string()) != std::string::npos);
    CHECK(r.err.find("--solvers") == std::string::npos);
  }
  SECTION("a problem that cannot be read") {
    fs::create_directories(dir / "lib");
    std::ofstream(dir / "lib" / "library.json")
        << R"({"format": "cbps-problem-library/1", "problems": [)"
        << R"({"name": "gone", "path": "gone.dat", "exact": "gone.mtx"}]})";
    const auto r = run_cli("profile " + (dir / "lib").string() + " --out " + out.string());
    CHECK(r.code == 2);
    CHECK(r.err.find("gone.dat") != std::string::npos);
  }
  CHECK_FALSE(fs::exists(out));  // nothing written
}

TEST_CASE("cbps profile on a folder of problem files without library.json", "[cli][profile]") {
  // Issue 51, item 4: Siconos' own dumps (a local problem whose W is not symmetric, a global
  // one), an FCLIB file and a non-symmetric Siconos LCP, side by side, their answers unknown.
  const auto dir = scratch_dir("profile_folder");
  const fs::path folder = dir / "problems";
  fs::create_directories(folder);
  const fs::path fc3d = fs::path(CBPS_DATA_DIR) / "siconos-fc3d";
  for (const char* name : {"Rover4396.dat", "GFC3D_Example0.dat"})
    fs::copy_file(fc3d / name, folder / name);
  fs::copy_file(fs::path(CBPS_DATA_DIR) / "fclib" / "Boxes_Stack_local_problem_test.hdf5",
                folder / "boxes.hdf5");
  fs::copy_file(fs::path(CBPS_DATA_DIR) / "siconos" / "lcp" / "lcp_CPS_4.dat",
                folder / "lcp_CPS_4.dat");
  fs::create_directories(folder / "not-a-problem");  // no A.mtx: not listed
  const auto r = run_cli("profile " + folder.string() +
                         " --solvers nsgs,direct --time-limit 5 --quiet --no-plot --json");
  INFO(r.err);
  REQUIRE(r.code == 0);
  const nlohmann::json j = nlohmann::json::parse(r.out);
  REQUIRE(j.at("problems").size() == 4);
  CHECK(j.at("problems")[0].at("name") == "GFC3D_Example0.dat");  // name order
  CHECK(j.at("problems")[0].at("exact").is_null());
  std::map<std::string, std::string> status;
  for (const auto& m : j.at("measurements"))
    status[m.at("problem").get<std::string>() + " " + m.at("solver").get<std::string>()] =
        m.at("status").get<std::string>();
  CHECK(status.at("Rover4396.dat direct") == "solved");
  CHECK(status.at("GFC3D_Example0.dat direct") == "solved");
  CHECK(status.at("boxes.hdf5 direct") == "solved");
  // CPS 4's M is not symmetric: the QP's exact path does not apply; nsgs is PGS there.
  CHECK(status.at("lcp_CPS_4.dat direct").rfind("not applicable: A is not symmetric", 0) == 0);
  for (const auto& m : j.at("measurements")) CHECK(m.at("lambda_error").is_null());
  // --quick needs a library's marks.
  const auto quick = run_cli("profile " + folder.string() + " --quick --solvers nsgs --no-plot");
  CHECK(quick.code == 2);
  CHECK(quick.err.find("no library.json to mark problems quick") != std::string::npos);
  // A folder with nothing to profile.
  const auto empty = run_cli("profile " + (folder / "not-a-problem").string() + " --no-plot");
  CHECK(empty.code == 2);
  CHECK(empty.err.find("no library.json and no problem in it") != std::string::npos);
}
