// cbps converge SCENE|PROBLEM --solvers LIST --out DIR: error against iterations and run time.
//
// One system (a scene's step K, or a stored problem) is solved by each solver of LIST from the
// same guess; after every sweep the command records the wall time of the sweeps so far (the
// recording itself is not timed), the natural-map residual (6.2), the error against the direct
// solution (lambda where A is positive definite, else only the unique v2 of 12.3.1) and the QP
// objective ½ λᵀ A λ − bᵀ λ. The direct path (6.2) is one point: its time and residual.
// With --record-every K only every K-th sweep (and the guess and the last sweep) is written;
// the milestones of the summary are still taken from every sweep.
// tao:TYPE (a build with PETSc, docs/distributed.md) runs TAO in this process from lambda = 0;
// its monitor hands each TAO iteration here as a "sweep" (time: since solve_tao was called,
// distributing A included, less the monitor's own time).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>

#include "cbps/base/error.hpp"
#include "cbps/io/stored_problem.hpp"
#include "cbps/solvers/direct.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/step/simulation.hpp"
#include "cbps/studies/solver_spec.hpp"
#include "common.hpp"
#include "tao_solvers.hpp"

namespace cbps::cli {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

/// The residuals the summary reports the first sweep and time for (N).
constexpr double kMilestones[] = {1e-3, 1e-6, 1e-10};

struct ConvergeOptions {
  SceneOptions scene;
  StepOptions step;
  std::string solvers = "pgs,psor:1.3,sgs,jacobi:0.7,matrix-free,direct";
  long at_step = 0;
  int iterations = 100000;
  int record_every = 1;
  double tolerance = 1e-10;
  double time_limit = 10.0;
  std::string out;
  bool json = false;
  bool quiet = false;
  bool plot = true;
};

/// The system under study and what is known about its answer.
struct Study {
  std::string name;
  StoredProblem stored;  ///< A, b, cmin, cmax; J, Minv, v1, fext, dt when known; cfm
  SpMat A_solved;        ///< with_cfm(A, cfm): the matrix every solver works on
  /// The previous step's lambda by row id as it was (scenes after step 0), else 0, N: each
  /// spec's warm-start factors scale it once (7).
  VecX previous_lambda;
  VecX lambda_star, v2_star;
  bool lambda_unique = false;  ///< A positive definite (a Cholesky factorization exists)
  bool has_bodies() const { return stored.has_bodies(); }
  /// The problem the solvers are handed (A = J Minv Jᵀ; each applies the cfm itself).
  BoxedProblem problem() const { return stored.problem(); }
  /// The problem with A + eps E: the one whose residual is measured.
  BoxedProblem solved() const { return BoxedProblem{A_solved, stored.b, stored.cmin, stored.cmax}; }
  VecX v2(const VecX& lambda) const {
    return compute_v2(stored.v1, stored.Minv, stored.J, lambda, stored.fext, stored.dt);
  }
};

bool is_problem(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) return true;
  return fs::path(path).extension() == ".dat";
}

Study study_of_problem(const std::string& path) {
  Study s;
  s.name = path;
  s.stored = read_problem(path);
  // The direct path (the reference) solves the QP of 6.2, which needs a symmetric A.
  require_symmetric(s.stored, "converge " + path);
  s.A_solved = with_cfm(s.stored.A, s.stored.cfm);
  s.previous_lambda = VecX::Zero(s.stored.rows());
  return s;
}

Study study_of_scene(const ConvergeOptions& o) {
  Scene scene = load_scene(o.scene);
  apply_step_options(scene, o.step);
  if (scene.world.friction == FrictionModel::Coulomb && scene.world.mu > 0.0)
    throw InputError(o.scene.scene +
                     ": Coulomb friction bounds move with lambda, so the system is not one boxed "
                     "problem; study it with friction=paper");
  Simulation sim(scene);
  for (long k = 0; k < o.at_step; ++k) sim.step();
  const System& sys = sim.assemble();
  Study s;
  s.name = o.scene.scene;
  s.stored = stored_problem(sys, scene.solver.cfm);
  s.A_solved = with_cfm(s.stored.A, s.stored.cfm);
  s.previous_lambda = sim.last_lambda(sys);
  return s;
}

/// The reference: the direct path from lambda = 0; lambda is unique when A is numerically
/// definite, as the direct path judges it (CHOLMOD's rcond ≥ kDefiniteRcond). A singular A can
/// still factor in floating point: four contacts per face give rcond ~1e-17.
SolverSummary solve_reference(Study& s) {
  s.lambda_star = VecX::Zero(s.stored.rows());
  // Handed J and Minv, the direct path factors in body space (M + Jᵀ D⁻¹ J); on A alone it
  // would factor A + D in row space, 100× slower on the base-20 pyramid (0.2 s against 22 s).
  SolverOptions options;
  options.method = Method::Direct;
  options.cfm = s.stored.cfm;
  const SolverSummary d = solve(s.problem(), s.lambda_star, options);
  s.lambda_unique = cholesky_rcond(s.A_solved) >= kDefiniteRcond;
  if (s.has_bodies()) s.v2_star = s.v2(s.lambda_star);
  return d;
}

struct Sample {
  int iteration = 0;
  double time_s = 0.0, residual = 0.0, lambda_error = NAN, velocity_error = NAN, objective = 0.0;
};

/// The first sweep and time at which the residual reached each of kMilestones, from every
/// sweep (recorded or not); iteration −1 while not reached.
struct Milestone {
  int iteration = -1;
  double time_s = 0.0;
};

struct Run {
  SolverSpec spec;
  std::vector<Sample> samples;  ///< the recorded ones (the guess, every K-th sweep, the last)
  std::string stopped;          ///< why the sweeps ended
  Milestone reached[std::size(kMilestones)];
  void reach(int iteration, double time_s, double residual) {
    for (std::size_t i = 0; i < std::size(kMilestones); ++i)
      if (reached[i].iteration < 0 && residual <= kMilestones[i]) reached[i] = {iteration, time_s};
  }
};

Sample measure(const Study& s, const VecX& lambda, int iteration, double time_s) {
  Sample m;
  m.iteration = iteration;
  m.time_s = time_s;
  const VecX Alambda = s.A_solved * lambda;
  m.residual = natural_map_residual(s.solved(), lambda);
  m.objective = 0.5 * lambda.dot(Alambda) - s.stored.b.dot(lambda);  // (6.2)
  if (s.lambda_unique) m.lambda_error = (lambda - s.lambda_star).lpNorm<Eigen::Infinity>();
  if (s.has_bodies()) m.velocity_error = (s.v2(lambda) - s.v2_star).lpNorm<Eigen::Infinity>();
  return m;
}

Run run_iterative(const Study& s, const SolverSpec& spec, const ConvergeOptions& o) {
  if (needs_jacobian(spec.method) && !s.stored.has_jacobian())
    throw InputError("--solvers " + spec.text + ": " + s.name +
                     " has no J and Minv (a Siconos file); " + std::string(to_string(spec.method)) +
                     " needs them");
  if (spec.contacts_first && s.stored.kinds.empty())
    throw InputError("--solvers " + spec.text + ": " + s.name +
                     " has no row kinds (no labels.json); contacts_first needs a scene or a "
                     "`cbps matrices` folder");
  Run run;
  run.spec = spec;
  // The spec's warm-start factors on the previous step's lambda (7), row by row, as `cbps run
  // --solver SPEC` starts the step: the spec's factors replace the scene's (apply_solver_spec).
  SolverSettings factors;
  apply_solver_spec(spec, factors);
  VecX lambda = VecX::Zero(s.stored.rows());
  for (std::size_t k = 0; k < s.stored.kinds.size(); ++k) {
    const auto row = static_cast<Eigen::Index>(k);
    lambda(row) = warm_guess(s.previous_lambda(row), factors.warm_factor(s.stored.kinds[k]));
  }
  run.samples.push_back(measure(s, lambda, 0, 0.0));
  run.reach(0, 0.0, run.samples.back().residual);
  // The last sweep's iterate when it was not recorded, to record it at the end.
  VecX last_lambda;
  int last_k = 0;
  double last_time = 0.0;
  // The solvers themselves, as `cbps run` uses them; they time their sweeps and hand each
  // iterate here, outside the clock.
  SolverOptions options = study_options(spec, o.iterations, s.stored.cfm);
  options.seed = o.step.seed >= 0 ? std::uint64_t(o.step.seed) : 0u;
  options.after_sweep = [&](int k, const VecX& l, double time_s) {
    const double residual = natural_map_residual(s.solved(), l);
    run.reach(k, time_s, residual);
    if (!std::isfinite(residual)) run.stopped = "non-finite values";
    if (residual <= o.tolerance) run.stopped = "residual tolerance";
    if (run.stopped.empty() && time_s >= o.time_limit) run.stopped = "time limit";
    const bool record = k % o.record_every == 0 || !run.stopped.empty() || k >= o.iterations;
    Sample m;
    if (record) {
      m = measure(s, l, k, time_s);
      run.samples.push_back(m);
    } else {
      m.residual = residual;
      last_lambda = l;
    }
    last_k = k;
    last_time = time_s;
    if (!o.quiet && k % 1000 == 0)
      std::fprintf(stderr,
                   "converge: %s: %d sweeps, %.2f s, residual %.3g N\n",
                   spec.text.c_str(),
                   k,
                   time_s,
                   m.residual);
    return run.stopped.empty();
  };
  solve(s.problem(), lambda, options);
  if (run.stopped.empty()) run.stopped = "iteration limit";
  if (run.samples.back().iteration != last_k)  // the solver stopped on its own
    run.samples.push_back(measure(s, last_lambda, last_k, last_time));
  return run;
}

/// tao:TYPE from lambda = 0 (TAO has no warm start here): every TAO iteration as a sweep, by
/// the monitor of solve_tao, which also gives the natural-map residual on PETSc's vectors; the
/// same stops as run_iterative (tolerance by solve_tao's own test, time limit and non-finite
/// values by the monitor).
Run run_tao(const Study& s,
            const SolverSpec& spec,
            const ConvergeOptions& o,
            const TaoInProcess& tao) {
  Run run;
  run.spec = spec;
  run.samples.push_back(measure(s, VecX::Zero(s.stored.rows()), 0, 0.0));
  run.reach(0, 0.0, run.samples.back().residual);
  VecX last_lambda;  // the last iteration's, when it was not recorded
  int last_k = 0;
  double last_time = 0.0, last_residual = run.samples.back().residual;
  const distributed::TaoMonitor monitor = [&](const distributed::TaoIterate& at, const VecX& l) {
    if (at.iteration <= last_k) return true;  // TAO's start (the guess row) or a repeat
    run.reach(at.iteration, at.time_s, at.residual);
    if (!std::isfinite(at.residual)) run.stopped = "non-finite values";
    if (run.stopped.empty() && at.time_s >= o.time_limit) run.stopped = "time limit";
    const bool record = at.iteration % o.record_every == 0 || !run.stopped.empty() ||
                        at.iteration >= o.iterations || at.residual <= o.tolerance;
    if (record) {
      Sample m = measure(s, l, at.iteration, at.time_s);
      m.residual = at.residual;  // the one TAO's stopping test saw
      run.samples.push_back(m);
    } else {
      last_lambda = l;
    }
    last_k = at.iteration;
    last_time = at.time_s;
    last_residual = at.residual;
    if (!o.quiet && at.iteration % 1000 == 0)
      std::fprintf(stderr,
                   "converge: %s: %d iterations, %.2f s, residual %.3g N\n",
                   spec.text.c_str(),
                   at.iteration,
                   at.time_s,
                   at.residual);
    return run.stopped.empty();
  };
  const TaoRun r = tao.solve(s.solved(), spec.tao, o.iterations, o.tolerance, monitor);
  if (run.stopped.empty())
    run.stopped = r.residual <= o.tolerance       ? "residual tolerance"
                  : r.reason == "DIVERGED_MAXITS" ? "iteration limit"
                                                  : "TAO " + r.reason;
  if (run.samples.back().iteration != last_k) {  // TAO stopped on its own
    Sample m = measure(s, last_lambda, last_k, last_time);
    m.residual = last_residual;
    run.samples.push_back(m);
  }
  return run;
}

Run run_direct(const Study& s, const SolverSpec& spec) {
  Run run;
  run.spec = spec;
  VecX lambda = VecX::Zero(s.stored.rows());
  const auto start = Clock::now();
  // solve() forms A + eps E and hands on J and Minv (body space).
  const SolverSummary d = solve(s.problem(), lambda, study_options(spec, 1, s.stored.cfm));
  const double time_s = std::chrono::duration<double>(Clock::now() - start).count();
  run.samples.push_back(measure(s, lambda, std::max(1, d.iterations), time_s));
  run.reach(run.samples.back().iteration, time_s, run.samples.back().residual);
  run.stopped = to_string(d.termination);
  return run;
}

std::string number(double x) {
  if (std::isnan(x)) return "";
  std::ostringstream out;
  out.precision(9);
  out << x;
  return out.str();
}

nlohmann::json json_or_null(double x) {
  return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr);
}

/// Runs the plot script on the CSV; true if it wrote its files.
bool plot(const std::string& csv, const std::string& prefix, const std::string& title) {
  return run_python_script("scripts/plot_convergence.py", {csv, prefix, "--title", title});
}

int converge_command(const ConvergeOptions& o) {
  const std::vector<SolverSpec> specs = parse_cli_solver_list(o.solvers, "--solvers");
  const TaoInProcess tao(specs, "converge --solvers");  // PETSc once, for every tao spec
  const bool problem = is_problem(o.scene.scene);
  if (problem && !o.scene.params.empty())
    throw InputError("--param: parameters apply to built-in scenes, not to the problem " +
                     o.scene.scene);
  Study s = problem ? study_of_problem(o.scene.scene) : study_of_scene(o);
  std::unique_ptr<OutputDir> dir;
  if (!o.out.empty()) dir = std::make_unique<OutputDir>(o.out);
  if (!o.quiet)
    std::fprintf(stderr,
                 "converge: %s: %ld rows, reference by the direct path\n",
                 s.name.c_str(),
                 static_cast<long>(s.stored.rows()));
  const SolverSummary reference = solve_reference(s);

  std::vector<Run> runs;
  for (const SolverSpec& spec : specs) {
    runs.push_back(!spec.tao.empty()            ? run_tao(s, spec, o, tao)
                   : !is_iterative(spec.method) ? run_direct(s, spec)
                                                : run_iterative(s, spec, o));
    if (!o.quiet) {
      const Sample& last = runs.back().samples.back();
      std::fprintf(stderr,
                   "converge: %s: %s after %s, %.3g s, residual %.3g N\n",
                   spec.text.c_str(),
                   runs.back().stopped.c_str(),
                   count_text(last.iteration, "sweep").c_str(),
                   last.time_s,
                   last.residual);
    }
  }

  // A step its guess already solves (step 0 of a chain released from rest: b = 0, lambda = 0)
  // shows nothing: every solver "converges" in 0 sweeps. Say so, on stderr and in the summary.
  std::vector<std::string> solved_by_guess;
  double guess_residual = 0.0;
  for (const Run& run : runs) {
    if (!is_iterative(run.spec.method)) continue;
    const double r0 = run.samples.front().residual;
    guess_residual = std::max(guess_residual, r0);
    if (r0 <= o.tolerance) solved_by_guess.push_back(run.spec.text);
  }
  nlohmann::json warnings = nlohmann::json::array();
  if (!solved_by_guess.empty()) {
    std::string names;
    for (const std::string& n : solved_by_guess) names += (names.empty() ? "" : ", ") + n;
    const std::string where = problem ? s.name : s.name + " step " + std::to_string(o.at_step);
    const std::string text =
        where + " is already solved by the initial guess of " + names +
        " (residual at the guess <= tolerance " + number_text(o.tolerance) +
        " N), so they reach it at sweep 0 and show no convergence" +
        (problem ? std::string("") : "; study a later --step (e.g. --step 10)");
    warnings.push_back(text);
    std::fprintf(stderr, "cbps: warning: converge: %s\n", text.c_str());
  }

  nlohmann::json summary;
  summary["problem"] = s.name;
  summary["rows"] = s.stored.rows();
  summary["cfm"] = s.stored.cfm;  // the problem studied is A + eps E (kg^-1; 0: A itself)
  summary["step"] = problem ? nlohmann::json(nullptr) : nlohmann::json(o.at_step);
  summary["lambda_unique"] = s.lambda_unique;
  summary["reference"] = {{"residual", reference.residual},
                          {"termination", to_string(reference.termination)}};
  summary["tolerance"] = o.tolerance;
  summary["record_every"] = o.record_every;
  summary["solved_by_initial_guess"] = !solved_by_guess.empty();
  summary["warnings"] = warnings;
  summary["solvers"] = nlohmann::json::array();
  std::ostringstream csv;
  csv << "solver,iteration,time_s,residual,lambda_error,velocity_error,objective\n";
  for (const Run& run : runs) {
    for (const Sample& m : run.samples) {
      csv << run.spec.text << ',' << m.iteration << ',' << number(m.time_s) << ','
          << number(m.residual) << ',' << number(m.lambda_error) << ',' << number(m.velocity_error)
          << ',' << number(m.objective) << '\n';
    }
    nlohmann::json j;
    const Sample& last = run.samples.back();
    j["solver"] = run.spec.text;
    j["method"] = run.spec.tao.empty() ? std::string(to_string(run.spec.method)) : "tao";
    j["relaxation"] = run.spec.relaxation;
    j["order"] = to_string(run.spec.order);
    j["warm_start"] = run.spec.warm > 0.0 || run.spec.warm_friction.value_or(run.spec.warm) > 0.0;
    j["warm"] = run.spec.warm;
    j["warm_friction"] = run.spec.warm_friction.value_or(run.spec.warm);
    j["contacts_first"] = run.spec.contacts_first;
    j["stopped"] = run.stopped;
    j["guess_residual"] = json_or_null(run.samples.front().residual);
    j["samples"] = run.samples.size();
    j["iterations"] = last.iteration;
    j["time_s"] = last.time_s;
    j["residual"] = json_or_null(last.residual);
    j["lambda_error"] = json_or_null(last.lambda_error);
    j["velocity_error"] = json_or_null(last.velocity_error);
    nlohmann::json reached = nlohmann::json::object();
    for (std::size_t i = 0; i < std::size(kMilestones); ++i) {
      const Milestone& at = run.reached[i];
      reached[number(kMilestones[i])] =
          at.iteration < 0 ? nlohmann::json(nullptr)
                           : nlohmann::json({{"iterations", at.iteration}, {"time_s", at.time_s}});
    }
    j["reached"] = reached;
    summary["solvers"].push_back(j);
  }

  if (dir) {
    write_text(dir->file("convergence.csv"), csv.str());
    write_text(dir->file("summary.json"), summary.dump(2) + "\n");
    if (o.plot) {
      const std::string title = s.name + " (" + std::to_string(s.stored.rows()) + " rows)";
      if (!plot(dir->file("convergence.csv"), dir->file("convergence"), title))
        throw ComputationError("converge: the plot script failed (" +
                               std::string(CBPS_PLOT_PYTHON) +
                               " scripts/plot_convergence.py); "
                               "nothing written (--no-plot skips the plot)");
    }
    dir->commit();
  }
  if (o.json) {
    std::printf("%s\n", summary.dump(2).c_str());
    return 0;
  }
  std::printf("%s: %ld rows, lambda %s; direct reference residual %.3g N\n",
              s.name.c_str(),
              static_cast<long>(s.stored.rows()),
              s.lambda_unique ? "unique (A definite)" : "not unique (A singular): v2 compared",
              reference.residual);
  std::printf("%-24s %10s %11s %11s  %-18s %-18s %-18s\n",
              "solver",
              "sweeps",
              "time (s)",
              "residual",
              "to 1e-3 N",
              "to 1e-6 N",
              "to 1e-10 N");
  for (const nlohmann::json& j : summary["solvers"]) {
    std::printf("%-24s %10d %11.3g %11.3g ",
                j["solver"].get<std::string>().c_str(),
                j["iterations"].get<int>(),
                j["time_s"].get<double>(),
                j["residual"].is_null() ? NAN : j["residual"].get<double>());
    for (const double target : kMilestones) {
      const nlohmann::json& at = j["reached"][number(target)];
      char cell[64] = "-";
      if (!at.is_null())
        std::snprintf(cell,
                      sizeof cell,
                      "%d / %.3g s",
                      at["iterations"].get<int>(),
                      at["time_s"].get<double>());
      std::printf(" %-18s", cell);
    }
    std::printf("\n");
  }
  if (!o.out.empty()) std::printf("wrote %s\n", o.out.c_str());
  return 0;
}

}  // namespace

void register_converge(CLI::App& app, Action& run) {
  auto* cmd = app.add_subcommand(
      "converge",
      "error against iterations and run time for each solver on one system (a scene's step or "
      "a stored problem): convergence.csv, summary.json, convergence.png/.svg");
  auto o = std::make_shared<ConvergeOptions>();
  cmd->add_option("SCENE",
                  o->scene.scene,
                  "built-in scene, JSON scene file, `cbps matrices` folder or Siconos .dat file")
      ->required();
  cmd->add_option("--param", o->scene.params, "NAME=VALUE: a built-in scene's parameter");
  cmd->add_option("--solvers",
                  o->solvers,
                  "comma-separated solver specs (the solvers listed below), e.g. "
                  "pgs,psor:1.3,sgs,jacobi:0.7,pgs:order=random,block-pgs,matrix-free,"
                  "pgs-nesterov,apgd,direct,tao:bqpip (tao:TYPE only in a build with PETSc; "
                  "default: " +
                      o->solvers + ")");
  cmd->footer(solver_spec_help() + tao_spec_help());
  cmd->add_option("--step",
                  o->at_step,
                  "scenes: study the system of this step (0: the first; later steps start "
                  "from the previous step's lambda unless a spec says warm=off)")
      ->transform(step_index());
  cmd->add_option("--dt", o->step.dt, "scenes: time step in s");
  cmd->add_option("--push", o->step.push, "scenes: original | improved")
      ->check(CLI::IsMember({"original", "improved"}));
  cmd->add_option("--iterations",
                  o->iterations,
                  "max sweeps per solver; TAO's iterations for tao:TYPE (default 100000)")
      ->check(positive());
  cmd->add_option("--tolerance", o->tolerance, "stop at this residual, N (default 1e-10)")
      ->check(non_negative());
  cmd->add_option("--record-every",
                  o->record_every,
                  "write one sample every K sweeps to convergence.csv (the guess and the last "
                  "sweep always; the summary's milestones still see every sweep; default 1)")
      ->check(positive());
  cmd->add_option("--time-limit", o->time_limit, "max sweep time per solver, s (default 10)")
      ->check(positive());
  cmd->add_option("--seed", o->step.seed, "seed of random row orders, >= 0 (default 0)")
      ->check(non_negative());
  cmd->add_option("--out", o->out, "write convergence.csv, summary.json and the plot here");
  cmd->add_flag("--json", o->json, "print the summary as JSON");
  cmd->add_flag("--quiet", o->quiet, "no progress on stderr");
  cmd->add_flag_callback(
      "--no-plot", [o] { o->plot = false; }, "write no convergence.png/.svg");
  cmd->callback([&run, o] { run = [o] { return converge_command(*o); }; });
}

}  // namespace cbps::cli
