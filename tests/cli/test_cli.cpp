// The command line against its contract (docs/cli-contract.md): exit codes, error
// messages naming what was wrong, nothing written on failure, the files of `run` and `matrices`.
#include <catch2/catch.hpp>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "fixture.hpp"

namespace fs = std::filesystem;

using namespace cbps::test;

TEST_CASE("cbps --help and every command's --help exit 0", "[cli]") {
  CHECK(run_cli("--help").code == 0);
  for (const char* c : {"scenes", "run", "explain", "matrices", "verify", "lcp"}) {
    CAPTURE(c);
    const CliResult r = run_cli(std::string(c) + " --help");
    CHECK(r.code == 0);
    CHECK(r.out.find("Usage") != std::string::npos);
  }
}

TEST_CASE("cbps scenes lists the built-in scenes with parameters and units", "[cli]") {
  const CliResult r = run_cli("scenes --json");
  REQUIRE(r.code == 0);
  CHECK(r.out.find("\"pendulum-wave\"") != std::string::npos);
  CHECK(r.out.find("\"chain\"") != std::string::npos);
  CHECK(r.out.find("\"theta0_deg\"") != std::string::npos);
}

TEST_CASE("cbps run --out writes summary.json, trajectory.csv and steps.csv", "[cli]") {
  const fs::path dir = scratch_dir("run");
  const fs::path out = dir / "wave";
  const CliResult r =
      run_cli("run pendulum-wave --param n=3 --steps 24 --check --quiet --out " + out.string());
  INFO(r.err);
  REQUIRE(r.code == 0);
  const std::string summary = slurp(out / "summary.json");
  for (const char* key : {"\"scene\"",
                          "\"parameters\"",
                          "\"steps\"",
                          "\"dt\"",
                          "\"solver\"",
                          "\"iterations_total\"",
                          "\"wall_time_s\"",
                          "\"max_constraint_error\"",
                          "\"energy_initial\"",
                          "\"energy_final\"",
                          "\"stages\"",
                          "\"cross_check\"",
                          "\"max_velocity_difference\"",
                          "\"steps_checked\": 24"}) {
    CAPTURE(key);
    CHECK(summary.find(key) != std::string::npos);
  }
  CHECK(summary.find("collision") == std::string::npos);  // no contacts, no collision stage
  std::ifstream traj(out / "trajectory.csv");
  std::string header;
  std::getline(traj, header);
  CHECK(header == "t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz");
  int rows = 0;
  for (std::string line; std::getline(traj, line);) ++rows;
  CHECK(rows == 3 * 25);  // 3 bodies at t = 0 and after each of 24 steps
  std::ifstream steps(out / "steps.csv");
  std::getline(steps, header);
  CHECK(header ==
        "t,rows,warm_rows,iterations,residual,max_constraint_error,energy,direct_route,"
        "wall_time_s,solve_time_s");
  fs::remove_all(dir);
}

TEST_CASE("bad input exits 2 with a message naming what was wrong, and writes nothing", "[cli]") {
  const fs::path dir = scratch_dir("bad");
  const fs::path out = dir / "out";
  write_file(dir / "malformed.json", "{\"bodies\": [ {\"shape\": }\n");
  write_file(dir / "negative_mass.json",
             R"({"bodies": [{"shape": {"type": "sphere", "radius": 0.1}, "mass": -1}]})");
  struct Case {
    std::string args;
    std::string expect;
  };
  const Case cases[] = {
      {"run no-such-scene", "no-such-scene"},
      {"run chain --param links=3", "unknown parameter 'links'"},
      {"run chain --param n=-2", "'n'"},
      {"run chain --dt 0", "--dt"},
      {"run chain --dt nan", "--dt"},
      {"run chain --solver magic", "--solver"},
      {"run " + (dir / "malformed.json").string(), "line 1"},
      {"run " + (dir / "negative_mass.json").string(), "/bodies/0/mass"},
      {"run chain --param n=3 --steps", "usage"},
      {"frobnicate", "usage"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.args);
    const CliResult r = run_cli(c.args + " --out " + out.string());
    INFO(r.err);
    CHECK(r.code == 2);
    CHECK(r.err.rfind("cbps: ", 0) == 0);
    CHECK(r.err.find(c.expect) != std::string::npos);
    CHECK_FALSE(fs::exists(out));
  }
  fs::remove_all(dir);
}

TEST_CASE("cbps matrices writes the system as Matrix Market files", "[cli]") {
  const fs::path dir = scratch_dir("mtx");
  const fs::path out = dir / "m";
  const CliResult r = run_cli("matrices chain --param n=4 --step 2 --out " + out.string());
  INFO(r.err);
  REQUIRE(r.code == 0);
  for (const char* f : {"J.mtx",
                        "Minv.mtx",
                        "A.mtx",
                        "b.mtx",
                        "cmin.mtx",
                        "cmax.mtx",
                        "v1.mtx",
                        "fext.mtx",
                        "upsilon.mtx",
                        "lambda.mtx",
                        "labels.json",
                        "dt.txt"}) {
    CAPTURE(f);
    CHECK(fs::exists(out / f));
  }
  const std::string J = slurp(out / "J.mtx");
  CHECK(J.rfind("%%MatrixMarket matrix coordinate real general", 0) == 0);
  CHECK(slurp(out / "cmin.mtx").find("-inf") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("cbps verify passes every derivation check and exits 0", "[cli]") {
  const CliResult r = run_cli("verify");
  INFO(r.out);
  CHECK(r.code == 0);
  CHECK(r.out.find("5.2.1") != std::string::npos);
  CHECK(r.out.find("FAIL") == std::string::npos);
}

TEST_CASE("cbps explain labels rows by constraint and columns by body and coordinate", "[cli]") {
  const CliResult r = run_cli("explain chain --param n=2 --json");
  REQUIRE(r.code == 0);
  CHECK(r.out.find("\"joint1\"") != std::string::npos);
  CHECK(r.out.find("\"link1.wz\"") != std::string::npos);
  CHECK(r.out.find("\"6.2.9\"") != std::string::npos);
}
