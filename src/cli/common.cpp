#include "common.hpp"

#include <fcntl.h>
#include <pthread.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <span>
#include <sstream>
#include <thread>

#include "cbps/base/error.hpp"
#include "cbps/base/numbers.hpp"
#include "cbps/io/fclib_file.hpp"
#include "cbps/io/output_file.hpp"
#include "cbps/scene/builtin.hpp"
#include "cbps/scene/scene_json.hpp"
#include "cbps/scene/settings.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/solvers/threads.hpp"
#include "cbps/studies/solver_spec.hpp"

extern char** environ;

namespace fs = std::filesystem;

namespace cbps::cli {

void add_scene_options(CLI::App* cmd, SceneOptions& o, const std::string& what) {
  cmd->add_option("SCENE", o.scene, what)->required();
  cmd->add_option("--param", o.params, "NAME=VALUE: a built-in scene's parameter (repeatable)");
}

namespace {

/// --KEY of a setting (settings.hpp), its help made from the entry; the value is kept as given
/// under its key and checked where it is applied.
template <typename T>
void add_setting_option(CLI::App* cmd,
                        std::map<std::string, std::string>& given,
                        const Setting<T>& s) {
  const std::string key(s.key);
  std::string help(s.rule);
  if (s.applies != nullptr) help = "under " + std::string(s.applies_text) + ": " + help;
  help += " (" + (s.unit.empty() ? "" : std::string(s.unit) + "; ") +
          (s.type == SettingType::Word ? "" : range_text(s) + "; ") + "default: the scene's)";
  cmd->add_option_function<std::string>(
         option_name(s), [&given, key](const std::string& value) { given[key] = value; }, help)
      ->type_name(s.type == SettingType::Real    ? "FLOAT"
                  : s.type == SettingType::Whole ? "INT"
                                                 : "WORD");
}

/// The settings given as options onto `target`, in the table's order, each checked as a scene
/// file's is: InputError naming the option.
template <typename T>
void apply_setting_options(T& target,
                           std::span<const Setting<T>> settings,
                           const std::map<std::string, std::string>& given) {
  for (const Setting<T>& s : settings)
    if (const auto text = given.find(std::string(s.key)); text != given.end())
      if (const std::string why = set_setting_text(target, s, text->second); !why.empty())
        throw InputError(option_name(s) + " " + text->second + ": " + why);
}

}  // namespace

void add_solver_options(CLI::App* cmd, StepOptions& o, std::initializer_list<const char*> keys) {
  for (const char* key : keys)
    add_setting_option(cmd, o.solver_settings, *find_solver_setting(key));  // an option's key
}

void add_world_options(CLI::App* cmd, StepOptions& o) {
  add_solver_options(cmd, o, {"cfm"});
  for (const WorldSetting& s : world_settings())
    if (s.option) add_setting_option(cmd, o.world, s);
}

void apply_solver_options(SolverSettings& solver, const StepOptions& o) {
  apply_setting_options(solver, solver_settings(), o.solver_settings);
}

void apply_world_options(World& world, const StepOptions& o) {
  apply_setting_options(world, world_settings(), o.world);
}

void add_step_options(CLI::App* cmd, StepOptions& o, bool run_length) {
  if (run_length) {
    auto* steps =
        cmd->add_option("--steps", o.steps, "number of steps (default: the scene's duration)")
            ->check(non_negative());
    cmd->add_option("--duration", o.duration, "simulated time in s (instead of --steps)")
        ->check(positive())
        ->excludes(steps);
  }
  cmd->add_option("--solver",
                  o.solver,
                  "NAME[:OMEGA][:order=natural|reverse|random][:contacts_first=on|off]"
                  "[:warm=on|off|F][:warm_friction=on|off|G][:key=value] with "
                  "NAME one of the solvers listed below, e.g. psor:1.3 (default: the scene's, "
                  "pgs)");
  cmd->footer(solver_spec_help());
  add_solver_options(cmd, o, {"seed", "iterations", "tolerance"});
  add_world_options(cmd, o);
}

CLI::Option* add_json_flag(CLI::App* cmd, bool& json, const std::string& what) {
  return cmd->add_flag("--json", json, "print " + what + " as JSON on stdout");
}

CLI::Option* add_out_option(CLI::App* cmd, std::string& out, const std::string& holds) {
  return cmd->add_option("--out", out, "output folder: " + holds + " (docs/outputs.md)");
}

CLI::Option* add_quiet_flag(CLI::App* cmd, bool& quiet, const std::string& what) {
  return cmd->add_flag("--quiet", quiet, what);
}

bool world_options_given(const StepOptions& o) {
  return !o.world.empty() || o.solver_settings.contains("cfm");
}

std::map<std::string, std::string> parameter_values(const std::vector<std::string>& params) {
  std::map<std::string, std::string> values;
  for (const std::string& p : params) {
    const auto eq = p.find('=');
    if (eq == std::string::npos || eq == 0) {
      throw InputError("--param '" + p + "': expected NAME=VALUE");
    }
    values[p.substr(0, eq)] = p.substr(eq + 1);
  }
  return values;
}

void add_cone_option(CLI::App* cmd, std::string& cone) {
  cmd->add_option("--cone",
                  cone,
                  "an FCLIB file's friction law: coulomb (Coulomb's law with De Saxce's "
                  "term, FCLIB's own) or ccp (the convex relaxation, cone complementarity) "
                  "(default coulomb; docs/cones.md)");
}

void add_problem_options(CLI::App* cmd, std::string& siconos, std::string& cone) {
  cmd->add_option("--siconos",
                  siconos,
                  "what a .dat file holds: auto (from its contents: a frictional-contact dump "
                  "begins d nc storage, an LCP n 0 n n; then n^2 + n numbers an LCP, n^2 + 3n a "
                  "relay problem), lcp, relay or fc3d (Siconos' frictional-contact dump, local "
                  "or global, docs/cones.md) (default auto)");
  add_cone_option(cmd, cone);
}

Scene load_scene(const SceneOptions& o) {
  const std::map<std::string, std::string> values = parameter_values(o.params);
  if (find_builtin_scene(o.scene) != nullptr) return make_builtin_scene(o.scene, values);
  std::error_code ec;
  if (fs::is_directory(o.scene, ec))
    throw InputError(o.scene +
                     ": is a folder, not a scene; give a built-in scene's name (cbps scenes) or "
                     "a JSON scene file (docs/scene-format.md)");
  if (fs::is_regular_file(o.scene, ec)) {
    if (is_hdf5_file(o.scene))
      throw InputError(o.scene + ": an HDF5 file (an FCLIB problem?), not a scene; `cbps lcp " +
                       o.scene + "` solves an FCLIB problem (docs/cones.md)");
    if (!values.empty()) {
      throw InputError("--param: parameters apply to built-in scenes only, not to the file " +
                       o.scene);
    }
    return read_scene_file(o.scene);
  }
  return make_builtin_scene(o.scene, values);  // throws, listing the built-in scenes
}

void apply_step_options(Scene& scene, const StepOptions& o) {
  apply_world_options(scene.world, o);
  if (!o.solver.empty()) {
    // InputError names what is wrong
    apply_solver_spec(parse_solver_spec(o.solver, "--solver"), scene.solver);
  }
  apply_solver_options(scene.solver, o);
}

long step_count(const Scene& scene, const StepOptions& o) {
  if (o.steps >= 0) return o.steps;
  const bool given = o.duration > 0.0;
  const double duration = given ? o.duration : scene.duration;
  const std::string what = given ? "--duration " + number_text(duration)
                                 : "the scene's duration " + number_text(duration);
  const double steps = duration / scene.world.dt;
  if (!std::isfinite(steps) || steps > kMaxSteps)
    throw InputError(what + " s: " + number_text(steps) +
                     " steps of dt = " + number_text(scene.world.dt) +
                     " s, more than a run can take (" + number_text(kMaxSteps) + ")");
  const long count = std::lround(steps);
  if (count < 1)
    throw InputError(what + " s: shorter than half a step (dt = " + number_text(scene.world.dt) +
                     " s), so no step would run; use --steps 1 or a longer duration");
  return count;
}

CLI::Validator positive() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double x = 0.0;
        if (!parse_number(text, x) || !(x > 0.0)) return "'" + text + "' is not a number > 0";
        return {};
      },
      "> 0");
}

CLI::Validator non_negative() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double x = 0.0;
        if (!parse_number(text, x) || !(x >= 0.0)) return "'" + text + "' is not a number >= 0";
        return {};
      },
      ">= 0");
}

CLI::Validator step_index() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double x = 0.0;
        if (!parse_number(text, x) || !(x >= 0.0) || x != std::floor(x) || x > kMaxReplaySteps)
          return "'" + text + "' is not a whole number of steps from 0 to " +
                 number_text(kMaxReplaySteps) +
                 " (1e6 accepted; the steps before it are replayed, so a later one is a run: "
                 "cbps run --steps N)";
        text = std::to_string(static_cast<long>(x));
        return {};
      },
      "0..1e7");
}

CLI::Validator non_empty() {
  return CLI::Validator(
      [](std::string& text) -> std::string { return text.empty() ? "empty file name" : ""; },
      "FILE");
}

bool run_python_script(const std::string& script, std::vector<std::string> args) {
  const std::string python = CBPS_PLOT_PYTHON;
  args.insert(args.begin(), {python, std::string(CBPS_SOURCE_DIR) + "/" + script});
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawn(&pid, python.c_str(), nullptr, nullptr, argv.data(), environ) != 0) return false;
  int status = 0;
  if (waitpid(pid, &status, 0) != pid) return false;
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

nlohmann::json threads_json() {
  const ThreadReport r = thread_report();
  return {{"requested", r.requested},
          {"blas", r.blas},
          {"blas_kind", r.blas_kind},
          {"blas_threads", r.blas_threads},
          {"openmp_threads", r.openmp_threads}};
}

namespace {
std::string& invocation() {
  static std::string text = "cbps";
  return text;
}

/// `word` as a POSIX shell reads it back: as it is when it holds only safe characters, else in
/// single quotes (a ' inside closed, escaped and reopened).
std::string shell_quoted(const std::string& word) {
  const bool safe = !word.empty() && word.find_first_not_of(
                                         "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                         "0123456789-_./=:,+@%") == std::string::npos;
  if (safe) return word;
  std::string quoted = "'";
  for (const char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}
}  // namespace

const std::string& invocation_text() { return invocation(); }

void set_invocation(int argc, const char* const* argv) {
  std::string text = "cbps";
  for (int i = 1; i < argc; ++i) text += " " + shell_quoted(argv[i]);
  invocation() = text;
}

struct Heartbeat::State {
  std::mutex mutex;
  std::condition_variable wake;
  bool started = false, done = false;
  std::thread thread;
};

Heartbeat::Heartbeat(std::string what, double time_limit, bool quiet) {
  if (quiet) return;
  state_ = std::make_unique<State>();
  State* s = state_.get();
  s->thread = std::thread([s, what = std::move(what), time_limit] {
    const auto start = std::chrono::steady_clock::now();
    std::unique_lock<std::mutex> lock(s->mutex);
    s->started = true;
    s->wake.notify_all();
    while (!s->wake.wait_for(lock, std::chrono::seconds(2), [s] { return s->done; })) {
      const double elapsed =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      // Formatted on the stack: a peer's fork() while this thread is inside malloc would leave
      // the child's allocator locked (seen as a child hung forever under AddressSanitizer).
      char line[512];
      const int n =
          time_limit > 0.0
              ? std::snprintf(line,
                              sizeof line,
                              "%s: running, %.1f s elapsed (time limit %g s)\n",
                              what.c_str(),
                              elapsed,
                              time_limit)
              : std::snprintf(
                    line, sizeof line, "%s: running, %.1f s elapsed\n", what.c_str(), elapsed);
      // A failed write of a progress line is not worth stopping for.
      if (n > 0) {
        [[maybe_unused]] const ssize_t written =
            ::write(2, line, std::min(static_cast<std::size_t>(n), sizeof line - 1));
      }
    }
  });
  // The thread's own start (its stack, the sanitizers' bookkeeping) allocates: wait until it is
  // parked in wait_for, so that no fork() of a peer's child meets it half-started.
  std::unique_lock<std::mutex> lock(s->mutex);
  s->wake.wait(lock, [s] { return s->started; });
}

Heartbeat::~Heartbeat() {
  if (!state_) return;
  {
    const std::lock_guard<std::mutex> lock(state_->mutex);
    state_->done = true;
  }
  state_->wake.notify_one();
  state_->thread.join();
}

}  // namespace cbps::cli
