// The stress catalogue (`cbps stress`): stiff and extreme cases, each run with several solvers,
// each with its own statement of what "stable" means and a verdict measured against it.
#pragma once

#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "cbps/scene/scene.hpp"
#include "cbps/step/simulation.hpp"
#include "cbps/studies/conditioning.hpp"

namespace cbps {

/// A case's own verdict on a run that did not diverge.
struct StressVerdict {
  bool stable = false;
  std::string measure;  ///< the quantity judged, with its value and limit, e.g. "drift 2e-3 m"
  /// Further named numbers for the JSON output (e.g. angular momentum drift).
  std::vector<std::pair<std::string, double>> extra;
};

/// Watches one run of a case: called before the first step, after every step, at the end.
class StressProbe {
 public:
  virtual ~StressProbe() = default;
  virtual void start(const Simulation& /*sim*/) {}
  virtual void after_step(const Simulation& /*sim*/, const StepReport& /*report*/) {}
  virtual StressVerdict finish(const Simulation& sim) = 0;
};

struct StressCase {
  std::string name;          ///< e.g. "stack-50"
  std::string group;         ///< e.g. "size"
  std::string description;   ///< what the scene is
  std::string stable_means;  ///< what "stable" means here, and why
  std::function<Scene()> build;
  long steps = 0;
  /// Solver specs (parse_solver_spec) the case runs with; "-" for a case without rows.
  std::vector<std::string> solvers;
  /// Solvers left out on purpose, with the measured reason.
  std::vector<std::pair<std::string, std::string>> skipped;
  std::function<std::unique_ptr<StressProbe>(const Scene&)> probe;
};

/// What one (case, solver) run measured.
struct StressResult {
  std::string case_name;
  std::string solver;
  Integrator integrator = Integrator::Paper;  ///< how the run turned the bodies (body.hpp)
  /// "stable", "unstable" (the case's criterion failed), "diverged" (the divergence guard
  /// stopped it), "budget" (the wall-time budget ran out first) or "skipped".
  std::string status;
  std::string note;  ///< the divergence message, the skip reason or the budget
  long steps = 0;
  long steps_done = 0;
  int max_rows = 0;
  double max_constraint_error = 0.0;    ///< m
  double max_penetration = 0.0;         ///< m
  double energy_initial = 0.0;          ///< J
  double energy_final = 0.0;            ///< J
  double final_residual = 0.0;          ///< last step's velocity-system residual, N
  double max_residual = 0.0;            ///< N
  double cfm = 0.0;                     ///< kg⁻¹
  double cfm_acceleration_error = 0.0;  ///< max eps |lambda|, m/s²
  ConditionEstimate condition;          ///< of A at the end of the run (the state it stopped in)
  double wall_time_s = 0.0;             ///< the steps only
  StressVerdict verdict;
};

/// The catalogue, in the order `cbps stress` runs it.
std::vector<StressCase> stress_catalogue();

/// Runs one case with one solver spec for its steps, or until the divergence guard stops it or
/// `budget_s` of wall time is spent, its bodies turned by `integrator` (the case's scene
/// says nothing of it). `progress(step, steps)` is called after every step.
StressResult run_stress(const StressCase& c,
                        const std::string& solver,
                        double budget_s,
                        const std::function<void(long, long)>& progress = {},
                        Integrator integrator = Integrator::Paper);

/// Progress of run_stress_catalogue: run `done` of `total` (case c, solver spec), at `step` of
/// `steps`; `result` is set once the run has ended, null while it runs.
using StressProgress = std::function<void(std::size_t done,
                                          std::size_t total,
                                          const StressCase& c,
                                          const std::string& solver,
                                          long step,
                                          long steps,
                                          const StressResult* result)>;

/// Every case with every solver of its list that `kept` keeps ("-" for a case without rows),
/// in the catalogue's order, each followed by the solvers the case leaves out (status
/// "skipped", with the reason).
std::vector<StressResult> run_stress_catalogue(const std::vector<StressCase>& cases,
                                               const std::function<bool(const std::string&)>& kept,
                                               double budget_s,
                                               const StressProgress& progress = {},
                                               Integrator integrator = Integrator::Paper);

/// One result as summary.json's "results" show it (docs/stress.md).
nlohmann::json stress_result_json(const StressResult& r);
/// summary.json of `cbps stress --out`: the cases, the results, counts by status, wall time.
nlohmann::json stress_report_json(const std::vector<StressCase>& cases,
                                  const std::vector<StressResult>& results,
                                  double wall_time_s);
/// The Markdown table, one row per run: what `cbps stress` prints and stress.md holds.
std::string stress_table(const std::vector<StressResult>& results);
/// stress.md: the table and what stable means for each case.
std::string stress_markdown(const std::vector<StressCase>& cases,
                            const std::vector<StressResult>& results);

}  // namespace cbps
