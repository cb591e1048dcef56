// cbps run SCENE [options]: simulate, with summary.json, trajectory.csv and steps.csv.
#include "cbps/studies/run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>

#include "cbps/base/error.hpp"
#include "common.hpp"

namespace cbps::cli {

namespace {

struct RunOptions {
  SceneOptions scene;
  StepOptions step;
  std::string out;
  bool json = false;
  bool check = false;
  double check_tolerance = -1.0;  ///< --check-tolerance, m/s; negative: none
  bool quiet = false;
  bool no_timing = false;
  long record_every = 1;
};

/// Progress on stderr every 2 s of a long run.
class Progress : public StepObserver {
 public:
  explicit Progress(long steps) : steps_(steps) {}
  bool after_step(const Simulation& sim, const StepReport&, long done) override {
    const auto now = std::chrono::steady_clock::now();
    if (now - last_ <= std::chrono::seconds(2)) return true;
    last_ = now;
    std::fprintf(stderr,
                 "cbps run: step %ld/%ld (%.0f%%), t = %.3f s, %.1f s elapsed\n",
                 done,
                 steps_,
                 100.0 * static_cast<double>(done) / static_cast<double>(steps_),
                 sim.time(),
                 std::chrono::duration<double>(now - start_).count());
    return true;
  }

 private:
  long steps_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point last_ = start_;
};

void print_text(const Scene& scene,
                const RunTotals& t,
                const CrossCheck* check,
                const std::string& out) {
  const auto n3 = [](double x) { return number_text(x, 3); };
  std::printf(
      "%s: %s of %s s, %s, %s, solver %s%s\n"
      "  iterations %ld in all, max residual %s N, max constraint error %s m, "
      "max penetration %s m\n"
      "  energy %s J -> %s J, wall time %.3f s\n",
      scene.name.c_str(),
      count_text(t.steps_done, "step").c_str(),
      number_text(scene.world.dt).c_str(),
      count_text(static_cast<long>(scene.bodies.size()), "body", "bodies").c_str(),
      count_text(t.max_rows, "row").c_str(),
      std::string(to_string(scene.solver.method)).c_str(),
      t.diverged ? " (stopped: diverged)" : "",
      t.iterations_total,
      n3(t.max_residual).c_str(),
      n3(t.max_constraint_error).c_str(),
      n3(t.max_penetration).c_str(),
      number_text(t.energy_initial, 9).c_str(),
      number_text(t.energy_final, 9).c_str(),
      t.wall_time_s);
  if (check != nullptr) {
    std::printf(
        "  cross-check over %s: max |v2 - v2_direct| %s m/s, max residual %s N "
        "(direct %s N; %s short of its 64 u tolerance, %ld unverified)\n",
        count_text(check->steps_checked, "step").c_str(),
        n3(check->max_velocity_difference).c_str(),
        n3(check->max_residual).c_str(),
        n3(check->max_direct_residual).c_str(),
        count_text(check->direct_short, "step").c_str(),
        check->direct_unverified);
  }
  if (scene.solver.cfm > 0.0) {
    std::printf(
        "  cfm %s kg^-1: the answer misses A lambda = b by up to %s m/s^2 (%s m/s "
        "per step)\n",
        n3(scene.solver.cfm).c_str(),
        n3(t.cfm_acceleration_error).c_str(),
        n3(t.cfm_acceleration_error * scene.world.dt).c_str());
  }
  if (!out.empty()) std::printf("  wrote %s\n", out.c_str());
}

/// The exit code, with what went wrong on stderr (and the summary's warnings): 1 when the run
/// diverged, --check found a step beyond --check-tolerance, or under --check-tolerance the
/// method failed a step (run_warnings).
int report_failures(const Scene& scene,
                    const RunTotals& t,
                    const CrossCheck* check,
                    const std::string& out) {
  if (check != nullptr && check->steps_beyond > 0) {
    std::fprintf(stderr,
                 "cbps run: --check failed: %ld of %ld steps beyond --check-tolerance %s m/s, "
                 "the first step %ld (t = %s s) with max |v2 - v2_direct| = %s m/s%s%s\n",
                 check->steps_beyond,
                 check->steps_checked,
                 number_text(check->tolerance()).c_str(),
                 check->first_beyond,
                 number_text(static_cast<double>(check->first_beyond) * scene.world.dt).c_str(),
                 number_text(check->first_beyond_difference).c_str(),
                 out.empty() ? "" : "; the run's output is in ",
                 out.c_str());
  }
  for (const std::string& warning : run_warnings(t))
    std::fprintf(stderr, "cbps run: warning: %s\n", warning.c_str());
  // --check-tolerance asks for a run that can be trusted: a step its method failed is not one.
  const bool failed_steps = check != nullptr && check->tolerance() >= 0.0 && t.steps_failed > 0;
  if (t.diverged) {
    std::string msg = "cbps run: diverged: ";
    msg.append(t.diverged->what());
    if (!out.empty()) {
      msg.append("; what was recorded before that step is in ");
      msg.append(out);
    }
    std::fprintf(stderr, "%s\n", msg.c_str());
    return 1;
  }
  return (check != nullptr && check->steps_beyond > 0) || failed_steps ? 1 : 0;
}

int run_command(const RunOptions& o) {
  Scene scene = load_scene(o.scene);
  apply_step_options(scene, o.step);
  const long steps = step_count(scene, o.step);
  if (o.record_every < 1) throw InputError("--record-every: must be ≥ 1");
  if (o.check_tolerance >= 0.0 && !o.check)
    throw InputError("--check-tolerance: needs --check (the cross-check it judges)");

  std::vector<StepObserver*> observers;
  std::unique_ptr<OutputDir> dir;
  std::unique_ptr<TrajectoryRecorder> trajectory;
  std::unique_ptr<StepsRecorder> steps_csv;
  if (!o.out.empty()) {
    dir = std::make_unique<OutputDir>(o.out);
    trajectory = std::make_unique<TrajectoryRecorder>(dir->file("trajectory.csv"), o.record_every);
    steps_csv = std::make_unique<StepsRecorder>(dir->file("steps.csv"), !o.no_timing);
    observers = {trajectory.get(), steps_csv.get()};
  }
  std::unique_ptr<CrossCheck> check;
  if (o.check) {
    check = std::make_unique<CrossCheck>(o.check_tolerance);
    observers.push_back(check.get());
  }
  Progress progress(steps);
  if (!o.quiet) observers.push_back(&progress);

  // The divergence guard (Simulation::step) stops the run at the step that failed; what was
  // recorded before it is kept and the summary says where and why.
  const RunTotals totals = run_scene(scene, steps, observers);

  nlohmann::json summary = run_summary_json(scene, totals, !o.no_timing, threads_json());
  if (check) summary["cross_check"] = check->json(!o.no_timing);
  if (dir) {
    trajectory->close();
    steps_csv->close();
    write_text(dir->file("summary.json"), summary.dump(2) + "\n");
    write_text(dir->file("bodies.json"), bodies_json(scene).dump(2) + "\n");
    dir->commit();
  }
  if (o.json)
    std::cout << summary.dump(2) << "\n";
  else
    print_text(scene, totals, check.get(), o.out);
  return report_failures(scene, totals, check.get(), o.out);
}

}  // namespace

void register_run(CLI::App& app, Action& run) {
  auto* cmd = app.add_subcommand("run", "simulate a scene");
  auto o = std::make_shared<RunOptions>();
  add_scene_options(cmd, o->scene);
  add_step_options(cmd, o->step);
  add_out_option(cmd,
                 o->out,
                 "summary.json, trajectory.csv, steps.csv, bodies.json (the body names of "
                 "trajectory.csv) and cbps-manifest.json");
  cmd->add_option("--record-every", o->record_every, "record the trajectory every K steps")
      ->check(positive());
  add_json_flag(cmd, o->json, "the summary");
  cmd->add_flag(
      "--check",
      o->check,
      "cross-check every step against the direct path (interior point with crossover); adds "
      "cross_check");
  cmd->add_option("--check-tolerance",
                  o->check_tolerance,
                  "with --check: exit 1, naming the first step, when a step's max |v2 - "
                  "v2_direct| exceeds this, m/s (the run still completes and writes --out)")
      ->check(non_negative());
  add_quiet_flag(cmd, o->quiet);
  cmd->add_flag("--no-timing",
                o->no_timing,
                "leave wall times out of summary.json and steps.csv, so that the same inputs "
                "give byte-identical outputs");
  cmd->callback([&run, o] { run = [o] { return run_command(*o); }; });
}

}  // namespace cbps::cli
