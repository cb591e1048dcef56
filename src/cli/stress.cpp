// cbps stress: the stability catalogue (stiff and extreme cases × solvers) as one table.
#include "cbps/studies/stress.hpp"

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
  bool json = false;
  bool list = false;
  bool quiet = false;
};

std::string sci(double x) {
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2g", x);
  return buf;
}

nlohmann::json result_json(const StressResult& r) {
  nlohmann::json j;
  j["case"] = r.case_name;
  j["solver"] = r.solver;
  j["status"] = r.status;
  if (!r.note.empty()) j["note"] = r.note;
  if (r.status == "skipped") return j;
  j["steps"] = r.steps;
  j["steps_done"] = r.steps_done;
  j["max_rows"] = r.max_rows;
  j["max_constraint_error_m"] = number_json(r.max_constraint_error);
  j["max_penetration_m"] = number_json(r.max_penetration);
  j["energy_initial_J"] = number_json(r.energy_initial);
  j["energy_final_J"] = number_json(r.energy_final);
  j["energy_change_J"] = number_json(r.energy_final - r.energy_initial);
  j["final_residual_N"] = number_json(r.final_residual);
  j["max_residual_N"] = number_json(r.max_residual);
  j["condition"] = {{"value", number_json(r.condition.condition)},
                    {"lambda_max", number_json(r.condition.lambda_max)},
                    {"lambda_min", number_json(r.condition.lambda_min)},
                    {"range_condition", number_json(r.condition.range_condition)},
                    {"nullity", r.condition.nullity},
                    {"exact", r.condition.exact},
                    {"method", r.condition.method}};
  if (r.cfm > 0.0) {
    j["regularization"] = {{"cfm", r.cfm},
                           {"max_acceleration_error", number_json(r.cfm_acceleration_error)}};
  }
  j["wall_time_s"] = r.wall_time_s;
  j["stable"] = r.status == "stable";
  j["measure"] = r.verdict.measure;
  nlohmann::json extra = nlohmann::json::object();
  for (const auto& [name, value] : r.verdict.extra) extra[name] = number_json(value);
  j["measured"] = extra;
  return j;
}

/// A divergence message without its "step N (t = …), system:" head (the table shows the step).
std::string short_divergence(const std::string& message) {
  const auto colon = message.find("): ");
  return colon == std::string::npos ? message : "guard: " + message.substr(colon + 3);
}

/// One Markdown table row per run; the same text goes to stdout and stress.md.
std::string table(const std::vector<StressResult>& results) {
  const std::vector<std::string> header = {"case",
                                           "solver",
                                           "stable",
                                           "max |c| m",
                                           "max pen. m",
                                           "ΔE J",
                                           "residual N",
                                           "cond(A)",
                                           "wall s",
                                           "judged on"};
  std::vector<std::vector<std::string>> rows;
  for (const StressResult& r : results) {
    if (r.status == "skipped") {
      rows.push_back({r.case_name, r.solver, "skipped", "", "", "", "", "", "", r.note});
      continue;
    }
    std::string stable = r.status == "stable" ? "yes" : r.status == "unstable" ? "NO" : r.status;
    if (r.status == "diverged" || r.status == "budget")
      stable += " @" + std::to_string(r.steps_done);
    std::string cond = sci(r.condition.condition);
    if (!r.condition.exact) cond += "~";
    if (r.condition.nullity > 0) cond += " (null " + std::to_string(r.condition.nullity) + ")";
    rows.push_back({r.case_name,
                    r.solver,
                    stable,
                    sci(r.max_constraint_error),
                    sci(r.max_penetration),
                    sci(r.energy_final - r.energy_initial),
                    sci(r.final_residual),
                    cond,
                    sci(r.wall_time_s),
                    r.status == "diverged" ? short_divergence(r.note) : r.verdict.measure});
  }
  std::ostringstream out;
  const auto line = [&](const std::vector<std::string>& cells) {
    out << "|";
    for (const std::string& cell : cells) {
      out << " ";
      for (const char ch : cell) {
        if (ch == '|') out << '\\';  // a Markdown table cell keeps its |c| and |ΔL|
        out << ch;
      }
      out << " |";
    }
    out << "\n";
  };
  line(header);
  out << "|";
  for (std::size_t k = 0; k < header.size(); ++k) out << (k >= 3 && k <= 8 ? "---:|" : "---|");
  out << "\n";
  for (const auto& row : rows) line(row);
  return out.str();
}

int stress_command(const StressOptions& o) {
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
    for (const StressCase& c : cases) {
      std::printf("%s [%s], %ld steps: %s\n  stable means: %s\n  solvers:",
                  c.name.c_str(),
                  c.group.c_str(),
                  c.steps,
                  c.description.c_str(),
                  c.stable_means.c_str());
      for (const std::string& s : c.solvers) std::printf(" %s", s.c_str());
      for (const auto& [s, why] : c.skipped)
        std::printf(" (%s skipped: %s)", s.c_str(), why.c_str());
      std::printf("\n");
    }
    return 0;
  }

  std::unique_ptr<OutputDir> dir;
  if (!o.out.empty()) dir = std::make_unique<OutputDir>(o.out);

  std::size_t total = 0;
  for (const StressCase& c : cases)
    total += static_cast<std::size_t>(std::count_if(c.solvers.begin(), c.solvers.end(), kept));
  std::vector<StressResult> results;
  const auto start = std::chrono::steady_clock::now();
  std::size_t done = 0;
  for (const StressCase& c : cases) {
    for (const std::string& solver : c.solvers) {
      if (!kept(solver)) continue;
      ++done;
      auto last = std::chrono::steady_clock::now();
      const auto progress = [&](long step, long steps) {
        const auto now = std::chrono::steady_clock::now();
        if (o.quiet || now - last < std::chrono::seconds(5)) return;
        last = now;
        std::fprintf(stderr,
                     "cbps stress: [%zu/%zu] %s %s: step %ld/%ld\n",
                     done,
                     total,
                     c.name.c_str(),
                     solver.c_str(),
                     step,
                     steps);
      };
      StressResult r = run_stress(c, solver, o.budget, progress);
      if (!o.quiet) {
        std::fprintf(
            stderr,
            "cbps stress: [%zu/%zu] %s %s: %s, %.2f s (%.0f s in all)\n",
            done,
            total,
            c.name.c_str(),
            solver.c_str(),
            r.status.c_str(),
            r.wall_time_s,
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      }
      results.push_back(std::move(r));
    }
    for (const auto& [solver, why] : c.skipped) {
      if (!kept(solver)) continue;
      StressResult r;
      r.case_name = c.name;
      r.solver = solver;
      r.status = "skipped";
      r.note = why;
      results.push_back(std::move(r));
    }
  }

  nlohmann::json report;
  report["cases"] = nlohmann::json::array();
  for (const StressCase& c : cases) {
    report["cases"].push_back({{"name", c.name},
                               {"group", c.group},
                               {"description", c.description},
                               {"stable_means", c.stable_means},
                               {"steps", c.steps}});
  }
  report["results"] = nlohmann::json::array();
  int stable = 0, unstable = 0, diverged = 0, other = 0;
  for (const StressResult& r : results) {
    report["results"].push_back(result_json(r));
    if (r.status == "stable")
      ++stable;
    else if (r.status == "unstable")
      ++unstable;
    else if (r.status == "diverged")
      ++diverged;
    else
      ++other;
  }
  report["counts"] = {
      {"stable", stable}, {"unstable", unstable}, {"diverged", diverged}, {"other", other}};
  report["wall_time_s"] =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  const std::string text = table(results);
  if (dir) {
    std::ostringstream md;
    md << "# cbps stress\n\n" << text << "\n## What stable means\n\n";
    for (const StressCase& c : cases)
      md << "- **" << c.name << "** (" << c.description << "): " << c.stable_means << "\n";
    write_text(dir->file("stress.md"), md.str());
    write_text(dir->file("summary.json"), report.dump(2) + "\n");
    dir->commit();
  }
  if (o.json) {
    std::cout << report.dump(2) << "\n";
  } else {
    std::cout << text;
    std::printf("%d stable, %d unstable, %d diverged, %d skipped or out of budget; %.0f s\n",
                stable,
                unstable,
                diverged,
                other,
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
  cmd->add_option("--out", o->out, "folder for summary.json (all numbers) and stress.md (table)");
  cmd->add_flag("--json", o->json, "print the results as JSON on stdout instead of the table");
  cmd->add_flag("--list", o->list, "list the cases, what stable means for each, and exit");
  cmd->add_flag("--quiet", o->quiet, "no progress lines on stderr");
  cmd->callback([&run, o] { run = [o] { return stress_command(*o); }; });
}

}  // namespace cbps::cli
