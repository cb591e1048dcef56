// cbps profile LIBRARY --solvers LIST --out DIR: performance profiles of solvers over a problem
// library. The study is studies/profile.hpp; here the options, tao:TYPE (a build with PETSc,
// docs/distributed.md; iterative here: its TAO iterations are its "sweeps", one costing far more
// than a sweep, handed over by solve_tao's monitor; time from the call of solve_tao,
// distributing A included), progress, the files and the table.
#include "cbps/studies/profile.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

#include "cbps/base/error.hpp"
#include "cbps/solvers/peers/peers.hpp"
#include "cbps/studies/solver_spec.hpp"
#include "common.hpp"
#include "tao_solvers.hpp"

namespace cbps::cli {

namespace {

using Clock = std::chrono::steady_clock;

struct ProfileOptions {
  std::string library;
  std::string solvers = "pgs,psor:1.3,sgs,pgs-nesterov,apgd,nncg,pgs-sm,admm,rbgs,block-pgs,direct";
  std::string out;
  bool quick = false;
  int budget_iterations = kStudyIterations;
  double time_limit = 1.0;
  bool json = false;
  bool quiet = false;
  bool plot = true;
};

int profile_command(const ProfileOptions& o) {
  const auto started = Clock::now();
  const ProfileLimits limits{o.budget_iterations, o.time_limit};
  const std::vector<SolverSpec> specs = parse_cli_solver_list(o.solvers, "--solvers");
  refuse_duplicates(specs, o.solvers);
  const TaoInProcess tao(specs, "profile --solvers");  // PETSc once, for every tao spec
  const std::vector<ProfileEntry> entries = read_library(o.library, o.quick);
  // Every problem is read before any solver runs, so a bad file is reported at once (exit 2).
  std::vector<ProfileProblem> problems;
  for (const ProfileEntry& e : entries) problems.push_back(load_profile_problem(e));
  std::unique_ptr<OutputDir> dir;
  if (!o.out.empty()) dir = std::make_unique<OutputDir>(o.out);

  std::vector<std::vector<ProfileMeasurement>> runs;  // [problem][solver]
  for (std::size_t p = 0; p < problems.size(); ++p) {
    runs.emplace_back();
    for (const SolverSpec& spec : specs) {
      runs.back().push_back(
          best_of_runs([&] { return profile_spec(problems[p], spec, limits, tao.profile()); }));
      const ProfileMeasurement& m = runs.back().back();
      if (!o.quiet)
        std::fprintf(stderr,
                     "profile: problem %zu of %zu, %s (%ld rows): %s: %s, %ld iterations, %.3g s, "
                     "relative residual %.3g\n",
                     p + 1,
                     problems.size(),
                     entries[p].name.c_str(),
                     static_cast<long>(problems[p].stored.rows()),
                     spec.text.c_str(),
                     m.status.c_str(),
                     m.iterations,
                     m.time_s,
                     m.residual);
    }
  }

  std::vector<Profile> profiles;  // per tolerance: time, then sweeps
  for (std::size_t t = 0; t < kProfileTolerancesCount; ++t)
    for (const bool sweeps : {false, true})
      profiles.push_back(make_profile(kProfileTolerances[t], t, sweeps, specs, runs));
  const double wall_time_s = std::chrono::duration<double>(Clock::now() - started).count();

  const ProfileReport report = profile_report(
      o.library, o.quick, limits, wall_time_s, entries, problems, specs, runs, profiles);
  const nlohmann::json& j = report.json;
  const std::string summary = profile_summary_text(entries, specs, profiles, limits, wall_time_s);

  if (dir) {
    write_text(dir->file("profile.json"), j.dump(2) + "\n");
    write_text(dir->file("profile.csv"), report.csv);
    write_text(dir->file("summary.txt"), summary);
    if (o.plot && !run_python_script("scripts/plot_profile.py",
                                     {dir->file("profile.json"), dir->file("profile")}))
      throw ComputationError("profile: the plot script failed (" + std::string(CBPS_PLOT_PYTHON) +
                             " scripts/plot_profile.py); nothing written (--no-plot skips the "
                             "plot)");
    dir->commit();
  }
  if (o.json) {
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
  }
  std::printf("%s", summary.c_str());
  if (!o.out.empty()) std::printf("wrote %s\n", o.out.c_str());
  return 0;
}

}  // namespace

void register_profile(CLI::App& app, Action& run) {
  auto* cmd = app.add_subcommand(
      "profile",
      "performance profiles (Dolan & More 2002) of solvers over a problem library or a folder of "
      "problem files: "
      "profile.json, profile.csv, summary.txt, profile.png/.svg");
  auto o = std::make_shared<ProfileOptions>();
  cmd->add_option("LIBRARY",
                  o->library,
                  "a problem library: the folder scripts/make_problem_library.py wrote (or its "
                  "library.json); or any folder of problem files without library.json (FCLIB "
                  ".hdf5, Siconos .dat, `cbps matrices` folders), whose answers are not known")
      ->required();
  cmd->add_option(
      "--solvers",
      o->solvers,
      "comma-separated solver specs (the solvers listed below; tao:TYPE only in a build with "
      "PETSc), each solver once: a spec listed twice, or two specs for the same method and "
      "settings (pgs and psor:1; warm factors do not count, every solve starts from lambda = 0), "
      "is refused (default: " +
          o->solvers + ")");
  cmd->footer(solver_spec_help() + tao_spec_help());
  cmd->add_flag("--quick", o->quick, "only the problems the library marks quick");
  cmd->add_option("--budget-iterations",
                  o->budget_iterations,
                  "max sweeps per problem and solver; TAO's iterations for tao:TYPE (default " +
                      std::to_string(kStudyIterations) + ")")
      ->check(positive());
  cmd->add_option("--time-limit",
                  o->time_limit,
                  "max time per problem and solver, s (default 1): a sweeping method stops after "
                  "the sweep that passes it, a Siconos peer's child process is killed at it")
      ->check(positive());
  cmd->add_option(
      "--out", o->out, "write profile.json, profile.csv, summary.txt and the plot here");
  add_json_flag(cmd, o->json, "profile.json instead of the table");
  add_quiet_flag(cmd, o->quiet);
  cmd->add_flag_callback(
      "--no-plot", [o] { o->plot = false; }, "write no profile.png/.svg");
  cmd->callback([&run, o] { run = [o] { return profile_command(*o); }; });
}

}  // namespace cbps::cli
