// `cbps run` beyond its files (test_cli.cpp): a divergence keeps the steps before it and exits 1,
// scene files set the divergence limits and cfm, cfm's effect is reported, and the same inputs
// give byte-identical outputs, and the direct path says per step how it reached its answer.
#include <stdlib.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cbps/solvers/peers/peers.hpp"
#include "fixture.hpp"

using cbps::test::run_cli;
using cbps::test::scratch_dir;
using cbps::test::slurp;

TEST_CASE("a run whose method fails its steps says so: a warning, exit 1 under --check-tolerance",
          "[cli][run][peers]") {
  // Issue 50, item 5: `run stack --solver bullet:dantzig` sank the stack 4.82 m and exited 0
  // without a word (Dantzig's method returns false on every step of it).
  if (!cbps::peer_available(cbps::Method::BulletDantzig)) {
    WARN("this build has no Bullet: not tested");
    return;
  }
  const auto r = run_cli("run stack --param n=3 --steps 5 --solver bullet:dantzig --json");
  INFO(r.err);
  REQUIRE(r.code == 0);  // a warning: the run itself completed
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["steps_with_rows"] == 5);
  CHECK(j["steps_method_failed"] == 5);
  REQUIRE(j["warnings"].size() == 1);
  CHECK(j["warnings"][0].get<std::string>().rfind("the method failed 5 of 5 steps with rows "
                                                  "(every one), the first step 0: bullet:dantzig",
                                                  0) == 0);
  CHECK(r.err.find("cbps run: warning: the method failed 5 of 5 steps") != std::string::npos);
  // Asked to be strict, it fails; the scene's own PGS does not warn.
  CHECK(run_cli("run stack --param n=3 --steps 5 --solver bullet:dantzig --check "
                "--check-tolerance 1e9")
            .code == 1);
  const auto pgs = run_cli("run stack --param n=3 --steps 5 --json");
  REQUIRE(pgs.code == 0);
  CHECK(nlohmann::json::parse(pgs.out)["warnings"].empty());
}

TEST_CASE("cbps run keeps the steps before a divergence and exits 1", "[stress][divergence][cli]") {
  const auto dir = scratch_dir("diverge");
  const auto r = run_cli("run stack --solver jacobi --out " + (dir / "out").string());
  CHECK(r.code == 1);
  CHECK(r.err.find("diverged: step 0") != std::string::npos);
  const auto summary = nlohmann::json::parse(slurp(dir / "out" / "summary.json"));
  CHECK(summary["status"] == "diverged");
  CHECK(summary["divergence"]["step"] == 0);
  CHECK(summary["divergence"]["row"].get<int>() >= 0);
  CHECK(summary["steps"] == 0);
  // trajectory.csv holds the initial state of all 11 bodies: the header and 11 lines.
  const std::string trajectory = slurp(dir / "out" / "trajectory.csv");
  CHECK(std::count(trajectory.begin(), trajectory.end(), '\n') == 12);
}

TEST_CASE("cbps run reports the effect of cfm", "[stress][cfm][cli]") {
  const auto r = run_cli("run chain --steps 10 --cfm 1e-4 --json --quiet");
  REQUIRE(r.code == 0);
  const auto summary = nlohmann::json::parse(r.out);
  CHECK(summary["solver"]["cfm"] == 1e-4);
  CHECK(summary["regularization"]["max_acceleration_error"].get<double>() > 0.0);
  CHECK(summary["regularization"]["max_velocity_error"].get<double>() ==
        Approx(summary["regularization"]["max_acceleration_error"].get<double>() / 240.0));
  CHECK(run_cli("run chain --steps 10 --cfm -1").code != 0);
}

TEST_CASE("the same inputs give byte-identical outputs", "[stress][determinism][cli]") {
  const auto dir = scratch_dir("determinism");
  for (const char* args : {"run stack --param n=4 --steps 60 --solver pgs:order=random --seed 7",
                           "run stack --param n=4 --steps 60 --solver direct",
                           "run chain --steps 200 --solver block-pgs"}) {
    INFO(args);
    const std::string common = std::string(args) + " --no-timing --quiet --out ";
    REQUIRE(run_cli(common + (dir / "a").string()).code == 0);
    REQUIRE(run_cli(common + (dir / "b").string()).code == 0);
    for (const char* file : {"summary.json", "trajectory.csv", "steps.csv"}) {
      INFO(file);
      const std::string a = slurp(dir / "a" / file);
      CHECK_FALSE(a.empty());
      CHECK(a == slurp(dir / "b" / file));
    }
    CHECK(slurp(dir / "a" / "summary.json").find("wall_time") == std::string::npos);
  }
}

TEST_CASE("scene files set the divergence limits and cfm, bad values name their path",
          "[stress][divergence][cli]") {
  const auto dir = scratch_dir("diverge_json");
  const auto scene = [&](const std::string& world, const std::string& solver) {
    const auto path = dir / "scene.json";
    cbps::test::write_file(
        path,
        R"({"world": {"dt": 0.01)" + world + R"(}, "solver": {"method": "pgs")" + solver +
            R"(}, "bodies": [{"name": "ball", "mass": 2, "shape": {"type": "sphere", "radius": 0.1}}]})");
    return path.string();
  };
  // Free fall: v = 9.81 (k + 1) 0.01 m/s passes 1 m/s at step 10; steps 0..9 are kept.
  const auto r = run_cli("run " + scene(R"(, "divergence_speed": 1)", "") + " --steps 50 --out " +
                         (dir / "out").string());
  CHECK(r.code == 1);
  CHECK(r.err.find("step 10 ") != std::string::npos);
  CHECK(r.err.find("body 0 (ball)") != std::string::npos);
  const auto summary = nlohmann::json::parse(slurp(dir / "out" / "summary.json"));
  CHECK(summary["divergence"]["step"] == 10);
  CHECK(summary["divergence"]["body"] == 0);
  CHECK(summary["steps"] == 10);
  CHECK(summary["steps_requested"] == 50);
  const std::string steps = slurp(dir / "out" / "steps.csv");
  CHECK(std::count(steps.begin(), steps.end(), '\n') == 11);  // header + steps 0..9
  const std::string trajectory = slurp(dir / "out" / "trajectory.csv");
  CHECK(std::count(trajectory.begin(), trajectory.end(), '\n') == 12);  // header, t = 0..0.1

  const auto bad_cfm = run_cli("run " + scene("", R"(, "cfm": -1)") + " --steps 1");
  CHECK(bad_cfm.code == 2);
  CHECK(bad_cfm.err.find("/solver/cfm") != std::string::npos);
  const auto bad_limit = run_cli("run " + scene(R"(, "divergence_spin": 0)", "") + " --steps 1");
  CHECK(bad_limit.code == 2);
  CHECK(bad_limit.err.find("/world/divergence_spin") != std::string::npos);
  const auto ok = run_cli("run " + scene("", R"(, "cfm": 1e-6)") + " --steps 3 --json");
  REQUIRE(ok.code == 0);
  CHECK(nlohmann::json::parse(ok.out)["solver"]["cfm"] == 1e-6);
}

TEST_CASE("cbps runs its libraries on one thread unless --threads says otherwise",
          "[cli][threads]") {
  // The report reads each library's own getter (openblas_get_num_threads,
  // omp_get_max_threads), not what cbps asked for. A threaded BLAS left alone uses every core;
  // Debian's reference BLAS has no threads at all (then blas_kind is "single-threaded").
  const auto dir = scratch_dir("threads");
  const auto threads_of = [&](const std::string& option) {
    const auto r =
        run_cli("run chain --steps 2 --quiet " + option + " --out " + (dir / "out").string());
    INFO(r.err);
    REQUIRE(r.code == 0);
    return nlohmann::json::parse(slurp(dir / "out" / "summary.json")).at("threads");
  };
  const auto one = threads_of("");
  CHECK(one.at("requested") == 1);
  CHECK(one.at("blas_threads") == 1);
  CHECK(one.at("openmp_threads").get<int>() <= 1);  // 0: no OpenMP runtime loaded
  const auto two = threads_of("--threads 2");
  CHECK(two.at("requested") == 2);
  if (two.at("blas_kind") != "single-threaded") CHECK(two.at("blas_threads") == 2);
  if (two.at("openmp_threads").get<int>() > 0) CHECK(two.at("openmp_threads") == 2);
  // Under --no-timing the summary holds nothing of the machine.
  const auto r = run_cli("run chain --steps 2 --quiet --no-timing --out " + (dir / "out").string());
  REQUIRE(r.code == 0);
  CHECK_FALSE(nlohmann::json::parse(slurp(dir / "out" / "summary.json")).contains("threads"));
  CHECK(run_cli("run chain --steps 2 --threads -1").code == 2);
}

TEST_CASE("a one-process command started by mpirun -n 2 is refused on every rank, said once",
          "[cli][mpi]") {
  // mpirun tells each process its job's size and rank in the environment (Open MPI's names);
  // the real mpirun runs in tests/petsc/test_tao.py (bad-input) where Open MPI is installed.
  const auto dir = scratch_dir("mpi_refused");
  const std::string out = (dir / "out").string();
  ::setenv("OMPI_COMM_WORLD_SIZE", "2", 1);
  for (const char* rank : {"0", "1"}) {
    CAPTURE(rank);
    ::setenv("OMPI_COMM_WORLD_RANK", rank, 1);
    for (const std::string& args : {"run chain --steps 2 --out " + out,
                                    "matrices chain --out " + out,
                                    "converge chain --step 2 --solvers pgs --out " + out}) {
      CAPTURE(args);
      const auto r = run_cli(args);
      CHECK(r.code == 2);
      CHECK(r.out.empty());
      if (std::string(rank) == "0")
        CHECK(r.err.find("without mpirun") != std::string::npos);
      else
        CHECK(r.err.empty());  // the message once, from rank 0
      CHECK_FALSE(std::filesystem::exists(out));
    }
  }
  ::setenv("OMPI_COMM_WORLD_SIZE", "1", 1);  // a job of one process runs as without mpirun
  ::setenv("OMPI_COMM_WORLD_RANK", "0", 1);
  CHECK(run_cli("run chain --steps 2 --quiet --out " + out).code == 0);
  ::unsetenv("OMPI_COMM_WORLD_SIZE");
  ::unsetenv("OMPI_COMM_WORLD_RANK");
}

TEST_CASE("cbps run --solver direct says per step how the exact path reached its answer",
          "[cli][direct]") {
  // The base-8 pyramid (768 rows, the interior point's size) at rest: the first step has no
  // guess, so the interior point; every later step starts from the last step's lambda, which
  // either already solves it or is finished by the crossover from its partition.
  const auto dir = scratch_dir("routes");
  const auto out = dir / "out";
  const auto r = run_cli(
      "run pyramid --param base=8 --param push=original --steps 12 --solver direct --quiet --out " +
      out.string());
  INFO(r.err);
  REQUIRE(r.code == 0);
  std::ifstream steps(out / "steps.csv");
  std::string line;
  std::getline(steps, line);
  const std::string header = "t,rows,warm_rows,iterations,residual,max_constraint_error,energy,";
  REQUIRE(line == header + "direct_route,wall_time_s,solve_time_s");
  std::map<std::string, long> counted;
  for (long k = 0; std::getline(steps, line); ++k) {
    std::vector<std::string> fields;
    std::stringstream row(line);
    for (std::string f; std::getline(row, f, ',');) fields.push_back(f);
    REQUIRE(fields.size() == 10);
    const std::string& route = fields[7];
    CAPTURE(k, line);
    if (k == 0)
      CHECK(route == "interior");
    else
      CHECK((route == "warm" || route == "guess"));
    CHECK(std::stod(fields[9]) >= 0.0);  // solve_time_s, s
    ++counted[route];
  }
  const auto summary = nlohmann::json::parse(slurp(out / "summary.json"));
  CHECK(summary["max_residual"].get<double>() <= 1e-9);
  CHECK(summary["direct_routes"].get<std::map<std::string, long>>() == counted);
  CHECK(!summary.contains("direct_routes_position"));  // one system per step (original push)
  CHECK(counted["warm"] > 0);
}

TEST_CASE("cbps run --integrator turns the bodies as named, and the summary says which",
          "[cli][integrator]") {
  const std::string box = std::string(CBPS_SOURCE_DIR) + "/scenes/spinning-box.json";
  const auto summary = [&](const std::string& args) {
    const auto r = run_cli("run " + args + " --quiet --json");
    INFO(r.err);
    REQUIRE(r.code == 0);
    return nlohmann::json::parse(r.out);
  };
  // The tumbling box of scenes/spinning-box.json, 20 s: the paper's turn gains energy (its
  // description says about a third), the midpoint turn keeps it to round-off, Bullet's
  // gyroscopic step loses some.
  const auto paper = summary(box);
  CHECK(paper.at("integrator") == "paper");
  const auto relative = [](const nlohmann::json& s) {
    const double e0 = s.at("energy_initial").get<double>();
    return (s.at("energy_final").get<double>() - e0) / e0;
  };
  CHECK(relative(paper) > 0.2);
  const auto midpoint = summary(box + " --integrator midpoint");
  CHECK(midpoint.at("integrator") == "midpoint");
  CHECK(std::abs(relative(midpoint)) <= 1e-10);
  const auto gyroscopic = summary(box + " --integrator gyroscopic");
  CHECK(gyroscopic.at("integrator") == "gyroscopic");
  CHECK(relative(gyroscopic) < 0.0);
  // A contact scene under each: a resting stack hardly turns, so each integrator's run ends
  // as the paper's does, its deepest penetration within 1 mm of the paper's.
  const auto stack_paper = summary("stack --steps 120");
  for (const char* name : {"gyroscopic", "midpoint"}) {
    CAPTURE(name);
    const auto stack = summary(std::string("stack --steps 120 --integrator ") + name);
    CHECK(stack.at("status") == "completed");
    CHECK(stack.at("integrator") == name);
    CHECK(std::abs(stack.at("max_penetration").get<double>() -
                   stack_paper.at("max_penetration").get<double>()) <= 1e-3);
  }
  CHECK(run_cli("run " + box + " --steps 1 --integrator verlet").code == 2);
}

TEST_CASE("cbps run --scheme substeps each step as named, from the command line and scene files",
          "[cli][scheme]") {
  const auto summary = [&](const std::string& args) {
    const auto r = run_cli("run " + args + " --quiet --json");
    INFO(args << ": " << r.err);
    REQUIRE(r.code == 0);
    return nlohmann::json::parse(r.out);
  };
  // The issue's two commands (60 steps of the 10-box stack): the summary names the scheme and its
  // substeps, every stage after collision detection runs once a substep, and the sweeps are
  // those asked: one relax sweep a substep under soft-step (its push system's apart), at most 5
  // under tgs.
  const auto soft = summary("stack --steps 60 --scheme soft-step --substeps 4 --iterations 1");
  CHECK(soft.at("scheme").at("name") == "soft-step");
  CHECK(soft.at("scheme").at("substeps") == 4);
  CHECK(soft.at("scheme").at("h").get<double>() == Approx(1.0 / 240.0).epsilon(1e-15));
  CHECK(soft.at("stages").at(0) == "collision (4)");
  CHECK(soft.at("stages").at(1).get<std::string>().rfind("soft-step substep (x4): ", 0) == 0);
  CHECK(soft.at("iterations_total").get<long>() <= 60 * 4);
  CHECK(soft.at("max_penetration").get<double>() < 0.01);
  const auto tgs = summary("stack --steps 60 --scheme tgs --substeps 4 --iterations 5");
  CHECK(tgs.at("scheme").at("name") == "tgs");
  CHECK(tgs.at("iterations_total").get<long>() > 60 * 4);
  CHECK(tgs.at("iterations_total").get<long>() <= 60 * 4 * 5);
  CHECK(summary("stack --steps 60 --scheme xpbd --iterations 1").at("scheme").at("substeps") == 4);
  // From a scene file: the scheme it names, and --scheme paper over it.
  const auto dir = scratch_dir("scheme_scene");
  auto scene =
      nlohmann::json::parse(slurp(std::string(CBPS_SOURCE_DIR) + "/scenes/box-on-plane.json"));
  scene["world"]["scheme"] = "soft-step";
  scene["world"]["substeps"] = 3;
  cbps::test::write_file(dir / "soft.json", scene.dump());
  const std::string file = (dir / "soft.json").string();
  CHECK(summary(file + " --steps 30").at("scheme").at("substeps") == 3);
  CHECK(summary(file + " --steps 30 --scheme paper").at("scheme").at("substeps") == 1);
  // --check solves every substep's system again with the direct path.
  const auto checked = summary("stack --steps 10 --scheme tgs --substeps 4 --iterations 5 --check");
  CHECK(checked.at("cross_check").at("steps_checked") == 40);
  CHECK(checked.at("cross_check").at("direct_unverified") == 0);
  // The soft schemes: the relax (rigid) and XPBD's compliant system, (A + alpha/h²) lambda = b.
  for (const char* scheme : {"soft-step --iterations 1", "xpbd --compliance 1e-4 --iterations 1"}) {
    CAPTURE(scheme);
    const auto soft_checked =
        summary(std::string("stack --steps 10 --substeps 4 --check --scheme ") + scheme);
    CHECK(soft_checked.at("cross_check").at("steps_checked") == 40);
    CHECK(soft_checked.at("cross_check").at("direct_unverified") == 0);
  }
  // Substeps need a scheme that substeps; an unknown scheme is refused.
  const auto paper = run_cli("run stack --steps 1 --substeps 4");
  CHECK(paper.code == 2);
  CHECK(paper.err.find("--substeps 4: needs a scheme that substeps (tgs, soft-step, xpbd)") !=
        std::string::npos);
  CHECK(run_cli("run stack --steps 1 --scheme verlet").code == 2);
}
