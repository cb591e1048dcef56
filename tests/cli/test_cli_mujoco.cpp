// `cbps mujoco MODEL --out DIR` writes each step asked as a problem folder that `cbps check`
// reads, with MuJoCo's answer beside it; bad input exits 2 naming it (docs/mujoco.md).
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <string>

#include "cbps/io/mujoco_problem.hpp"
#include "fixture.hpp"

using namespace cbps;
using test::CliResult;
using test::run_cli;
using test::scratch_dir;
namespace fs = std::filesystem;

TEST_CASE("cbps mujoco writes steps cbps check judges MuJoCo's forces on", "[cli][mujoco]") {
  const fs::path dir = scratch_dir("mujoco_cli");
  const std::string model =
      std::string(CBPS_SOURCE_DIR) + "/tests/data/mujoco/hinge_chain_limits.xml";
  const std::string out = (dir / "chain").string();
  const CliResult r =
      run_cli("mujoco " + model + " --keyframe bent --steps 21 --every 10 --out " + out);
  if (!mujoco_built()) {
    CHECK(r.code == 2);
    CHECK(r.err.find("libmujoco-dev") != std::string::npos);
    return;
  }
  REQUIRE(r.code == 0);
  CHECK(r.out.find("step-20: 4 rows, 0 contacts; MuJoCo newton:") != std::string::npos);
  for (const char* file : {"A.mtx",
                           "b.mtx",
                           "cmin.mtx",
                           "cmax.mtx",
                           "labels.json",
                           "lambda_mujoco.mtx",
                           "mujoco_J.mtx",
                           "mujoco_M.mtx",
                           "mujoco_R.mtx"})
    CHECK(fs::exists(fs::path(out) / "step-10" / file));
  const nlohmann::json stats =
      nlohmann::json::parse(test::slurp(fs::path(out) / "step-10" / "mujoco.json"));
  CHECK(stats["solver"] == "newton");
  CHECK(stats["tolerance"] == 1e-15);
  CHECK(stats["nv"] == 4);
  // MuJoCo's Newton at its floor: cbps's verdict is solved, exit 0.
  const CliResult check =
      run_cli("check " + out + "/step-20 --lambda " + out + "/step-20/lambda_mujoco.mtx --json");
  CHECK(check.code == 0);
  // Two PGS sweeps are not MuJoCo's answer to its own problem: cbps says so, exit 1.
  const std::string pgs = (dir / "pgs").string();
  REQUIRE(run_cli("mujoco " + model +
                  " --keyframe bent --steps 21 --step 20 --mujoco-solver pgs "
                  "--mujoco-iterations 2 --out " +
                  pgs)
              .code == 0);
  CHECK(run_cli("check " + pgs + "/step-20 --lambda " + pgs + "/step-20/lambda_mujoco.mtx").code ==
        1);
  CHECK(run_cli("mujoco " + (dir / "none.xml").string() + " --out " + (dir / "x").string()).code ==
        2);
  const CliResult step =
      run_cli("mujoco " + model + " --steps 3 --step 7 --out " + (dir / "y").string());
  CHECK(step.code == 2);
  CHECK(step.err.find("--step 7: not one of the 3 steps run") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "y"));
  fs::remove_all(dir);
}
