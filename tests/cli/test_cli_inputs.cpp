// Bad input the readers and commands used to let through (issue "Trust", item 4): each is
// refused with exit 2 and a message naming the value, nothing written; and `--check` that can
// fail (item 5); bodies named beside trajectory.csv (item 8).
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "fixture.hpp"

namespace fs = std::filesystem;
using namespace cbps::test;

namespace {

/// Runs `args --out DIR/out` and checks: exit 2, "cbps: " first, `expect` in the message, a
/// short message (no 300-digit DBL_MAX), and no output folder.
void refused(const std::string& args, const std::string& expect, const fs::path& dir) {
  CAPTURE(args);
  const fs::path out = dir / "out";
  const CliResult r = run_cli(args + " --out " + out.string());
  INFO(r.err);
  CHECK(r.code == 2);
  CHECK(r.err.rfind("cbps: ", 0) == 0);
  CHECK(r.err.find(expect) != std::string::npos);
  CHECK(r.err.find("179769") == std::string::npos);
  CHECK(r.err.size() < 400);
  CHECK_FALSE(fs::exists(out));
}

}  // namespace

TEST_CASE("run lengths that give no step or too many are refused", "[cli][inputs]") {
  const fs::path dir = scratch_dir("inputs_length");
  refused("run chain --duration 1e30", "--duration 1e+30", dir);
  refused("run chain --duration 1e-3", "shorter than half a step", dir);
  write_file(
      dir / "long.json",
      R"({"duration": 1e30, "bodies": [{"shape": {"type": "sphere", "radius": 0.1}, "mass": 1}]})");
  refused("run " + (dir / "long.json").string(), "the scene's duration 1e+30", dir);
  // explain and matrices take --step K; --steps and --duration would be ignored, so they are
  // not options of theirs.
  const CliResult e = run_cli("explain chain --steps 3");
  CHECK(e.code == 2);
  CHECK(e.err.find("--steps") != std::string::npos);
  refused("matrices chain --duration 1", "--duration", dir);
  fs::remove_all(dir);
}

TEST_CASE("option values are checked and named, without DBL_MAX in 300 digits", "[cli][inputs]") {
  const fs::path dir = scratch_dir("inputs_options");
  refused("run chain --seed -5", "--seed", dir);
  refused("run chain --iterations -1", "--iterations -1: must be >= 1", dir);
  refused("run chain --tolerance -1", "--tolerance -1: must be >= 0", dir);
  refused("run chain --solver pgs:order=random:order=natural", "'order=' given twice", dir);
  refused("run chain --check-tolerance 1e-3", "needs --check", dir);
  write_file(dir / "rod.json",
             R"({"bodies": [{"shape": {"type": "sphere", "radius": 0.1}, "mass": 1,
                             "inertia": [1, 1, 5]}]})");
  refused("run " + (dir / "rod.json").string(), "/bodies/0/inertia", dir);
  const CliResult big = run_cli("explain chain --param n=3000 --json");
  CHECK(big.code == 2);
  CHECK(big.err.find("3000 x 18000") != std::string::npos);
  CHECK(big.err.find("cbps matrices") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("stored problems: impossible bounds and non-symmetric A for converge are refused",
          "[cli][inputs][lcp]") {
  const fs::path dir = scratch_dir("inputs_stored");
  const fs::path m = dir / "m";
  REQUIRE(run_cli("matrices chain --param n=2 --step 3 --out " + m.string()).code == 0);
  const std::string header = "%%MatrixMarket matrix array real general\n2 1\n";
  write_file(m / "cmin.mtx", header + "inf\n-inf\n");  // no lambda is >= +inf
  refused("lcp " + m.string(), "cmin[0] = inf", dir);
  write_file(m / "cmin.mtx", header + "-inf\n-inf\n");
  write_file(m / "cmax.mtx", header + "inf\n-inf\n");
  refused("lcp " + m.string(), "cmax[1] = -inf", dir);
  // A non-symmetric stored A: lcp's direct path and converge's reference both refuse it.
  const fs::path lcp = dir / "nonsym.dat";
  write_file(lcp, "2\n0\n2 2\n2 2\n2 1\n0 2\n-1 -1\n");  // columns (2, 1) and (0, 2)
  refused("converge " + lcp.string() + " --solvers pgs --no-plot", "symmetric", dir);
  refused("lcp " + lcp.string() + " --solver direct", "symmetric", dir);
  fs::remove_all(dir);
}

TEST_CASE("a Siconos relay file is recognised by its contents, wherever it lies",
          "[cli][inputs][lcp][siconos]") {
  const std::string relay =
      std::string(CBPS_SOURCE_DIR) + "/fuzz/corpus/siconos/cbps_relay_2x2.dat";
  const CliResult r = run_cli("lcp " + relay + " --json");
  INFO(r.err);
  CHECK(r.code == 0);
  CHECK(nlohmann::json::parse(r.out)["status"] == "solved");
  const CliResult as_lcp = run_cli("lcp " + relay + " --siconos lcp");
  CHECK(as_lcp.code == 2);
  CHECK(as_lcp.err.find("after q") != std::string::npos);
  CHECK(run_cli("lcp " + relay + " --siconos boxed").code == 2);
}

TEST_CASE("lcp on a 4000-link chain's folder uses the exact path and solves it",
          "[cli][inputs][lcp]") {
  const fs::path dir = scratch_dir("inputs_chain4000");
  const fs::path m = dir / "m";
  REQUIRE(run_cli("matrices chain --param n=4000 --step 2 --out " + m.string()).code == 0);
  const CliResult r = run_cli("lcp " + m.string() + " --json");
  INFO(r.err);
  CHECK(r.code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["solver"] == "direct");
  CHECK(j["status"] == "solved");
  CHECK(j["rows"] == 4000);
  fs::remove_all(dir);
}

TEST_CASE("run --check with a tolerance fails the run and names the first step beyond it",
          "[cli][inputs][check]") {
  const fs::path dir = scratch_dir("inputs_check");
  const fs::path out = dir / "run";
  // A 100-link chain with a heavy end: 100 PGS sweeps leave v2 off the direct path's by up to
  // m/s. Step 0 starts from rest with the links horizontal, so b = -J Minv fext = 0 (gravity is
  // normal to every link) and lambda = 0 exactly: the first step beyond any tolerance is step 1.
  const std::string chain = "run chain --param n=100 --param mass_ratio=100 --steps 20 --quiet";
  const CliResult r = run_cli(chain + " --check --check-tolerance 1e-6 --out " + out.string());
  INFO(r.err);
  CHECK(r.code == 1);
  CHECK(r.err.find("the first step 1 ") != std::string::npos);
  const auto summary = nlohmann::json::parse(slurp(out / "summary.json"));
  const auto& check = summary["cross_check"];
  CHECK(check["first_step_beyond_tolerance"] == 1);
  CHECK(check["steps_beyond_tolerance"] == 19);
  CHECK(check["passed"] == false);
  CHECK(check["tolerance"] == 1e-6);
  // The direct path itself passes its own cross-check.
  const CliResult d = run_cli(chain + " --solver direct --check --check-tolerance 1e-9 --json");
  INFO(d.err);
  CHECK(d.code == 0);
  CHECK(nlohmann::json::parse(d.out)["cross_check"]["passed"] == true);
  // bodies.json names trajectory.csv's body column.
  const auto bodies = nlohmann::json::parse(slurp(out / "bodies.json"))["bodies"];
  REQUIRE(bodies.size() == 100);
  CHECK(bodies[0]["index"] == 0);
  CHECK(bodies[0]["name"] == "link0");
  CHECK(bodies[99]["mass"].get<double>() == Approx(10.0));  // 0.1 kg × mass_ratio 100
  fs::remove_all(dir);
}

TEST_CASE("an option that does not apply is refused, never dropped", "[cli][inputs][messages]") {
  // Issue 50, item 9: each of these ran, exit 0, as if the option had not been given.
  const fs::path dir = scratch_dir("options_not_applying");
  struct Case {
    std::string args;
    std::string said;
  };
  for (const Case& c :
       {Case{"run stack --param n=2 --steps 2 --compliance 1e-4", "--compliance"},
        Case{"run stack --param n=2 --steps 2 --scheme tgs --compliance 1e-4", "--compliance"},
        Case{"run stack --param n=2 --steps 2 --contact-hertz 60", "--contact-hertz"},
        Case{"run stack --param n=2 --steps 2 --scheme xpbd --contact-hertz 60", "--contact-hertz"},
        Case{"run chain --param n=2 --steps 2 --scheme tgs --joint-damping-ratio 1",
             "--joint-damping-ratio"},
        Case{"explain stack --param n=2 --joint-hertz 30", "--joint-hertz"}}) {
    CAPTURE(c.args);
    const CliResult r = run_cli(c.args);
    CHECK(r.code == 2);
    CHECK(r.err.find("cbps: " + c.said + " ") == 0);
    CHECK(r.err.find(": a setting of scheme ") != std::string::npos);
  }
  // Where they apply they run, and the clamped contact stiffness is reported as used: at dt
  // 1/60 and 4 substeps a quarter of the substep rate is 60 Hz.
  const CliResult soft = run_cli(
      "run stack --param n=2 --steps 2 --json --scheme soft-step --substeps 4 --contact-hertz 500");
  INFO(soft.err);
  REQUIRE(soft.code == 0);
  const auto j = nlohmann::json::parse(soft.out);
  CHECK(j["scheme"]["soft"]["contact_hertz"] == 500.0);
  CHECK(j["scheme"]["soft"]["contact_hertz_used"].get<double>() ==
        Approx(0.25 / (j["dt"].get<double>() / 4)));
  CHECK(run_cli("run stack --param n=2 --steps 2 --scheme xpbd --compliance 1e-6").code == 0);
  // --siconos says what a .dat file holds: given for a folder or an FCLIB file it is refused.
  REQUIRE(run_cli("matrices stack --param n=2 --quiet --out " + (dir / "m").string()).code == 0);
  const CliResult folder = run_cli("lcp " + (dir / "m").string() + " --siconos lcp");
  CHECK(folder.code == 2);
  CHECK(folder.err.find("--siconos lcp: says what a Siconos .dat file holds") != std::string::npos);
  const fs::path fclib = fs::path(CBPS_DATA_DIR) / "fclib";
  for (const auto& e : fs::directory_iterator(fclib)) {
    if (e.path().extension() != ".hdf5") continue;
    const CliResult r = run_cli("lcp " + e.path().string() + " --siconos relay");
    CHECK(r.code == 2);
    CHECK(r.err.find("an HDF5 (FCLIB) file") != std::string::npos);
    break;
  }
  // An empty file named .hdf5 is not read as a Siconos file.
  const fs::path empty = dir / "empty.hdf5";
  { std::ofstream out(empty); }
  const CliResult r = run_cli("lcp " + empty.string());
  CHECK(r.code == 2);
  CHECK(r.err == "cbps: " + empty.string() +
                     ": named as an HDF5 (FCLIB) file but not one: it is "
                     "empty\n");
}

TEST_CASE("messages a new user can act on: missing and binary files, --step, --html, --quiet",
          "[cli][inputs][messages]") {
  const fs::path dir = scratch_dir("new_user_messages");
  SECTION("a missing problem says no such file or folder, not line 0") {
    const CliResult r = run_cli("lcp " + (dir / "nothing").string());
    CHECK(r.code == 2);
    CHECK(r.err == "cbps: " + (dir / "nothing").string() + ": no such file or folder\n");
  }
  SECTION("an HDF5 file is named as a format cbps does not read, its bytes not echoed") {
    const fs::path hdf5 = dir / "fclib-problem.hdf5";
    {
      std::ofstream out(hdf5, std::ios::binary);
      out.write("\x89HDF\r\n\x1a\n\0\0\0\0\x01\x08\x08\0", 16);
    }
    const CliResult r = run_cli("lcp " + hdf5.string());
    CHECK(r.code == 2);
    CHECK(r.err.find("an HDF5 file") != std::string::npos);
    CHECK(r.err.find("\x89") == std::string::npos);
    CHECK(r.err.find('\x1a') == std::string::npos);
  }
  SECTION("--step takes 1e1 and gives its range for what it refuses") {
    CHECK(run_cli("matrices chain --param n=2 --step 1e1 --quiet --out " + (dir / "m").string())
              .code == 0);
    for (const std::string step : {"1e9", "1e9.5", "2.5", "-1", "1e13"}) {
      CAPTURE(step);
      const CliResult r = run_cli("explain chain --step " + step);
      CHECK(r.code == 2);
      CHECK(r.err.find("whole number of steps from 0 to 1e+07") != std::string::npos);
    }
  }
  SECTION("a folder given as a scene is named a folder") {
    const CliResult r = run_cli("run " + dir.string());
    CHECK(r.code == 2);
    CHECK(r.err.find(dir.string() + ": is a folder, not a scene") != std::string::npos);
  }
  SECTION("explain --html with an empty file name is refused") {
    const CliResult r = run_cli("explain chain --param n=2 --html ''");
    CHECK(r.code == 2);
    CHECK(r.out.empty());
    CHECK(r.err.find("empty file name") != std::string::npos);
  }
  SECTION("matrices --quiet prints nothing; one body is one movable body") {
    const CliResult quiet = run_cli("matrices slide --quiet --out " + (dir / "q").string());
    CHECK(quiet.code == 0);
    CHECK(quiet.out.empty());
    const CliResult loud = run_cli("matrices slide --out " + (dir / "l").string());
    CHECK(loud.code == 0);
    CHECK(loud.out.find(", 1 movable body;") != std::string::npos);
    const CliResult run = run_cli("run slide --steps 1");
    CHECK(run.out.find("slide: 1 step of ") != std::string::npos);
  }
  SECTION("--help shows no {false} artefacts") {
    for (const std::string command : {"run",
                                      "explain",
                                      "matrices",
                                      "lcp",
                                      "converge",
                                      "profile",
                                      "stress",
                                      "scenes",
                                      "verify"}) {
      CAPTURE(command);
      const CliResult r = run_cli(command + " --help");
      CHECK(r.code == 0);
      CHECK(r.out.find("{false}") == std::string::npos);
      CHECK(r.out.find("{true}") == std::string::npos);
    }
  }
  fs::remove_all(dir);
}
