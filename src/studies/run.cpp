#include "cbps/studies/run.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "cbps/io/json_numbers.hpp"
#include "cbps/solvers/exact/direct.hpp"
#include "cbps/solvers/paper/coulomb.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/step/scheme.hpp"
#include "cbps/studies/solver_spec.hpp"
#include "cbps/system/unit_free.hpp"

namespace cbps {

namespace {

/// The step scheme of a run (docs/schemes.md), as summary.json gives it.
nlohmann::json scheme_summary(const World& world) {
  const SchemeSettings& s = world.scheme;
  nlohmann::json j = {{"name", scheme_names().at(static_cast<std::size_t>(s.kind))},
                      {"substeps", s.substeps},
                      {"h", world.dt / s.substeps}};
  if (s.kind == Scheme::SoftStep)
    j["soft"] = {{"contact_hertz", s.contact_hertz},
                 {"contact_hertz_used", contact_hertz(s, world.dt / s.substeps)},
                 {"contact_damping_ratio", s.contact_damping_ratio},
                 {"joint_hertz", s.joint_hertz},
                 {"joint_damping_ratio", s.joint_damping_ratio},
                 {"max_push_speed", s.max_push_speed}};
  if (s.kind == Scheme::Xpbd) j["compliance"] = s.compliance;
  if (s.kind != Scheme::Paper) j["speculative_distance"] = s.speculative_distance;
  return j;
}

/// The method did not solve the step: what a sweep's iteration limit is not (its answer is
/// what the paper's step takes), but a refused answer, a non-finite one or a stop short is.
bool method_failed(Termination t) {
  return t == Termination::PeerUnsolved || t == Termination::NonFinite ||
         t == Termination::NotConverged || t == Termination::NoSolution ||
         t == Termination::TimeLimit;
}

/// Adds one step's report to the totals.
void add_step(RunTotals& t, const Simulation& sim, const StepReport& r) {
  if (r.rows > 0) {
    ++t.steps_with_rows;
    if (method_failed(r.solver.termination)) {
      if (t.steps_failed++ == 0) {
        t.first_failed_step = t.steps_done;
        t.first_failure = r.solver.message;
      }
    }
  }
  ++t.steps_done;
  t.cfm_acceleration_error = std::max(t.cfm_acceleration_error, r.cfm_acceleration_error);
  t.iterations_total += r.solver.iterations;
  t.final_residual = r.solver.residual;
  t.max_residual = std::max(t.max_residual, r.solver.residual);
  t.max_constraint_error = std::max(t.max_constraint_error, r.max_constraint_error);
  t.max_rows = std::max(t.max_rows, r.rows);
  t.max_contacts = std::max(t.max_contacts, r.contacts);
  if (r.friction_contacts > 0) {
    const bool first = t.friction_contact_steps == 0;
    t.solved_mu_min = first ? r.mu_min : std::min(t.solved_mu_min, r.mu_min);
    t.solved_mu_max = first ? r.mu_max : std::max(t.solved_mu_max, r.mu_max);
    t.friction_contact_steps += r.friction_contacts;
    t.solved_laws[std::string(law_name(r.law))] += r.friction_contacts;
  }
  t.stage_times += r.times;
  if (!r.solver.route.empty()) ++t.routes[r.solver.route];
  if (!r.position_solver.route.empty()) ++t.position_routes[r.position_solver.route];
  t.max_penetration = std::max(t.max_penetration, r.max_penetration);
  for (const std::string& stage : sim.stages()) {
    if (std::find(t.stages.begin(), t.stages.end(), stage) == t.stages.end())
      t.stages.push_back(stage);
  }
}

void record_bodies(CsvFile& csv, double t, const std::vector<Body>& bodies) {
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

}  // namespace

RunTotals run_scene(const Scene& scene, long steps, const std::vector<StepObserver*>& observers) {
  Simulation sim(scene);
  return run_steps(sim, steps, observers);
}

void step_to(Simulation& sim, long steps, const std::string& command, bool quiet) {
  const auto start = std::chrono::steady_clock::now();
  auto last = start;
  for (long s = 0; s < steps; ++s) {
    sim.step();
    const auto now = std::chrono::steady_clock::now();
    if (quiet || now - last <= std::chrono::seconds(2)) continue;
    last = now;
    std::fprintf(stderr,
                 "cbps %s: stepping to step %ld: %ld/%ld (%.0f%%), %.1f s elapsed\n",
                 command.c_str(),
                 steps,
                 s + 1,
                 steps,
                 100.0 * static_cast<double>(s + 1) / static_cast<double>(steps),
                 std::chrono::duration<double>(now - start).count());
  }
}

RunTotals run_steps(Simulation& sim, long steps, const std::vector<StepObserver*>& observers) {
  RunTotals t;
  t.steps_requested = steps;
  t.energy_initial = sim.energy();
  t.max_constraint_error = sim.max_constraint_error();
  for (StepObserver* o : observers) o->start(sim);
  const auto start = std::chrono::steady_clock::now();
  for (long s = 0; s < steps && !t.stopped; ++s) {
    for (StepObserver* o : observers) o->before_step(sim, s);
    StepReport r;
    try {
      r = sim.step();
    } catch (const DivergenceError& e) {
      t.diverged = e;
      break;
    }
    add_step(t, sim, r);
    for (StepObserver* o : observers) {
      if (!o->after_step(sim, r, s + 1) && s + 1 < steps) t.stopped = true;
    }
  }
  t.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  t.energy_final = sim.energy();
  t.time = sim.time();
  return t;
}

void CrossCheck::start(Simulation& sim) {
  SolverSettings direct = sim.scene().solver;
  direct.method = kExactMethod;
  direct.tolerance = 0.0;  // the reference: to the direct path's rounding floor
  const double cfm = sim.scene().solver.cfm;
  const int interior_from_rows = direct.options().direct.interior_from_rows;
  sim.set_observer([this, &sim, direct, cfm, interior_from_rows](
                       const System& sys, const VecX& lambda, const VecX& v2) {
    // Where the interior point runs (interior_from_rows and more), the iterative λ is the
    // direct path's guess only when it already solves the step to the rounding floor (then
    // taken as it is): elsewhere the solve starts from λ = 0, since the warm crossover from
    // an iterative λ rarely finishes there and spends its 100 pivoting rounds first (the
    // base-20 pyramid under PGS: every step, docs/exact-path.md). Fewer rows: the active-set
    // path, which tries the guess and then λ = 0 and keeps the better.
    VecX lambda_direct = lambda;
    const BoxedProblem problem = sys.problem();
    if (sys.rows() >= interior_from_rows &&
        !(natural_map_residual(problem, lambda) <= residual_floor(problem, lambda)))
      lambda_direct.setZero();
    const auto start = std::chrono::steady_clock::now();
    const SolverSummary s = sim.solve_system(sys, sys.b, lambda_direct, direct);
    direct_time_s +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (s.termination != Termination::Direct) ++direct_short;
    if (!s.route.empty()) ++routes[s.route];
    direct_pivots += s.pivots;
    // Verified as `cbps lcp` verifies (system/unit_free.hpp), with the Coulomb bounds at λ.
    const UnitFreeResidual unit_free =
        coulomb_unit_free(problem, sys.coulomb(), lambda_direct, cfm);
    if (!is_solved(unit_free, lambda_direct)) ++direct_unverified;
    max_keep_nan(max_direct_unit_free, unit_free.relative);
    const VecX v2_direct = compute_v2(sys, lambda_direct);
    const double difference = v2.size() > 0 ? (v2 - v2_direct).lpNorm<Eigen::Infinity>() : 0.0;
    max_velocity_difference = std::max(max_velocity_difference, difference);
    if (tolerance_ >= 0.0 && !(difference <= tolerance_)) {
      if (first_beyond < 0) {
        first_beyond = sim.steps_done();
        first_beyond_difference = difference;
      }
      ++steps_beyond;
    }
    max_residual =
        std::max(max_residual, coulomb_residual(sys.problem(), sys.coulomb(), lambda, cfm));
    max_direct_residual = std::max(max_direct_residual, s.residual);
    ++steps_checked;
  });
}

nlohmann::json CrossCheck::json(bool timing) const {
  nlohmann::json j = {{"max_velocity_difference", number_json(max_velocity_difference)},
                      {"max_pgs_residual", number_json(max_residual)},
                      {"max_direct_residual", number_json(max_direct_residual)},
                      {"max_direct_unit_free", number_json(max_direct_unit_free)},
                      {"direct_stopped_short", direct_short},
                      {"direct_unverified", direct_unverified},
                      {"steps_checked", steps_checked},
                      {"direct_routes", routes},
                      {"direct_pivots", direct_pivots}};
  if (timing) j["direct_time_s"] = number_json(direct_time_s);
  if (tolerance_ >= 0.0) {
    j["tolerance"] = tolerance_;
    j["steps_beyond_tolerance"] = steps_beyond;
    j["first_step_beyond_tolerance"] =
        first_beyond >= 0 ? nlohmann::json(first_beyond) : nlohmann::json(nullptr);
    j["passed"] = steps_beyond == 0;
  }
  return j;
}

TrajectoryRecorder::TrajectoryRecorder(const std::string& path, long every)
    : csv_(path, "t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz"), every_(every) {}

void TrajectoryRecorder::start(Simulation& sim) {
  record_bodies(csv_, sim.time(), sim.scene().bodies);
}

bool TrajectoryRecorder::after_step(const Simulation& sim, const StepReport&, long done) {
  if (done % every_ == 0) record_bodies(csv_, sim.time(), sim.scene().bodies);
  return true;
}

StepsRecorder::StepsRecorder(const std::string& path, bool timing)
    : csv_(path,
           timing
               ? "t,rows,warm_rows,iterations,residual,max_constraint_error,energy,direct_route,"
                 "wall_time_s,solve_time_s"
               : "t,rows,warm_rows,iterations,residual,max_constraint_error,energy,direct_route"),
      timing_(timing) {}

bool StepsRecorder::after_step(const Simulation& sim, const StepReport& r, long) {
  csv_.num(sim.time());
  csv_.integer(r.rows);
  csv_.integer(r.warm_rows);
  csv_.integer(r.solver.iterations);
  csv_.num(r.solver.residual);
  csv_.num(r.max_constraint_error);
  csv_.num(sim.energy());
  csv_.text(r.solver.route);
  if (timing_) {
    csv_.num(r.wall_time_s);
    csv_.num(r.times.solve);
  }
  csv_.end_row();
  return true;
}

std::vector<std::string> run_warnings(const RunTotals& t) {
  std::vector<std::string> warnings;
  if (t.steps_failed > 0)
    warnings.push_back("the method failed " + std::to_string(t.steps_failed) + " of " +
                       std::to_string(t.steps_with_rows) + " steps with rows" +
                       (t.steps_failed == t.steps_with_rows ? " (every one)" : "") +
                       ", the first step " + std::to_string(t.first_failed_step) + ": " +
                       t.first_failure);
  return warnings;
}

nlohmann::json run_summary_json(const Scene& scene,
                                const RunTotals& t,
                                bool timing,
                                const nlohmann::json& threads) {
  nlohmann::json summary;
  summary["scene"] = scene.name;
  nlohmann::json params = nlohmann::json::object();
  for (const auto& [name, value] : scene.parameters) params[name] = value;
  summary["parameters"] = params;
  summary["status"] = t.diverged ? "diverged" : "completed";
  if (t.diverged) {
    summary["divergence"] = {{"step", t.diverged->step()},
                             {"body", t.diverged->body()},
                             {"row", t.diverged->row()},
                             {"message", t.diverged->what()}};
  }
  const SolverSettings& solver = scene.solver;
  summary["bodies"] = scene.bodies.size();
  summary["rows"] = t.max_rows;
  summary["steps"] = t.steps_done;
  summary["steps_requested"] = t.steps_requested;
  summary["dt"] = scene.world.dt;
  summary["beta"] = scene.world.beta;
  summary["duration"] = number_json(t.time);
  summary["solver"] = {
      {"method", std::string(to_string(solver.method))},
      {"iterations", solver.max_iterations},
      {"tolerance", solver.tolerance},
      {"warm_start", solver.warm > 0.0 || solver.warm_factor(RowKind::Friction) > 0.0},
      {"warm", solver.warm},
      {"warm_friction", solver.warm_factor(RowKind::Friction)},
      {"relaxation", solver.relaxation},
      {"order", to_string(solver.order)},
      {"contacts_first", solver.contacts_first},
      {"seed", solver.seed},
      {"cfm", solver.cfm}};
  for (const auto& [key, value] : method_parameters(solver.method, solver.methods))
    summary["solver"]["parameters"][key] = value;
  if (solver.cfm > 0.0) {
    // CFM is never silent: how far the answer is from A lambda = b because of it.
    summary["regularization"] = {
        {"cfm", solver.cfm},
        {"max_acceleration_error", number_json(t.cfm_acceleration_error)},
        {"max_velocity_error", number_json(t.cfm_acceleration_error * scene.world.dt)}};
  }
  summary["push"] = scene.world.push == PushMode::Improved ? "improved" : "original";
  summary["integrator"] = integrator_names().at(static_cast<std::size_t>(scene.world.integrator));
  summary["scheme"] = scheme_summary(scene.world);
  summary["contacts"] = {{"mu", scene.world.mu},
                         {"friction", std::string(friction_name(scene.world.friction))},
                         {"restitution", scene.world.restitution},
                         {"persistence", scene.world.contact_persistence},
                         {"max_points", t.max_contacts}};
  if (is_cone(scene.world.friction))
    summary["contacts"]["cone"] = std::string(cone_law_name(scene.world.friction));
  // What the steps solved, from their systems' contacts (not the scene's settings).
  summary["contacts"]["solved"] = {
      {"friction_contact_steps", t.friction_contact_steps},
      {"mu_min", t.friction_contact_steps > 0 ? nlohmann::json(t.solved_mu_min) : nullptr},
      {"mu_max", t.friction_contact_steps > 0 ? nlohmann::json(t.solved_mu_max) : nullptr},
      {"laws", t.solved_laws}};
  summary["max_penetration"] = number_json(t.max_penetration);
  summary["steps_with_rows"] = t.steps_with_rows;
  summary["steps_method_failed"] = t.steps_failed;
  summary["warnings"] = run_warnings(t);
  summary["iterations_total"] = t.iterations_total;
  summary["max_residual"] = number_json(t.max_residual);
  summary["max_constraint_error"] = number_json(t.max_constraint_error);
  summary["energy_initial"] = number_json(t.energy_initial);
  summary["energy_final"] = number_json(t.energy_final);
  summary["stages"] = t.stages;
  if (!t.routes.empty()) summary["direct_routes"] = t.routes;
  if (!t.position_routes.empty()) summary["direct_routes_position"] = t.position_routes;
  if (timing) {
    const StageTimes& s = t.stage_times;
    summary["wall_time_s"] = t.wall_time_s;
    summary["threads"] = threads;
    summary["stage_times_s"] = {{"broad_phase", s.broad_phase},
                                {"narrow_phase", s.narrow_phase},
                                {"rows", s.rows},
                                {"assembly", s.assembly},
                                {"solve", s.solve},
                                {"integrate", s.integrate}};
  }
  return summary;
}

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

}  // namespace cbps
