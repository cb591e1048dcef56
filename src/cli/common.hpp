// Shared pieces of the command line: scene loading, step options, output folders.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <initializer_list>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cbps/io/json_numbers.hpp"
#include "cbps/io/output_dir.hpp"
#include "cbps/io/output_file.hpp"
#include "cbps/io/stored_problem.hpp"
#include "cbps/scene/scene.hpp"

namespace cbps::cli {

/// SCENE and --param NAME=VALUE.
struct SceneOptions {
  std::string scene;
  std::vector<std::string> params;
};

/// The contract's common options of commands that step a scene; unset values keep the scene's.
struct StepOptions {
  long steps = -1;
  double duration = -1.0;
  std::string solver;
  /// --KEY VALUE of the world and solver settings given (settings.hpp: --dt, --beta, ...;
  /// --seed, --iterations, --tolerance, --cfm) by key, as given; the rest keep the scene's.
  std::map<std::string, std::string> world, solver_settings;
};

void add_scene_options(
    CLI::App* cmd,
    SceneOptions& o,
    const std::string& what = "built-in scene name (see `cbps scenes`) or JSON scene file");
/// --cfm and the world settings that have an option (settings.hpp: --dt, --beta, --push,
/// --integrator, --scheme, --substeps and the schemes' own).
void add_world_options(CLI::App* cmd, StepOptions& o);
/// --KEY of the solver settings `keys` (settings.hpp; each one whose entry is an option).
void add_solver_options(CLI::App* cmd, StepOptions& o, std::initializer_list<const char*> keys);
/// The world (solver) options given onto a world (solver), in the table's order (a scheme before
/// its own settings), each checked as a scene file's /world/KEY (/solver/KEY) is: InputError
/// naming the option.
void apply_world_options(World& world, const StepOptions& o);
void apply_solver_options(SolverSettings& solver, const StepOptions& o);
/// --solver, --seed, --iterations, --tolerance and the world options; with run_length also
/// --steps and --duration (commands that run a scene; explain and matrices take --step).
void add_step_options(CLI::App* cmd, StepOptions& o, bool run_length = true);
/// Any world option or --cfm given (they apply to scenes only).
bool world_options_given(const StepOptions& o);
/// --cone coulomb|ccp: the friction law of a stored problem's contacts in cones (docs/cones.md).
void add_cone_option(CLI::App* cmd, std::string& cone);
/// --siconos KIND (what a .dat file holds) and --cone LAW: how a stored problem is read
/// (io/stored_problem.hpp's read_problem with their words).
void add_problem_options(CLI::App* cmd, std::string& siconos, std::string& cone);

/// --json: print `what` as JSON on stdout instead of the text.
CLI::Option* add_json_flag(CLI::App* cmd, bool& json, const std::string& what);
/// --out DIR: the output folder, written whole or not at all (OutputDir); `holds` says what
/// the command writes there.
CLI::Option* add_out_option(CLI::App* cmd, std::string& out, const std::string& holds);
/// --quiet: `what` (default: no progress lines on stderr).
CLI::Option* add_quiet_flag(CLI::App* cmd,
                            bool& quiet,
                            const std::string& what = "no progress lines on stderr");

/// Option checks whose messages show the value as given (CLI11's own print DBL_MAX in full).
CLI::Validator positive();      ///< a finite number > 0
CLI::Validator non_negative();  ///< a finite number >= 0
/// A whole number of steps from 0 to kMaxReplaySteps, also written 1e6; rewritten as digits for
/// the option's integer (`--step` of explain, matrices, converge).
CLI::Validator step_index();
CLI::Validator non_empty();  ///< any text but the empty one (a file name)

/// The most steps a run takes (a longer run is a typo: 1e12 steps of a one-body scene take days).
inline constexpr double kMaxSteps = 1e12;
/// The latest step `--step K` shows: explain, matrices and converge replay the K steps before it
/// without output or progress (1e7 steps of the 50-ball pendulum wave take about 9 minutes at
/// the README's 5e-5 s a step); a later step is a run (`cbps run`) rather than a look at one.
inline constexpr double kMaxReplaySteps = 1e7;

/// The --param NAME=VALUE texts as name → value; InputError for one without a name or '='.
std::map<std::string, std::string> parameter_values(const std::vector<std::string>& params);
/// A built-in scene by name (with its --param values) or a JSON scene file.
Scene load_scene(const SceneOptions& o);
/// Applies --dt, --beta, --solver, --iterations, --tolerance, --cfm to the scene.
void apply_step_options(Scene& scene, const StepOptions& o);
/// Number of steps from --steps, else --duration, else the scene's duration; InputError when
/// the duration gives no step or more than kMaxSteps.
long step_count(const Scene& scene, const StepOptions& o);

/// The command line this process was started with, as a command a reader can type again:
/// "cbps" and its arguments, each quoted for a POSIX shell where it needs it (set by main).
const std::string& invocation_text();
void set_invocation(int argc, const char* const* argv);

/// While it lives, a line on stderr every 2 s ("cbps lcp: siconos:lemke on F: running, 4.0 s
/// elapsed (time limit 600 s)") unless `quiet`: a solve that exposes no iterates (a peer in its
/// child process, an exact path) is not silent. Written by write(2), not stdio: a peer's fork
/// while this thread holds stderr's lock would leave the child's stderr locked.
class Heartbeat {
 public:
  Heartbeat(std::string what, double time_limit, bool quiet);
  ~Heartbeat();
  Heartbeat(const Heartbeat&) = delete;
  Heartbeat& operator=(const Heartbeat&) = delete;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// The threads the libraries run with (set_threads, from --threads) as summaries report them:
/// {"requested", "blas", "blas_kind", "blas_threads", "openmp_threads"}.
nlohmann::json threads_json();

/// Runs one of cbps's own Python scripts, SCRIPT relative to the source tree (e.g.
/// "scripts/plot_convergence.py"), under CBPS_PLOT_PYTHON (Debian's python3, which has
/// matplotlib) with the arguments given; true if it exited 0.
bool run_python_script(const std::string& script, std::vector<std::string> args);

/// Registration of each command: adds the subcommand and sets `run` to its action.
using Action = std::function<int()>;
void register_scenes(CLI::App& app, Action& run);
void register_run(CLI::App& app, Action& run);
void register_stress(CLI::App& app, Action& run);
void register_explain(CLI::App& app, Action& run);
void register_matrices(CLI::App& app, Action& run);
void register_lcp(CLI::App& app, Action& run);
void register_check(CLI::App& app, Action& run);
void register_mujoco(CLI::App& app, Action& run);
void register_verify(CLI::App& app, Action& run);
void register_converge(CLI::App& app, Action& run);
void register_profile(CLI::App& app, Action& run);

}  // namespace cbps::cli
