// cbps run SCENE [options]: simulate, with summary.json, trajectory.csv and steps.csv.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>

#include "cbps/base/error.hpp"
#include "cbps/solvers/coulomb.hpp"
#include "cbps/solvers/lemke.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/step/simulation.hpp"
#include "cbps/studies/solver_spec.hpp"
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

/// A buffered CSV file with fixed-precision numbers.
class Csv {
 public:
  Csv(const std::string& path, const char* header)
      : path_(path), f_(std::fopen(path.c_str(), "w")) {
    if (f_ == nullptr) throw std::runtime_error(path + ": cannot open for writing");
    std::fputs(header, f_);
    std::fputc('\n', f_);
  }
  ~Csv() {
    if (f_ != nullptr) std::fclose(f_);
  }
  Csv(const Csv&) = delete;
  Csv& operator=(const Csv&) = delete;
  void num(double x) {
    std::fprintf(f_, first_ ? "%.12g" : ",%.12g", x);
    first_ = false;
  }
  void integer(long x) {
    std::fprintf(f_, first_ ? "%ld" : ",%ld", x);
    first_ = false;
  }
  void end_row() {
    std::fputc('\n', f_);
    first_ = true;
  }
  void close() {
    const bool bad = std::ferror(f_) != 0;
    const bool closed = std::fclose(f_) == 0;
    f_ = nullptr;
    if (bad || !closed) throw std::runtime_error(path_ + ": write failed");
  }

 private:
  std::string path_;
  std::FILE* f_;
  bool first_ = true;
};

void record_bodies(Csv& csv, double t, const std::vector<Body>& bodies) {
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const Body& body = bodies[i];
    const Vec3 v = body.v();
    const Vec3 w = body.omega();
    csv.num(t);
    csv.integer(static_cast<long>(i));
    for (double x : {body.x.x(),
                     body.x.y(),
                     body.x.z(),
                     body.q.w(),
                     body.q.x(),
                     body.q.y(),
                     body.q.z(),
                     v.x(),
                     v.y(),
                     v.z(),
                     w.x(),
                     w.y(),
                     w.z()}) {
      csv.num(x);
    }
    csv.end_row();
  }
}

/// The bodies of trajectory.csv's `body` column: index, name, shape, static or not, mass.
nlohmann::json bodies_json(const Scene& scene) {
  nlohmann::json list = nlohmann::json::array();
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    const Body& body = scene.bodies[i];
    const char* shape = body.shape.kind == Shape::Kind::Sphere ? "sphere"
                        : body.shape.kind == Shape::Kind::Box  ? "box"
                                                               : "plane";
    nlohmann::json b = {
        {"index", i}, {"name", body.name}, {"shape", shape}, {"static", body.is_static}};
    if (!body.is_static) b["mass"] = body.m;
    list.push_back(b);
  }
  return {{"about",
           "the bodies of trajectory.csv: its column body is the index here (docs/outputs.md)"},
          {"bodies", list}};
}

int run_command(const RunOptions& o) {
  Scene scene = load_scene(o.scene);
  apply_step_options(scene, o.step);
  const long steps = step_count(scene, o.step);
  if (o.record_every < 1) throw InputError("--record-every: must be ≥ 1");
  if (o.check_tolerance >= 0.0 && !o.check)
    throw InputError("--check-tolerance: needs --check (the cross-check it judges)");

  std::unique_ptr<OutputDir> dir;
  std::unique_ptr<Csv> trajectory;
  std::unique_ptr<Csv> steps_csv;
  if (!o.out.empty()) {
    dir = std::make_unique<OutputDir>(o.out);
    trajectory = std::make_unique<Csv>(dir->file("trajectory.csv"),
                                       "t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz");
    steps_csv = std::make_unique<Csv>(
        dir->file("steps.csv"),
        o.no_timing
            ? "t,rows,warm_rows,iterations,residual,max_constraint_error,energy"
            : "t,rows,warm_rows,iterations,residual,max_constraint_error,energy,wall_time_s");
  }

  Simulation sim(scene);
  // --check: the same system solved by the direct path (solve_direct, 6.2), started from the
  // iterative solver's lambda; v2 is unique, so it is compared.
  double max_velocity_difference = 0.0;
  double max_pgs_residual = 0.0;
  double max_direct_residual = 0.0;
  long steps_checked = 0;
  long direct_short = 0;
  long direct_unverified = 0;
  long steps_beyond = 0;   // steps whose v2 differs by more than --check-tolerance
  long first_beyond = -1;  // the first of them
  double first_beyond_diff = 0.0;
  if (o.check) {
    SolverSettings direct = scene.solver;
    direct.method = Method::Direct;
    direct.tolerance = 0.0;  // the reference: to the direct path's rounding floor
    sim.set_observer([&, direct](const System& sys, const VecX& lambda, const VecX& v2) {
      VecX lambda_direct = lambda;
      const SolverSummary s = sim.solve_system(sys, sys.b, lambda_direct, direct);
      if (s.termination != Termination::Direct) ++direct_short;
      // Verified as `cbps lcp` verifies: residual ≤ 1e-9 · max(1, ‖b‖∞, max |A_ij|).
      if (!(s.residual <= kLcpSolvedTolerance * scale_of(sys.problem()))) ++direct_unverified;
      const VecX v2_direct = compute_v2(sys, lambda_direct);
      const double difference = v2.size() > 0 ? (v2 - v2_direct).lpNorm<Eigen::Infinity>() : 0.0;
      max_velocity_difference = std::max(max_velocity_difference, difference);
      if (o.check_tolerance >= 0.0 && !(difference <= o.check_tolerance)) {
        if (first_beyond < 0) {
          first_beyond = sim.steps_done();
          first_beyond_diff = difference;
        }
        ++steps_beyond;
      }
      max_pgs_residual =
          std::max(max_pgs_residual,
                   coulomb_residual(sys.problem(), sys.coulomb(), lambda, scene.solver.cfm));
      max_direct_residual = std::max(max_direct_residual, s.residual);
      ++steps_checked;
    });
  }

  const double energy_initial = sim.energy();
  double max_constraint_error = sim.max_constraint_error();
  double max_residual = 0.0;
  long iterations_total = 0;
  int max_rows = 0;
  int max_contacts = 0;
  StageTimes stage_s;  // summed over the steps
  double max_penetration = 0.0;
  double cfm_error = 0.0;           // max eps |lambda|, m/s²
  std::vector<std::string> stages;  // every stage that ran, in order of first appearance
  if (trajectory) record_bodies(*trajectory, 0.0, sim.scene().bodies);

  const auto start = std::chrono::steady_clock::now();
  auto last_progress = start;
  // The divergence guard (Simulation::step) stops the run at the step that failed; what was
  // recorded before it is kept and the summary says where and why.
  std::unique_ptr<DivergenceError> diverged;
  long steps_done = 0;
  for (long s = 0; s < steps; ++s) {
    StepReport r;
    try {
      r = sim.step();
    } catch (const DivergenceError& e) {
      diverged = std::make_unique<DivergenceError>(e);
      break;
    }
    steps_done = s + 1;
    cfm_error = std::max(cfm_error, r.cfm_acceleration_error);
    iterations_total += r.solver.iterations;
    max_residual = std::max(max_residual, r.solver.residual);
    max_constraint_error = std::max(max_constraint_error, r.max_constraint_error);
    max_rows = std::max(max_rows, r.rows);
    max_contacts = std::max(max_contacts, r.contacts);
    stage_s += r.times;
    max_penetration = std::max(max_penetration, r.max_penetration);
    for (const std::string& stage : sim.stages()) {
      if (std::find(stages.begin(), stages.end(), stage) == stages.end()) stages.push_back(stage);
    }
    if (steps_csv) {
      steps_csv->num(sim.time());
      steps_csv->integer(r.rows);
      steps_csv->integer(r.warm_rows);
      steps_csv->integer(r.solver.iterations);
      steps_csv->num(r.solver.residual);
      steps_csv->num(r.max_constraint_error);
      steps_csv->num(sim.energy());
      if (!o.no_timing) steps_csv->num(r.wall_time_s);
      steps_csv->end_row();
    }
    if (trajectory && (s + 1) % o.record_every == 0) {
      record_bodies(*trajectory, sim.time(), sim.scene().bodies);
    }
    const auto now = std::chrono::steady_clock::now();
    if (!o.quiet && now - last_progress > std::chrono::seconds(2)) {
      last_progress = now;
      std::fprintf(stderr,
                   "cbps run: step %ld/%ld (%.0f%%), t = %.3f s, %.1f s elapsed\n",
                   s + 1,
                   steps,
                   100.0 * static_cast<double>(s + 1) / static_cast<double>(steps),
                   sim.time(),
                   std::chrono::duration<double>(now - start).count());
    }
  }
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  nlohmann::json summary;
  summary["scene"] = scene.name;
  nlohmann::json params = nlohmann::json::object();
  for (const auto& [name, value] : scene.parameters) params[name] = value;
  summary["parameters"] = params;
  summary["status"] = diverged ? "diverged" : "completed";
  if (diverged) {
    summary["divergence"] = {{"step", diverged->step()},
                             {"body", diverged->body()},
                             {"row", diverged->row()},
                             {"message", diverged->what()}};
  }
  summary["bodies"] = scene.bodies.size();
  summary["rows"] = max_rows;
  summary["steps"] = steps_done;
  summary["steps_requested"] = steps;
  summary["dt"] = scene.world.dt;
  summary["beta"] = scene.world.beta;
  summary["duration"] = sim.time();
  summary["solver"] = {
      {"method", std::string(to_string(scene.solver.method))},
      {"iterations", scene.solver.iterations},
      {"tolerance", scene.solver.tolerance},
      {"warm_start", scene.solver.warm > 0.0 || scene.solver.warm_factor(RowKind::Friction) > 0.0},
      {"warm", scene.solver.warm},
      {"warm_friction", scene.solver.warm_factor(RowKind::Friction)},
      {"relaxation", scene.solver.relaxation},
      {"order", to_string(scene.solver.order)},
      {"contacts_first", scene.solver.contacts_first},
      {"seed", scene.solver.seed},
      {"cfm", scene.solver.cfm}};
  for (const auto& [key, value] : method_parameters(scene.solver.method, scene.solver.methods))
    summary["solver"]["parameters"][key] = value;
  if (scene.solver.cfm > 0.0) {
    // CFM is never silent: how far the answer is from A lambda = b because of it.
    summary["regularization"] = {{"cfm", scene.solver.cfm},
                                 {"max_acceleration_error", cfm_error},
                                 {"max_velocity_error", cfm_error * scene.world.dt}};
  }
  summary["push"] = scene.world.push == PushMode::Improved ? "improved" : "original";
  summary["contacts"] = {
      {"mu", scene.world.mu},
      {"friction", scene.world.friction == FrictionModel::Coulomb ? "coulomb" : "paper"},
      {"restitution", scene.world.restitution},
      {"persistence", scene.world.contact_persistence},
      {"max_points", max_contacts}};
  summary["max_penetration"] = max_penetration;
  summary["iterations_total"] = iterations_total;
  summary["max_residual"] = max_residual;
  if (!o.no_timing) summary["wall_time_s"] = wall;
  if (!o.no_timing) summary["threads"] = threads_json();  // of this machine, as the times are
  summary["max_constraint_error"] = max_constraint_error;
  summary["energy_initial"] = energy_initial;
  summary["energy_final"] = sim.energy();
  summary["stages"] = stages;
  if (!o.no_timing) {
    summary["stage_times_s"] = {{"broad_phase", stage_s.broad_phase},
                                {"narrow_phase", stage_s.narrow_phase},
                                {"rows", stage_s.rows},
                                {"assembly", stage_s.assembly},
                                {"solve", stage_s.solve},
                                {"integrate", stage_s.integrate}};
  }
  if (o.check) {
    summary["cross_check"] = {{"max_velocity_difference", max_velocity_difference},
                              {"max_pgs_residual", max_pgs_residual},
                              {"max_direct_residual", max_direct_residual},
                              {"direct_stopped_short", direct_short},
                              {"direct_unverified", direct_unverified},
                              {"steps_checked", steps_checked}};
    if (o.check_tolerance >= 0.0) {
      summary["cross_check"]["tolerance"] = o.check_tolerance;
      summary["cross_check"]["steps_beyond_tolerance"] = steps_beyond;
      summary["cross_check"]["first_step_beyond_tolerance"] =
          first_beyond >= 0 ? nlohmann::json(first_beyond) : nlohmann::json(nullptr);
      summary["cross_check"]["passed"] = steps_beyond == 0;
    }
  }
  if (dir) {
    trajectory->close();
    steps_csv->close();
    write_text(dir->file("summary.json"), summary.dump(2) + "\n");
    write_text(dir->file("bodies.json"), bodies_json(scene).dump(2) + "\n");
    dir->commit();
  }
  if (o.json) {
    std::cout << summary.dump(2) << "\n";
  } else {
    std::printf(
        "%s: %s of %.6g s, %s, %s, solver %s%s\n"
        "  iterations %ld in all, max residual %.3g N, max constraint error %.3g m, "
        "max penetration %.3g m\n"
        "  energy %.9g J -> %.9g J, wall time %.3f s\n",
        scene.name.c_str(),
        count_text(steps_done, "step").c_str(),
        scene.world.dt,
        count_text(static_cast<long>(scene.bodies.size()), "body", "bodies").c_str(),
        count_text(max_rows, "row").c_str(),
        std::string(to_string(scene.solver.method)).c_str(),
        diverged ? " (stopped: diverged)" : "",
        iterations_total,
        max_residual,
        max_constraint_error,
        max_penetration,
        energy_initial,
        sim.energy(),
        wall);
    if (o.check) {
      std::printf(
          "  cross-check over %ld steps: max |v2 - v2_direct| %.3g m/s, max residual %.3g N "
          "(direct %.3g N; %ld steps short of its 64 u tolerance, %ld unverified)\n",
          steps_checked,
          max_velocity_difference,
          max_pgs_residual,
          max_direct_residual,
          direct_short,
          direct_unverified);
    }
    if (scene.solver.cfm > 0.0) {
      std::printf(
          "  cfm %.3g kg^-1: the answer misses A lambda = b by up to %.3g m/s^2 (%.3g m/s "
          "per step)\n",
          scene.solver.cfm,
          cfm_error,
          cfm_error * scene.world.dt);
    }
    if (dir) std::printf("  wrote %s\n", o.out.c_str());
  }
  if (steps_beyond > 0) {
    std::fprintf(stderr,
                 "cbps run: --check failed: %ld of %ld steps beyond --check-tolerance %s m/s, "
                 "the first step %ld (t = %.6g s) with max |v2 - v2_direct| = %s m/s%s%s\n",
                 steps_beyond,
                 steps_checked,
                 number_text(o.check_tolerance).c_str(),
                 first_beyond,
                 static_cast<double>(first_beyond) * scene.world.dt,
                 number_text(first_beyond_diff).c_str(),
                 dir ? "; the run's output is in " : "",
                 dir ? o.out.c_str() : "");
  }
  if (diverged) {
    std::string msg = "cbps run: diverged: ";
    msg.append(diverged->what());
    if (dir) {
      msg.append("; what was recorded before that step is in ");
      msg.append(o.out);
    }
    std::fprintf(stderr, "%s\n", msg.c_str());
    return 1;
  }
  return steps_beyond > 0 ? 1 : 0;
}

}  // namespace

void register_run(CLI::App& app, Action& run) {
  auto* cmd = app.add_subcommand("run", "simulate a scene");
  auto o = std::make_shared<RunOptions>();
  add_scene_options(cmd, o->scene);
  add_step_options(cmd, o->step);
  cmd->add_option("--out",
                  o->out,
                  "folder for summary.json, trajectory.csv, steps.csv, bodies.json (the body "
                  "names of trajectory.csv) and cbps-manifest.json (docs/outputs.md)");
  cmd->add_option("--record-every", o->record_every, "record the trajectory every K steps")
      ->check(positive());
  cmd->add_flag("--json", o->json, "print the summary as JSON on stdout");
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
  cmd->add_flag("--quiet", o->quiet, "no progress lines on stderr");
  cmd->add_flag("--no-timing",
                o->no_timing,
                "leave wall times out of summary.json and steps.csv, so that the same inputs "
                "give byte-identical outputs");
  cmd->callback([&run, o] { run = [o] { return run_command(*o); }; });
}

}  // namespace cbps::cli
