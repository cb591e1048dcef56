#include "common.hpp"

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>

#include "cbps/error.hpp"
#include "cbps/scene_json.hpp"
#include "cbps/scenes.hpp"
#include "cbps/solver.hpp"

namespace fs = std::filesystem;

namespace cbps::cli {

void add_scene_options(CLI::App* cmd, SceneOptions& o) {
  cmd->add_option("SCENE", o.scene, "built-in scene name (see `cbps scenes`) or JSON scene file")
      ->required();
  cmd->add_option("--param", o.params, "NAME=VALUE: a built-in scene's parameter (repeatable)");
}

void add_step_options(CLI::App* cmd, StepOptions& o, bool run_length) {
  cmd->add_option("--dt", o.dt, "time step in s (fractions such as 1/240 accepted)");
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
                  "NAME[:OMEGA][:order=natural|reverse|random][:warm=on|off] with NAME pgs, "
                  "psor, sgs, jacobi, block-pgs, matrix-free or direct, e.g. psor:1.3 "
                  "(default: the scene's, pgs)");
  cmd->add_option("--seed", o.seed, "seed of the random row order (order=random), >= 0")
      ->check(non_negative());
  cmd->add_option("--iterations", o.iterations, "max solver sweeps per step")->check(positive());
  cmd->add_option("--tolerance",
                  o.tolerance,
                  "natural-map residual to stop at, N, for every method (0: all sweeps; the "
                  "direct path stops at its rounding floor if that is higher; default: the "
                  "scene's, 1e-10)")
      ->check(non_negative());
  cmd->add_option("--cfm",
                  o.cfm,
                  "constraint-force mixing eps in kg^-1: solve (A + eps E) lambda = b; the "
                  "summary reports its effect eps max|lambda| (default: the scene's, 0)")
      ->check(non_negative());
  cmd->add_option("--beta", o.beta, "Baumgarte push factor in [0, 1] (5.2.3)")
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--push",
                  o.push,
                  "push factor form: original (Baumgarte in the one system, 5.2.3, 5.3) | "
                  "improved (velocity and position systems, 8.1); default: the scene's")
      ->check(CLI::IsMember({"original", "improved"}));
}

Scene load_scene(const SceneOptions& o) {
  std::map<std::string, std::string> values;
  for (const std::string& p : o.params) {
    const auto eq = p.find('=');
    if (eq == std::string::npos || eq == 0) {
      throw InputError("--param '" + p + "': expected NAME=VALUE");
    }
    values[p.substr(0, eq)] = p.substr(eq + 1);
  }
  if (find_builtin_scene(o.scene) != nullptr) return make_builtin_scene(o.scene, values);
  std::error_code ec;
  if (fs::is_regular_file(o.scene, ec)) {
    if (!values.empty()) {
      throw InputError("--param: parameters apply to built-in scenes only, not to the file " +
                       o.scene);
    }
    return read_scene_file(o.scene);
  }
  return make_builtin_scene(o.scene, values);  // throws, listing the built-in scenes
}

void apply_step_options(Scene& scene, const StepOptions& o) {
  if (!o.dt.empty()) {
    double dt = 0.0;
    if (!parse_number(o.dt, dt) || !(dt > 0.0)) {
      throw InputError("--dt '" + o.dt + "': must be a positive finite time in s");
    }
    scene.world.dt = dt;
  }
  if (o.beta >= 0.0) scene.world.beta = o.beta;
  if (o.push == "original") scene.world.push = PushMode::Original;
  if (o.push == "improved") scene.world.push = PushMode::Improved;
  if (!o.solver.empty()) {
    // InputError names what is wrong
    apply_solver_spec(parse_solver_spec(o.solver, "--solver"), scene.solver);
  }
  if (o.seed >= 0) scene.solver.seed = static_cast<std::uint64_t>(o.seed);
  if (o.iterations > 0) scene.solver.iterations = o.iterations;
  if (o.tolerance >= 0.0) scene.solver.tolerance = o.tolerance;
  if (o.cfm >= 0.0) scene.solver.cfm = o.cfm;
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

OutputDir::OutputDir(const std::string& final_path) : final_(final_path) {
  std::error_code ec;
  if (fs::exists(final_, ec)) {
    if (!fs::is_directory(final_, ec)) {
      throw InputError("--out " + final_ + ": exists and is not a folder");
    }
    const bool empty = fs::is_empty(final_, ec);
    const bool ours = fs::exists(fs::path(final_) / "summary.json", ec) ||
                      fs::exists(fs::path(final_) / "labels.json", ec) ||
                      fs::exists(fs::path(final_) / "result.json", ec);
    if (!empty && !ours) {
      throw InputError("--out " + final_ +
                       ": folder exists and is not a cbps output; refusing to replace it");
    }
  }
  const fs::path parent = fs::absolute(final_).parent_path();
  fs::create_directories(parent, ec);
  if (ec) throw InputError("--out " + final_ + ": cannot create " + parent.string());
  temp_ =
      (parent / ("." + fs::path(final_).filename().string() + ".tmp-" + std::to_string(::getpid())))
          .string();
  fs::remove_all(temp_, ec);
  if (!fs::create_directory(temp_, ec)) throw InputError("--out " + final_ + ": cannot create");
}

OutputDir::~OutputDir() {
  if (!committed_) {
    std::error_code ec;
    fs::remove_all(temp_, ec);
  }
}

std::string OutputDir::file(const std::string& name) const {
  return (fs::path(temp_) / name).string();
}

void OutputDir::commit() {
  std::error_code ec;
  fs::remove_all(final_, ec);
  fs::rename(temp_, final_, ec);
  if (ec) throw std::runtime_error("--out " + final_ + ": cannot rename: " + ec.message());
  committed_ = true;
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  out.flush();
  if (!out) throw std::runtime_error(path + ": write failed");
}

std::vector<std::string> column_labels(const Scene& scene, const System& sys) {
  static const char* const coords[6] = {"vx", "vy", "vz", "wx", "wy", "wz"};
  std::vector<std::string> labels;
  for (int body : sys.body_of_block) {
    for (const char* c : coords) {
      labels.push_back(scene.bodies[static_cast<std::size_t>(body)].name + "." + c);
    }
  }
  return labels;
}

nlohmann::json number_json(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  return x;
}

nlohmann::json dense_json(const MatX& M) {
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index r = 0; r < M.rows(); ++r) {
    nlohmann::json row = nlohmann::json::array();
    for (Eigen::Index c = 0; c < M.cols(); ++c) row.push_back(number_json(M(r, c)));
    rows.push_back(row);
  }
  return rows;
}

nlohmann::json vector_json(const VecX& v) {
  nlohmann::json a = nlohmann::json::array();
  for (Eigen::Index k = 0; k < v.size(); ++k) a.push_back(number_json(v(k)));
  return a;
}

}  // namespace cbps::cli
