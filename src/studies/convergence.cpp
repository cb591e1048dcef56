#include "cbps/studies/convergence.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "cbps/base/error.hpp"
#include "cbps/io/json_numbers.hpp"
#include "cbps/scene/scene.hpp"
#include "cbps/solvers/exact/direct.hpp"
#include "cbps/solvers/peers/peers.hpp"
#include "cbps/step/simulation.hpp"
#include "cbps/studies/run.hpp"
#include "cbps/system/cone_problem.hpp"

namespace cbps {

namespace {

using Clock = std::chrono::steady_clock;

/// A number of convergence.csv: 9 significant digits, empty for NaN (not measured).
std::string csv_number(double x) {
  if (std::isnan(x)) return "";
  std::ostringstream out;
  out.precision(9);
  out << x;
  return out.str();
}

}  // namespace

std::string milestone_key(double residual) { return csv_number(residual); }

ConvergenceSystem convergence_system(const std::string& path) {
  ConvergenceSystem s;
  s.name = path;
  s.stored = read_problem(path);
  // The direct path (the reference) solves the QP of 6.2, which needs a symmetric A.
  require_symmetric(s.stored, "converge " + path);
  s.previous_lambda = VecX::Zero(s.stored.rows());
  return s;
}

ConvergenceSystem convergence_system(Scene scene,
                                     const std::string& name,
                                     long at_step,
                                     bool quiet) {
  if (scene.world.friction == FrictionLaw::CoulombBox && scene.world.mu > 0.0)
    throw InputError(name +
                     ": Coulomb friction bounds move with lambda, so the system is not one boxed "
                     "problem; study it with friction=paper");
  // The steps before the one studied need a method that solves cones (the boxed methods refuse
  // them): the scene's own if it does, else the exact path (docs/cones.md).
  if (is_cone(scene.world.friction) && scene.world.mu > 0.0 &&
      !takes_cone_law(scene.solver.method, scene.world.friction))
    scene.solver.method = kExactMethod;
  Simulation sim(scene);
  step_to(sim, at_step, "converge", quiet);
  const System sys = sim.build_system();  // with A, whatever the scene's method reads
  ConvergenceSystem s;
  s.name = name;
  s.step = at_step;
  s.stored = stored_problem(sys, scene.solver.cfm);
  s.previous_lambda = sim.last_lambda(sys);
  return s;
}

SolverSummary solve_reference(ConvergenceSystem& s) {
  s.lambda_star = VecX::Zero(s.stored.rows());
  // Handed J and Minv, the direct path factors in body space (M + Jᵀ D⁻¹ J); on A alone it
  // would factor A + D in row space, 100× slower on the base-20 pyramid (0.2 s against 22 s).
  SolverOptions options;
  options.method = kExactMethod;
  options.tolerance = 0.0;  // the reference: to the direct path's rounding floor
  options.cfm = s.stored.cfm;
  const SolverSummary d = solve(s.problem(), s.lambda_star, options);
  s.lambda_unique = cholesky_rcond(with_cfm(s.stored.A, s.stored.cfm)) >= kDefiniteRcond;
  // On cones λ* is unique for the relaxation with A definite (a strictly convex QP), and only if
  // the direct path verified it; Coulomb's law may have several answers even then.
  if (!s.stored.cones.empty())
    s.lambda_unique = s.lambda_unique && s.stored.cones.law == FrictionLaw::Relaxation &&
                      d.termination == Termination::Direct;
  if (s.has_bodies()) s.v2_star = s.v2(s.lambda_star);
  return d;
}

ConvergenceSample measure(const ConvergenceSystem& s,
                          const VecX& lambda,
                          int iteration,
                          double time_s) {
  ConvergenceSample m;
  m.iteration = iteration;
  m.time_s = time_s;
  const VecX Alambda = s.stored.A * lambda + s.stored.cfm * lambda;  // (A + eps E) λ
  m.residual = s.residual(lambda);
  m.objective = 0.5 * lambda.dot(Alambda) - s.stored.b.dot(lambda);  // (6.2)
  if (s.lambda_unique) m.lambda_error = (lambda - s.lambda_star).lpNorm<Eigen::Infinity>();
  if (s.has_bodies()) m.velocity_error = (s.v2(lambda) - s.v2_star).lpNorm<Eigen::Infinity>();
  return m;
}

ConvergenceRun run_iterative(const ConvergenceSystem& s,
                             const SolverSpec& spec,
                             const ConvergenceLimits& limits) {
  if (needs_jacobian(spec.method) && !s.stored.has_jacobian())
    throw InputError("--solvers " + spec.text + ": " + s.name +
                     " has no J and Minv (a Siconos file); " + std::string(to_string(spec.method)) +
                     " needs them");
  if (spec.contacts_first && s.stored.kinds.empty())
    throw InputError("--solvers " + spec.text + ": " + s.name +
                     " has no row kinds (no labels.json); contacts_first needs a scene or a "
                     "`cbps matrices` folder");
  ConvergenceRun run;
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
  SolverOptions options = study_options(spec, limits.iterations, s.stored.cfm);
  options.seed = limits.seed;
  double next_progress = 1.0;  // s of sweep time
  options.after_sweep = [&](int k, const VecX& l, double time_s) {
    const double residual = s.residual(l);
    run.reach(k, time_s, residual);
    if (!std::isfinite(residual)) run.stopped = "non-finite values";
    if (residual <= limits.tolerance) run.stopped = "residual tolerance";
    if (run.stopped.empty() && time_s >= limits.time_limit) run.stopped = "time limit";
    const bool record =
        recorded_sweep(k, limits.record_every) || !run.stopped.empty() || k >= limits.iterations;
    if (record)
      run.samples.push_back(measure(s, l, k, time_s));
    else
      last_lambda = l;
    last_k = k;
    last_time = time_s;
    // Progress by time, not by sweeps (a sweep of a large problem can take seconds): a line
    // at most every second of sweep time.
    if (limits.progress && time_s >= next_progress) {
      limits.progress(spec, k, time_s, residual);
      next_progress = time_s + 1.0;
    }
    return run.stopped.empty();
  };
  solve(s.problem(), lambda, options);
  if (run.stopped.empty()) run.stopped = "iteration limit";
  if (run.samples.back().iteration != last_k)  // the solver stopped on its own
    run.samples.push_back(measure(s, last_lambda, last_k, last_time));
  return run;
}

bool recorded_sweep(int k, int record_every) {
  if (record_every != kRecordLog) return k % record_every == 0;
  if (k <= 100) return true;
  return std::floor(100.0 * std::log10(static_cast<double>(k))) !=
         std::floor(100.0 * std::log10(static_cast<double>(k - 1)));
}

ConvergenceRun run_exact(const ConvergenceSystem& s,
                         const SolverSpec& spec,
                         const ConvergenceLimits& limits) {
  ConvergenceRun run;
  run.spec = spec;
  VecX lambda = VecX::Zero(s.stored.rows());
  const auto start = Clock::now();
  // solve() applies the cfm and hands on J and Minv (body space).
  SolverOptions options = study_options(spec, 1, s.stored.cfm);
  options.time_limit = limits.time_limit;
  const SolverSummary d = solve(s.problem(), lambda, options);
  const double time_s = std::chrono::duration<double>(Clock::now() - start).count();
  // Its own count, as `cbps lcp` reports it (interior iterations, pivots; 0 for a guess that
  // already solved it).
  run.samples.push_back(measure(s, lambda, d.iterations, time_s));
  run.reach(run.samples.back().iteration, time_s, run.samples.back().residual);
  // The verdict is the study's tolerance, as for every other method: a direct solve that stops
  // short of its own rounding floor but below that tolerance reached it (it said "stopped short
  // of its tolerance" there).
  run.stopped =
      d.termination == Termination::NotConverged && run.samples.back().residual <= limits.tolerance
          ? "residual tolerance"
          : to_string(d.termination);
  return run;
}

ConvergenceRun run_peer(const ConvergenceSystem& s,
                        const SolverSpec& spec,
                        const ConvergenceLimits& limits) {
  ConvergenceRun run;
  run.spec = spec;
  run.final_point_only = true;
  VecX lambda = VecX::Zero(s.stored.rows());
  run.samples.push_back(measure(s, lambda, 0, 0.0));
  SolverOptions options = study_options(spec, limits.iterations, s.stored.cfm);
  options.tolerance = limits.tolerance;
  options.time_limit = limits.time_limit;  // a Siconos peer's child is killed at it
  const SolverSummary d = solve(s.problem(), lambda, options);
  // The peer's own conversion and solve, without cbps's verdict or the process around Siconos.
  const double time_s = d.convert_time_s + d.peer_solve_time_s;
  run.samples.push_back(measure(s, lambda, std::max(1, d.iterations), time_s));
  run.reach(run.samples.back().iteration, time_s, run.samples.back().residual);
  run.stopped = "final point only (the peer exposes no iterates): " + to_string(d.termination) +
                "; peer: " + d.peer_status;
  run.peer_status = d.peer_status;
  run.convert_time_s = d.convert_time_s;
  return run;
}

ConvergenceRun run_spec(const ConvergenceSystem& s,
                        const SolverSpec& spec,
                        const ConvergenceLimits& limits,
                        const ConvergenceTao& tao) {
  if (!spec.tao.empty()) {
    if (!tao) throw std::logic_error("run_spec: " + spec.text + " given, but no TAO runner");
    return tao(s, spec, limits);
  }
  return is_peer(spec.method)         ? run_peer(s, spec, limits)
         : !is_iterative(spec.method) ? run_exact(s, spec, limits)
                                      : run_iterative(s, spec, limits);
}

std::string solved_by_guess_warning(const ConvergenceSystem& s,
                                    const std::vector<ConvergenceRun>& runs,
                                    double tolerance) {
  // A step its guess already solves (step 0 of a chain released from rest: b = 0, lambda = 0)
  // shows nothing: every solver "converges" in 0 sweeps.
  std::string names;
  for (const ConvergenceRun& run : runs) {
    if (!is_iterative(run.spec.method) || run.final_point_only ||
        !(run.samples.front().residual <= tolerance))
      continue;
    names += (names.empty() ? "" : ", ") + run.spec.text;
  }
  if (names.empty()) return "";
  const std::string where = s.step ? s.name + " step " + std::to_string(*s.step) : s.name;
  return where + " is already solved by the initial guess of " + names +
         " (residual at the guess <= tolerance " + number_text(tolerance) +
         " N), so they reach it at sweep 0 and show no convergence" +
         (s.step ? "; study a later --step (e.g. --step 10)" : "");
}

nlohmann::json convergence_summary(const ConvergenceSystem& s,
                                   const SolverSummary& reference,
                                   const std::vector<ConvergenceRun>& runs,
                                   const ConvergenceLimits& limits,
                                   const std::string& warning) {
  nlohmann::json summary;
  summary["problem"] = s.name;
  summary["rows"] = s.stored.rows();
  summary["cfm"] = s.stored.cfm;  // the problem studied is A + eps E (kg^-1; 0: A itself)
  summary["step"] = s.step ? nlohmann::json(*s.step) : nlohmann::json(nullptr);
  summary["lambda_unique"] = s.lambda_unique;
  summary["cone"] = s.stored.cones.empty()
                        ? nlohmann::json(nullptr)
                        : nlohmann::json{{"law", cone_law_name(s.stored.cones.law)},
                                         {"contacts", s.stored.cones.contacts()}};
  summary["reference"] = {{"residual", reference.residual},
                          {"termination", to_string(reference.termination)}};
  summary["tolerance"] = limits.tolerance;
  summary["record_every"] = limits.record_every == kRecordLog ? nlohmann::json("log")
                                                              : nlohmann::json(limits.record_every);
  summary["solved_by_initial_guess"] = !warning.empty();
  summary["warnings"] = nlohmann::json::array();
  if (!warning.empty()) summary["warnings"].push_back(warning);
  summary["solvers"] = nlohmann::json::array();
  for (const ConvergenceRun& run : runs) {
    nlohmann::json j;
    const ConvergenceSample& last = run.samples.back();
    j["solver"] = run.spec.text;
    j["method"] = run.spec.tao.empty() ? std::string(to_string(run.spec.method)) : "tao";
    j["relaxation"] = run.spec.relaxation;
    j["order"] = to_string(run.spec.order);
    j["warm_start"] = run.spec.warm > 0.0 || run.spec.warm_friction.value_or(run.spec.warm) > 0.0;
    j["warm"] = run.spec.warm;
    j["warm_friction"] = run.spec.warm_friction.value_or(run.spec.warm);
    j["contacts_first"] = run.spec.contacts_first;
    j["stopped"] = run.stopped;
    j["final_point_only"] = run.final_point_only;
    j["peer_status"] =
        run.peer_status.empty() ? nlohmann::json(nullptr) : nlohmann::json(run.peer_status);
    j["convert_time_s"] =
        run.final_point_only ? nlohmann::json(run.convert_time_s) : nlohmann::json(nullptr);
    j["guess_residual"] = number_json(run.samples.front().residual);
    j["samples"] = run.samples.size();
    j["iterations"] = last.iteration;
    j["time_s"] = last.time_s;
    j["residual"] = number_json(last.residual);
    // null: not measured (lambda not unique; no bodies to form v2 of)
    j["lambda_error"] = s.lambda_unique ? number_json(last.lambda_error) : nlohmann::json(nullptr);
    j["velocity_error"] =
        s.has_bodies() ? number_json(last.velocity_error) : nlohmann::json(nullptr);
    nlohmann::json reached = nlohmann::json::object();
    for (std::size_t i = 0; i < std::size(kConvergenceMilestones); ++i) {
      const ConvergenceMilestone& at = run.reached[i];
      reached[milestone_key(kConvergenceMilestones[i])] =
          at.iteration < 0 ? nlohmann::json(nullptr)
                           : nlohmann::json({{"iterations", at.iteration}, {"time_s", at.time_s}});
    }
    j["reached"] = reached;
    summary["solvers"].push_back(j);
  }
  return summary;
}

std::string convergence_csv(const std::vector<ConvergenceRun>& runs) {
  std::ostringstream csv;
  csv << "solver,iteration,time_s,residual,lambda_error,velocity_error,objective\n";
  for (const ConvergenceRun& run : runs) {
    for (const ConvergenceSample& m : run.samples) {
      csv << run.spec.text << ',' << m.iteration << ',' << csv_number(m.time_s) << ','
          << csv_number(m.residual) << ',' << csv_number(m.lambda_error) << ','
          << csv_number(m.velocity_error) << ',' << csv_number(m.objective) << '\n';
    }
  }
  return csv.str();
}

}  // namespace cbps
