// cbps stress: the stability catalogue (stiff and extreme cases × solvers) as one table.
#include "cbps/studies/stress.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <regex>
#include <sstream>

#include "cbps/base/error.hpp"
#include "cbps/studies/solver_spec.hpp"
#include "common.hpp"

namespace cbps::cli {

namespace {

struct StressOptions {
  std::string cases;    ///< regular expression over case names
  std::string solvers;  ///< comma-separated solver specs to keep
  std::string out;
  double budget = 90.0;
  std::string integrator = "paper";  ///< integrator_names()
  bool json = false;
  bool list = false;
  bool quiet = false;
};

/// The cases --case selects (all without it).
std::vector<StressCase> selected_cases(const StressOptions& o) {
  std::vector<StressCase> cases = stress_catalogue();
  if (!o.cases.empty()) {
    std::regex pattern;
    try {
      pattern = std::regex(o.cases);
    } catch (const std::regex_error& e) {
      throw InputError("--case '" + o.cases + "': not a regular expression (" + e.what() + ")");
    }
    std::erase_if(cases, [&](const StressCase& c) { return !std::regex_search(c.name, pattern); });
    if (cases.empty()) throw InputError("--case '" + o.cases + "': matches no case (see --list)");
  }
  return cases;
}

/// --list: each case, what stable means, its solvers.
void print_cases(const std::vector<StressCase>& cases) {
  for (const StressCase& c : cases) {
    std::printf("%s [%s], %ld steps: %s\n  stable means: %s\n  solvers:",
                c.name.c_str(),
                c.group.c_str(),
                c.steps,
                c.description.c_str(),
                c.stable_means.c_str());
    for (const std::string& s : c.solvers) std::printf(" %s", s.c_str());
    for (const auto& [s, why] : c.skipped) std::printf(" (%s skipped: %s)", s.c_str(), why.c_str());
    std::printf("\n");
  }
}

int stress_command(const StressOptions& o) {
  const std::vector<StressCase> cases = selected_cases(o);
  std::vector<std::string> keep;
  if (!o.solvers.empty()) {
    for (const SolverSpec& spec : parse_solver_list(o.solvers, "--solver"))
      keep.push_back(spec.text);
  }
  const auto kept = [&](const std::string& solver) {
    return keep.empty() || solver == "-" ||
           std::find(keep.begin(), keep.end(), solver) != keep.end();
  };
  if (o.list) {
    print_cases(cases);
    return 0;
  }

  std::unique_ptr<OutputDir> dir;
  if (!o.out.empty()) dir = std::make_unique<OutputDir>(o.out);
  const auto start = std::chrono::steady_clock::now();
  auto last = start;
  const auto progress = [&](std::size_t done,
                            std::size_t total,
                            const StressCase& c,
                            const std::string& solver,
                            long step,
                            long steps,
                            const StressResult* r) {
    const auto now = std::chrono::steady_clock::now();
    if (o.quiet || (r == nullptr && now - last < std::chrono::seconds(5))) return;
    last = now;
    char what[160];
    if (r == nullptr)
      std::snprintf(what, sizeof what, "step %ld/%ld", step, steps);
    else
      std::snprintf(what,
                    sizeof what,
                    "%s, %.2f s (%.0f s in all)",
                    r->status.c_str(),
                    r->wall_time_s,
                    std::chrono::duration<double>(now - start).count());
    std::fprintf(stderr,
                 "cbps stress: [%zu/%zu] %s %s: %s\n",
                 done,
                 total,
                 c.name.c_str(),
                 solver.c_str(),
                 what);
  };
  const std::vector<StressResult> results = run_stress_catalogue(
      cases, kept, o.budget, progress, integrator_named(o.integrator).value_or(Integrator::Paper));
  const nlohmann::json report = stress_report_json(
      cases,
      results,
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  if (dir) {
    write_text(dir->file("stress.md"), stress_markdown(cases, results));
    write_text(dir->file("summary.json"), report.dump(2) + "\n");
    dir->commit();
  }
  if (o.json) {
    std::cout << report.dump(2) << "\n";
  } else {
    const nlohmann::json& counts = report["counts"];
    std::cout << stress_table(results);
    std::printf("%d stable, %d unstable, %d diverged, %d skipped or out of budget; %.0f s\n",
                counts["stable"].get<int>(),
                counts["unstable"].get<int>(),
                counts["diverged"].get<int>(),
                counts["other"].get<int>(),
                report["wall_time_s"].get<double>());
    if (dir) std::printf("wrote %s\n", o.out.c_str());
  }
  return 0;
}

}  // namespace

void register_stress(CLI::App& app, Action& run) {
  auto* cmd = app.add_subcommand(
      "stress",
      "run the stability catalogue (stiff and extreme cases x solvers) and print one table: "
      "stable or not, max constraint error, max penetration, energy change, final residual, "
      "condition of A, wall time");
  auto o = std::make_shared<StressOptions>();
  cmd->add_option("--case", o->cases, "run only the cases whose name matches this regex");
  cmd->add_option("--solver",
                  o->solvers,
                  "comma-separated solver specs to keep (of each case's own list), e.g. "
                  "pgs,direct");
  cmd->add_option("--budget", o->budget, "wall-time budget of one run, s (default 90)")
      ->check(positive());
  cmd->add_option("--integrator",
                  o->integrator,
                  "how every case turns its bodies: paper | gyroscopic | midpoint "
                  "(docs/integrators.md; default paper)")
      ->check(CLI::IsMember(integrator_names()));
  add_out_option(cmd, o->out, "summary.json (all numbers) and stress.md (the table)");
  add_json_flag(cmd, o->json, "the results instead of the table");
  cmd->add_flag("--list", o->list, "list the cases, what stable means for each, and exit");
  add_quiet_flag(cmd, o->quiet);
  cmd->callback([&run, o] { run = [o] { return stress_command(*o); }; });
}

}  // namespace cbps::cli
