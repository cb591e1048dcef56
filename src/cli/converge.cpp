// cbps converge SCENE|PROBLEM --solvers LIST --out DIR: error against iterations and run time.
//
// The study itself is studies/convergence.hpp; this reads the options, runs each spec (tao:TYPE,
// in a build with PETSc, docs/distributed.md, runs TAO in this process from lambda = 0; its
// monitor hands each TAO iteration here as a "sweep", timed since solve_tao was called,
// distributing A included, less the monitor's own time), writes and prints.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>

#include "cbps/base/error.hpp"
#include "cbps/io/fclib_file.hpp"
#include "cbps/io/stored_problem.hpp"
#include "cbps/solvers/exact/direct.hpp"
#include "cbps/solvers/peers/peers.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/studies/convergence.hpp"
#include "cbps/studies/solver_spec.hpp"
#include "common.hpp"
#include "tao_solvers.hpp"

namespace cbps::cli {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

const char* const kDefaultSolvers = "pgs,psor:1.3,sgs,jacobi:0.7,matrix-free,direct";
const char* const kDefaultConeSolvers = "nsgs,nsgs:local=3,direct";

struct ConvergeOptions {
  SceneOptions scene;
  StepOptions step;
  std::string solvers;         ///< not given: kDefaultSolvers, or kDefaultConeSolvers on cones
  bool solvers_given = false;  ///< --solvers was given (an empty list is refused)
  std::string cone;            ///< --cone: an FCLIB file's law
  long at_step = 0;
  int iterations = kStudyIterations;
  int record_every = kRecordLog;                 ///< --record-every: K, or log (kRecordLog)
  double tolerance = SolveSettings{}.tolerance;  ///< N, the one default (solver.hpp)
  double time_limit = 10.0;
  std::string out;
  bool json = false;
  bool quiet = false;
  bool plot = true;
};

bool is_problem(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) return true;
  return fs::path(path).extension() == ".dat" || is_hdf5_file(path);  // Siconos, FCLIB
}

ConvergenceSystem system_of_scene(const ConvergeOptions& o) {
  Scene scene = load_scene(o.scene);
  apply_step_options(scene, o.step);
  return convergence_system(std::move(scene), o.scene.scene, o.at_step, o.quiet);
}

/// Runs the plot script on the CSV; true if it wrote its files.
bool plot(const std::string& csv, const std::string& prefix, const std::string& title) {
  return run_python_script("scripts/plot_convergence.py", {csv, prefix, "--title", title});
}

void print_table(const ConvergenceSystem& s,
                 const SolverSummary& reference,
                 const nlohmann::json& summary) {
  std::printf("%s: %ld rows, lambda %s; direct reference residual %.3g N\n",
              s.name.c_str(),
              static_cast<long>(s.stored.rows()),
              s.lambda_unique ? "unique (A definite)" : "not unique (A singular): v2 compared",
              reference.residual);
  std::printf("%-24s %10s %11s %11s  %-18s %-18s %-18s\n",
              "solver",
              "sweeps",
              "time (s)",
              "residual",
              "to 1e-3 N",
              "to 1e-6 N",
              "to 1e-10 N");
  for (const nlohmann::json& j : summary["solvers"]) {
    std::printf("%-24s %10d %11.3g %11.3g ",
                j["solver"].get<std::string>().c_str(),
                j["iterations"].get<int>(),
                j["time_s"].get<double>(),
                number_of_json(j["residual"]));
    for (const double target : kConvergenceMilestones) {
      const nlohmann::json& at = j["reached"][milestone_key(target)];
      char cell[64] = "-";
      if (!at.is_null())
        std::snprintf(cell,
                      sizeof cell,
                      "%d / %.3g s",
                      at["iterations"].get<int>(),
                      at["time_s"].get<double>());
      std::printf(" %-18s", cell);
    }
    std::printf("\n");
  }
}

ConvergenceLimits limits_of(const ConvergeOptions& o) {
  ConvergenceLimits limits;
  limits.iterations = o.iterations;
  limits.record_every = o.record_every;
  limits.tolerance = o.tolerance;
  limits.time_limit = o.time_limit;
  SolverSettings given;  // --seed, checked as a scene's /solver/seed (default 0)
  apply_solver_options(given, o.step);
  limits.seed = given.seed;
  if (!o.quiet) {
    limits.progress = [](const SolverSpec& spec, int k, double time_s, double residual) {
      if (k == 0) return;
      std::fprintf(stderr,
                   "converge: %s: %d sweeps, %.2f s, residual %.3g N\n",
                   spec.text.c_str(),
                   k,
                   time_s,
                   residual);
    };
  }
  return limits;
}

int converge_command(const ConvergeOptions& o) {
  // A given list first: a bad name is reported before the data are read.
  std::vector<SolverSpec> specs;
  if (o.solvers_given) {
    specs = parse_cli_solver_list(o.solvers, "--solvers");  // '' is an empty entry: refused
    // A spec given twice draws the same curve twice (a warm factor makes specs differ here:
    // converge starts each from the previous step's lambda times it).
    for (std::size_t i = 0; i < specs.size(); ++i)
      for (std::size_t j = 0; j < i; ++j)
        if (specs[i].text == specs[j].text)
          throw InputError("--solvers '" + o.solvers + "': '" + specs[i].text +
                           "' is given twice and would draw the same curve; give it once");
  }
  const bool problem = is_problem(o.scene.scene);
  if (!problem && !o.cone.empty())
    throw InputError("--cone " + o.cone +
                     ": the law of a stored problem's friction cones (an FCLIB file, a folder "
                     "with cones.json); a scene sets its own with --param cone=LAW, not "
                     "--cone (" +
                     o.scene.scene + ")");
  if (problem && !o.scene.params.empty())
    throw InputError("--param: parameters apply to built-in scenes, not to the problem " +
                     o.scene.scene);
  if (problem && world_options_given(o.step))
    throw InputError(
        "--dt, --cfm, --beta, --push, --integrator, --scheme and its options: they apply to "
        "scenes, not to the problem " +
        o.scene.scene + " (its cfm.txt gives its cfm)");
  ConvergenceSystem s = problem ? convergence_system(o.scene.scene) : system_of_scene(o);
  set_cone_law(s.stored, o.cone, o.scene.scene);
  if (!o.solvers_given)
    specs = parse_cli_solver_list(s.stored.cones.empty() ? kDefaultSolvers : kDefaultConeSolvers,
                                  "--solvers");
  const TaoInProcess tao(specs, "converge --solvers");  // PETSc once, for every tao spec
  std::unique_ptr<OutputDir> dir;
  if (!o.out.empty()) dir = std::make_unique<OutputDir>(o.out);
  if (!o.quiet)
    std::fprintf(stderr,
                 "converge: %s: %ld rows, reference by the direct path\n",
                 s.name.c_str(),
                 static_cast<long>(s.stored.rows()));
  const SolverSummary reference = solve_reference(s);

  const ConvergenceLimits limits = limits_of(o);
  std::vector<ConvergenceRun> runs;
  for (const SolverSpec& spec : specs) {
    runs.push_back(run_spec(s, spec, limits, tao.converge()));
    if (!o.quiet) {
      const ConvergenceSample& last = runs.back().samples.back();
      std::fprintf(stderr,
                   "converge: %s: %s after %s, %.3g s, residual %.3g N\n",
                   spec.text.c_str(),
                   runs.back().stopped.c_str(),
                   count_text(last.iteration, "sweep").c_str(),
                   last.time_s,
                   last.residual);
    }
  }
  // A step its guess already solves shows nothing: say so, on stderr and in the summary.
  const std::string warning = solved_by_guess_warning(s, runs, o.tolerance);
  if (!warning.empty()) std::fprintf(stderr, "cbps: warning: converge: %s\n", warning.c_str());
  const nlohmann::json summary = convergence_summary(s, reference, runs, limits, warning);
  if (dir) {
    write_text(dir->file("convergence.csv"), convergence_csv(runs));
    write_text(dir->file("summary.json"), summary.dump(2) + "\n");
    if (o.plot) {
      const std::string title = s.name + " (" + std::to_string(s.stored.rows()) + " rows)";
      if (!plot(dir->file("convergence.csv"), dir->file("convergence"), title))
        throw ComputationError("converge: the plot script failed (" +
                               std::string(CBPS_PLOT_PYTHON) +
                               " scripts/plot_convergence.py); "
                               "nothing written (--no-plot skips the plot)");
    }
    dir->commit();
  }
  if (o.json) {
    std::printf("%s\n", summary.dump(2).c_str());
    return 0;
  }
  print_table(s, reference, summary);
  if (!o.out.empty()) std::printf("wrote %s\n", o.out.c_str());
  return 0;
}

}  // namespace

void register_converge(CLI::App& app, Action& run) {
  auto* cmd = app.add_subcommand(
      "converge",
      "error against iterations and run time for each solver on one system (a scene's step or "
      "a stored problem): convergence.csv, summary.json, convergence.png/.svg");
  auto o = std::make_shared<ConvergeOptions>();
  add_scene_options(cmd,
                    o->scene,
                    "built-in scene, JSON scene file, `cbps matrices` folder or Siconos .dat file");
  auto* solvers = cmd->add_option(
      "--solvers",
      o->solvers,
      "comma-separated solver specs (the solvers listed below), e.g. "
      "pgs,psor:1.3,sgs,jacobi:0.7,pgs:order=random,block-pgs,matrix-free,"
      "pgs-nesterov,apgd,direct,tao:bqpip (tao:TYPE only in a build with PETSc; "
      "default: " +
          std::string(kDefaultSolvers) + "; on friction cones " + kDefaultConeSolvers + ")");
  add_cone_option(cmd, o->cone);
  cmd->footer(solver_spec_help() + tao_spec_help());
  cmd->add_option("--step",
                  o->at_step,
                  "scenes: study the system of this step (0: the first; later steps start "
                  "from the previous step's lambda unless a spec says warm=off)")
      ->transform(step_index());
  add_world_options(cmd, o->step);
  cmd->add_option("--iterations",
                  o->iterations,
                  "max sweeps per solver; TAO's iterations for tao:TYPE (default " +
                      std::to_string(kStudyIterations) + ")")
      ->check(positive());
  cmd->add_option("--tolerance",
                  o->tolerance,
                  "stop at this residual, N (default " + number_text(o->tolerance) + ")")
      ->check(non_negative());
  cmd->add_option_function<std::string>(
         "--record-every",
         [o](const std::string& text) {
           if (text == "log") {
             o->record_every = kRecordLog;
             return;
           }
           int k = 0;
           std::size_t used = 0;
           try {
             k = std::stoi(text, &used);
           } catch (const std::exception&) {
             used = 0;
           }
           if (used != text.size() || k < 1)
             throw CLI::ValidationError(
                 "--record-every", "expected a whole number >= 1 or 'log', found '" + text + "'");
           o->record_every = k;
         },
         "which sweeps convergence.csv keeps: K (every K-th) or log (every sweep to 100, then "
         "100 a decade: 400 rows for 100,000 sweeps); the guess and the last sweep always, and "
         "the summary's milestones see every sweep (default log)")
      ->type_name("K|log");
  cmd->add_option(
         "--time-limit",
         o->time_limit,
         "max time per solver, s (default 10): a sweeping method stops after the sweep that "
         "passes it, a Siconos peer's child process is killed at it")
      ->check(positive());
  add_solver_options(cmd, o->step, {"seed"});
  add_out_option(cmd, o->out, "convergence.csv, summary.json and the plot");
  add_json_flag(cmd, o->json, "the summary");
  add_quiet_flag(cmd, o->quiet);
  cmd->add_flag_callback(
      "--no-plot", [o] { o->plot = false; }, "write no convergence.png/.svg");
  cmd->callback([&run, o, solvers] {
    o->solvers_given = solvers->count() > 0;
    run = [o] { return converge_command(*o); };
  });
}

}  // namespace cbps::cli
