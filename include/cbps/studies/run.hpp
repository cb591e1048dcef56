// A run of a scene: the one step loop (`cbps run`, `cbps stress`, the Python module's
// Simulation.run, the validation programs), what its steps add up to, and the observers that
// watch it: the --check cross-check against the direct path, the trajectory.csv and steps.csv
// recorders, and summary.json (docs/outputs.md).
#pragma once

#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "cbps/base/error.hpp"
#include "cbps/io/csv_file.hpp"
#include "cbps/step/simulation.hpp"

namespace cbps {

/// What the steps of a run add up to. The maxima start from the state before the first step
/// where the state has one (the constraint error); the others from the first step.
struct RunTotals {
  long steps_requested = 0;
  long steps_done = 0;
  double energy_initial = 0.0;        ///< J, before the first step
  double energy_final = 0.0;          ///< J, after the last step done
  double time = 0.0;                  ///< s, the simulation's time after the last step done
  double max_constraint_error = 0.0;  ///< m, over the start and every step
  double max_residual = 0.0;          ///< N, the solver's residual (SolverSummary::residual)
  double final_residual = 0.0;        ///< N, of the last step done
  long iterations_total = 0;
  int max_rows = 0;
  int max_contacts = 0;
  /// The friction the steps solved (StepReport): contacts with friction rows summed over the
  /// steps, the range of their mu, and each law seen → the contact-steps that carried it.
  long friction_contact_steps = 0;
  double solved_mu_min = 0.0, solved_mu_max = 0.0;
  std::map<std::string, long> solved_laws;
  double max_penetration = 0.0;         ///< m
  double cfm_acceleration_error = 0.0;  ///< m/s², max eps |lambda| (StepReport)
  StageTimes stage_times;               ///< summed over the steps, s
  /// The direct path's routes (SolverSummary::route) → steps that took them: the step's system
  /// (the velocity system with the improved push), and the position system (8.1)
  std::map<std::string, long> routes, position_routes;
  std::vector<std::string> stages;  ///< every stage that ran, in order of first appearance
  /// The divergence guard's error when it stopped the run (the steps before it are counted).
  std::optional<DivergenceError> diverged;
  bool stopped = false;  ///< an observer stopped the run before its last step
  /// Steps with rows, and those whose method failed (method_failed: a peer's answer cbps's
  /// residual rejects, the direct path stopped short, non-finite values, no solution, the time
  /// limit); the first such step (0-based; −1: none).
  long steps_with_rows = 0;
  long steps_failed = 0;
  long first_failed_step = -1;
  std::string first_failure;  ///< that step's solver message
  double wall_time_s = 0.0;
};

/// Watches a run step by step (run_steps).
class StepObserver {
 public:
  virtual ~StepObserver() = default;
  /// Before the first step.
  virtual void start(Simulation& /*sim*/) {}
  /// Before step `index` (0-based) of the run.
  virtual void before_step(Simulation& /*sim*/, long /*index*/) {}
  /// After a step; `done` steps of the run are done. Returning false stops the run there (a
  /// wall-time budget, Ctrl-C); RunTotals::stopped then says so.
  virtual bool after_step(const Simulation& /*sim*/, const StepReport& /*report*/, long /*done*/) {
    return true;
  }
};

/// Runs `steps` steps of sim with the observers, in their order, and adds up what the steps
/// report. A DivergenceError ends the run at the step that failed (RunTotals::diverged, the
/// bodies as they were before that step); other errors propagate.
RunTotals run_steps(Simulation& sim, long steps, const std::vector<StepObserver*>& observers = {});

/// run_steps over a new Simulation of `scene` (`cbps run`).
RunTotals run_scene(const Scene& scene,
                    long steps,
                    const std::vector<StepObserver*>& observers = {});

/// Steps `sim` `steps` times (to the step a command studies: the system of step K is the one
/// after K steps), with a progress line on stderr every 2 s ("cbps COMMAND: stepping to step N:
/// k/N (p%), s elapsed") unless `quiet`: a command that steps for long before its work is not
/// silent. A DivergenceError propagates.
void step_to(Simulation& sim, long steps, const std::string& command, bool quiet = false);

/// `cbps run --check`: every step's system solved again by the direct path (interior point with
/// crossover, 6.2) from the iterative solver's lambda (from interior_from_rows rows on only
/// when that already solves the step to the rounding floor, else from 0), and v2 compared (v2
/// is unique where
/// lambda is not). Attaches itself to the simulation's system observer in start().
class CrossCheck : public StepObserver {
 public:
  /// `tolerance` (m/s): a step whose max |v2 - v2_direct| exceeds it is counted as beyond;
  /// negative: none.
  explicit CrossCheck(double tolerance = -1.0) : tolerance_(tolerance) {}
  void start(Simulation& sim) override;

  double max_velocity_difference = 0.0;  ///< m/s, max over the steps of max |v2 - v2_direct|
  double max_residual = 0.0;             ///< N, of the iterative solver's lambda
  double max_direct_residual = 0.0;      ///< N, of the direct path's lambda
  double max_direct_unit_free = 0.0;     ///< its largest unit-free residual (unit_free.hpp)
  long steps_checked = 0;
  long direct_short = 0;       ///< steps the direct path ended short of its tolerance
  long direct_unverified = 0;  ///< steps whose direct answer `cbps lcp` would not call solved
  long steps_beyond = 0;       ///< steps beyond the tolerance
  long first_beyond = -1;      ///< the first of them (0-based step), -1 if none
  double first_beyond_difference = 0.0;
  std::map<std::string, long> routes;  ///< the direct solves' routes (SolverSummary::route)
  double direct_time_s = 0.0;          ///< s, in the direct solves, all steps
  long direct_pivots = 0;              ///< their crossover pivots, all steps

  double tolerance() const { return tolerance_; }
  /// summary.json's "cross_check" (docs/outputs.md); its direct_time_s only with `timing` (a
  /// wall time).
  nlohmann::json json(bool timing) const;

 private:
  double tolerance_;
};

/// trajectory.csv: the bodies' state at the start and after every `every`-th step.
class TrajectoryRecorder : public StepObserver {
 public:
  TrajectoryRecorder(const std::string& path, long every);
  void start(Simulation& sim) override;
  bool after_step(const Simulation& sim, const StepReport& report, long done) override;
  void close() { csv_.close(); }

 private:
  CsvFile csv_;
  long every_;
};

/// steps.csv: one row per step (wall times left out with `timing` false).
class StepsRecorder : public StepObserver {
 public:
  StepsRecorder(const std::string& path, bool timing);
  bool after_step(const Simulation& sim, const StepReport& report, long done) override;
  void close() { csv_.close(); }

 private:
  CsvFile csv_;
  bool timing_;
};

/// What the summary warns of (summary.json "warnings"; `cbps run` prints them on stderr): the
/// steps whose method failed (RunTotals::steps_failed), with the first one's step and message.
std::vector<std::string> run_warnings(const RunTotals& t);

/// summary.json of `cbps run` without its cross_check (docs/outputs.md); wall times, stage times
/// and threads only with `timing` (`threads` is the machine's thread report, as the times are).
nlohmann::json run_summary_json(const Scene& scene,
                                const RunTotals& totals,
                                bool timing,
                                const nlohmann::json& threads);

/// bodies.json: the bodies of trajectory.csv's `body` column.
nlohmann::json bodies_json(const Scene& scene);

}  // namespace cbps
