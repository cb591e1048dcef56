// The time step (paper 3.2 with 4, 5, 6.2, 7, 8 and 12.3), stage by stage.
#include "cbps/step/simulation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "cbps/rows/build_rows.hpp"
#include "cbps/solvers/exact/direct.hpp"
#include "cbps/solvers/paper/coulomb.hpp"
#include "cbps/step/guard.hpp"
#include "cbps/step/push.hpp"
#include "cbps/step/scheme.hpp"
#include "stage_timer.hpp"

namespace cbps {

using Clock = std::chrono::steady_clock;
using detail::StageTimer;

std::string stage_name(Stage stage, Method method, PushMode push) {
  const std::string name(to_string(method));
  switch (stage) {
    case Stage::Collision:
      return "collision (4)";
    case Stage::DistanceRows:
      return "distance_rows (5.2)";
    case Stage::ContactRows:
      return "contact_rows (5.3)";
    case Stage::FrictionRows:
      return "friction_rows (5.4)";
    case Stage::Assembly:
      return "assembly (6.1, 6.2.9)";
    case Stage::AssemblyWithoutA:
      return "assembly (6.1, 6.2.9 without A)";
    case Stage::Solve:
      if (push == PushMode::Improved) return "velocity_system_" + name + " (8.1)";
      return "solve_" + name + (!is_iterative(method) ? " (6.2)" : " (7.1.1)");
    case Stage::PositionSystem:
      return "position_system_" + name + " (8.1)";
    case Stage::Integrate:
      return "integrate (12.3.1, 3.2)";
  }
  return "?";
}

Simulation::Simulation(Scene scene)
    : scene_(std::move(scene)),
      exact_memory_(make_exact_memory()),
      collision_stage_(scene_.has_contact_pairs()) {}

StepReport Simulation::step() {
  if (scene_.world.scheme.kind != Scheme::Paper) return scheme_step();
  const auto start = Clock::now();
  StepReport report;
  const System& sys = assemble(&report.times);  // Collision (4), Rows (5.2–5.4), Assembly (6.1)
  name_stages();
  report_contacts(sys, report);
  report.warm_rows = continued_rows(sys);
  // Where this step's contact points sit on their bodies, for the next step's persistence.
  ContactMemory contacts =
      persistence() ? keep_contacts(scene_.bodies, manifolds_, contacts_.next_id) : ContactMemory{};
  VecX lambda = initial_lambda(sys);  // warm start (7)
  {
    const StageTimer solve(report.times.solve);
    report.solver = solve_system(sys, lambda);  // Solve (7.1.1 / 6.2)
  }
  const VecX v2 = compute_v2(sys, lambda);  // v2 = v1 + Δt M⁻¹ (Jᵀ λ + f_ext) (12.3.1)
  check_divergence(sys, scene_.bodies, scene_.world, lambda, v2, steps_, system_name(sys.push));
  if (observer_) observer_(sys, lambda, v2);  // not timed: a cross-check is not the step
  report.cfm_acceleration_error = cfm_acceleration_error(sys, lambda);
  const bool improved = sys.push == PushMode::Improved;
  const VecX v_move = improved ? position_velocities(sys, lambda, report) : v2;  // (8.1)
  integrate(sys, v2, v_move, report.times);                                      // Integrate (3.2)
  remember(sys, lambda);  // for the next step's warm start (7)
  contacts_ = std::move(contacts);
  t_ = static_cast<double>(++steps_) * scene_.world.dt;  // not a running sum: no drift
  report.max_constraint_error = max_constraint_error();
  report.wall_time_s = std::chrono::duration<double>(Clock::now() - start).count();
  return report;
}

namespace {

/// A substep's solver summary added to the step's: sweeps, factorizations, pivots and time
/// summed; residual and termination the last substep's.
void add_substep(SolverSummary& step, const SolverSummary& substep) {
  const SolverSummary sum = step;
  step = substep;
  step.iterations += sum.iterations;
  step.factorizations += sum.factorizations;
  step.pivots += sum.pivots;
  step.restarts += sum.restarts;
  step.updates += sum.updates;
  step.wall_time_s += sum.wall_time_s;
}

}  // namespace

StepReport Simulation::scheme_step() {
  const auto start = Clock::now();
  StepReport report;
  detect_contacts(manifolds_, &report.times);  // Collision (4), once a step
  // Where each contact point sits on its bodies: the substeps carry the points with them, and
  // the next step's persistence continues them.
  ContactMemory kept = keep_contacts(scene_.bodies, manifolds_, contacts_.next_id);
  std::vector<Manifold> moved;
  const int substeps = std::max(1, scene_.world.scheme.substeps);
  for (int k = 0; k < substeps; ++k) {
    if (k > 0) carry_contacts(manifolds_, kept, scene_.bodies, moved);
    substep_system(k == 0 ? manifolds_ : moved, rows_, sys_, false, &report.times);
    if (k == 0) {
      A_formed_ = sys_.A.rows() == sys_.rows();
      name_stages();
      report_contacts(sys_, report);
      report.warm_rows = continued_rows(sys_);
    }
    substep(report);
  }
  contacts_ = persistence() ? std::move(kept) : ContactMemory{};
  t_ = static_cast<double>(++steps_) * scene_.world.dt;  // not a running sum: no drift
  report.max_constraint_error = max_constraint_error();
  report.wall_time_s = std::chrono::duration<double>(Clock::now() - start).count();
  return report;
}

void Simulation::substep(StepReport& report) {
  const System& sys = sys_;
  const Scheme kind = scene_.world.scheme.kind;
  // XPBD starts every substep from lambda = 0 (Macklin et al. 2016, Algorithm 1); the others
  // from the last substep's lambda, the first from last step's (7).
  VecX lambda = kind == Scheme::Xpbd ? VecX::Zero(sys.rows()) : initial_lambda(sys);
  VecX v_move;
  if (kind == Scheme::SoftStep) {
    // The soft push system moves the bodies; the relax starts from its lambda (Box2D v3's
    // solve, integrate positions, relax).
    VecX lambda_push = lambda;
    {
      const StageTimer solve(report.times.solve);
      add_substep(report.position_solver,
                  solve_position_system(sys, lambda_push, step_options(scene_.solver)));
    }
    v_move = compute_v2(sys, lambda_push);  // (12.3.1) with the push system's lambda
    check_divergence(
        sys, scene_.bodies, scene_.world, lambda_push, v_move, steps_, "soft push system");
    lambda = lambda_push;
  }
  {
    const StageTimer solve(report.times.solve);
    add_substep(report.solver, solve_system(sys, lambda));  // relax under soft-step
  }
  const VecX v2 = compute_v2(sys, lambda);  // (12.3.1)
  check_divergence(sys, scene_.bodies, scene_.world, lambda, v2, steps_, system_name(sys.push));
  if (observer_) observer_(sys, lambda, v2);
  report.cfm_acceleration_error =
      std::max(report.cfm_acceleration_error, cfm_acceleration_error(sys, lambda));
  if (kind != Scheme::SoftStep)
    v_move = sys.push == PushMode::Improved ? position_velocities(sys, lambda, report) : v2;
  integrate(sys, v2, v_move, report.times);  // Integrate (3.2) over h
  remember(sys, lambda);                     // the next substep's (and step's) warm start
}

void Simulation::substep_system(const std::vector<Manifold>& manifolds,
                                std::vector<Row>& rows,
                                System& sys,
                                bool always_form_A,
                                StageTimes* times) const {
  const World& w = scene_.world;
  const double h = substep_dt(w);
  double rows_s = 0.0, assembly_s = 0.0;
  {
    const StageTimer timer(rows_s);
    cbps::build_rows(scene_.bodies, scene_.distances, manifolds, substep_row_settings(w), rows);
    scheme_rows(w, rows);
  }
  const bool form_A =
      always_form_A || scheme_softens(w) || forms_A(static_cast<Eigen::Index>(rows.size()));
  {
    const StageTimer timer(assembly_s);
    assemble_system(scene_.bodies, rows, w.gravity, h, scheme_push(w), sys, form_A);
    start_velocities(sys);
    if (scheme_softens(w)) soften(sys, scheme_softness(w, rows, sys));
  }
  if (times != nullptr) {
    times->rows += rows_s;
    times->assembly += assembly_s;
  }
}

void Simulation::report_contacts(const System& sys, StepReport& report) const {
  report.rows = sys.rows();
  report.friction_contacts = static_cast<int>(sys.contacts.contacts());
  report.law = sys.contacts.law;
  if (!sys.contacts.empty()) {
    report.mu_min = sys.contacts.mu.minCoeff();
    report.mu_max = sys.contacts.mu.maxCoeff();
  }
  for (const Manifold& manifold : manifolds_) {
    report.contacts += static_cast<int>(manifold.points.size());
    for (const ContactPoint& point : manifold.points)
      report.max_penetration = std::max(report.max_penetration, point.depth);
  }
}

double Simulation::cfm_acceleration_error(const System& sys, const VecX& lambda) const {
  if (!(scene_.solver.cfm > 0.0) || sys.rows() == 0) return 0.0;
  return scene_.solver.cfm * lambda.lpNorm<Eigen::Infinity>();  // eps max |lambda_k|, m/s²
}

const char* Simulation::system_name(PushMode push) {
  return push == PushMode::Improved ? "velocity system (8.1)" : "system (6.2)";
}

void Simulation::name_stages() {
  const Method method = scene_.solver.method;
  const PushMode push = scheme_push(scene_.world);
  const SchemeSettings& scheme = scene_.world.scheme;
  stages_.clear();
  // Under a substepping scheme every stage after collision detection runs once a substep.
  std::string each;
  if (scheme.kind != Scheme::Paper)
    each = scheme_names().at(static_cast<std::size_t>(scheme.kind)) + " substep (x" +
           std::to_string(scheme.substeps) + "): ";
  const auto add = [&](Stage stage) {
    stages_.push_back((stage == Stage::Collision ? "" : each) + stage_name(stage, method, push));
  };
  if (collision_stage_) add(Stage::Collision);
  if (!scene_.distances.empty()) add(Stage::DistanceRows);
  if (collision_stage_) add(Stage::ContactRows);
  if (collision_stage_ && scene_.world.mu > 0.0) add(Stage::FrictionRows);
  add(A_formed_ ? Stage::Assembly : Stage::AssemblyWithoutA);
  if (scheme.kind == Scheme::SoftStep) {  // the soft push system first, then the relax
    add(Stage::PositionSystem);
    add(Stage::Solve);
  } else {
    add(Stage::Solve);
    if (push == PushMode::Improved) add(Stage::PositionSystem);
  }
  add(Stage::Integrate);
}

void Simulation::detect_contacts(std::vector<Manifold>& manifolds, StageTimes* times) const {
  manifolds.clear();
  if (!collision_stage_) return;
  double broad_s = 0.0, narrow_s = 0.0;
  std::vector<std::pair<int, int>> pairs;
  {
    const StageTimer broad(broad_s);
    pairs = broad_phase(scene_.bodies, scene_.world.detection_margin());  // (4, step 1)
  }
  {
    const StageTimer narrow(narrow_s);
    manifolds = narrow_phase(scene_.bodies, pairs, scene_.world.detection_margin());  // (4, 2)
    // The points that continue last step's keep their ids (7).
    if (persistence())
      continue_contacts(contacts_, scene_.bodies, scene_.world.contact_persistence, manifolds);
  }
  if (times != nullptr) {
    times->broad_phase = broad_s;
    times->narrow_phase = narrow_s;
  }
}

void Simulation::build_rows(std::vector<Row>& rows,
                            std::vector<Manifold>& manifolds,
                            StageTimes* times) const {
  detect_contacts(manifolds, times);
  double rows_s = 0.0;
  {
    const StageTimer timer(rows_s);
    cbps::build_rows(scene_.bodies, scene_.distances, manifolds, scene_.world.rows(), rows);
  }
  if (times != nullptr) times->rows = rows_s;
}

std::vector<Row> Simulation::build_rows() const {
  std::vector<Row> rows;
  std::vector<Manifold> manifolds;
  build_rows(rows, manifolds);
  return rows;
}

System Simulation::build_system() const {
  const World& w = scene_.world;
  if (w.scheme.kind != Scheme::Paper) {
    std::vector<Manifold> manifolds;
    detect_contacts(manifolds, nullptr);
    std::vector<Row> rows;
    System sys;
    substep_system(manifolds, rows, sys, true, nullptr);
    return sys;
  }
  System sys = assemble_system(scene_.bodies, build_rows(), w.gravity, w.dt, w.push);
  start_velocities(sys);
  return sys;
}

const System& Simulation::assemble(StageTimes* times) {
  build_rows(rows_, manifolds_, times);
  const World& w = scene_.world;
  double assembly_s = 0.0;
  {
    const StageTimer timer(assembly_s);
    A_formed_ = forms_A(static_cast<Eigen::Index>(rows_.size()));
    assemble_system(scene_.bodies, rows_, w.gravity, w.dt, w.push, sys_, A_formed_);
    start_velocities(sys_);
  }
  if (times != nullptr) times->assembly = assembly_s;
  return sys_;
}

void Simulation::start_velocities(System& sys) const {
  const World& w = scene_.world;
  if (w.integrator != Integrator::Gyroscopic) return;
  // Bullet's implicit gyroscopic step: the step starts from ω' (body.hpp), so v1 and b (6.2.9)
  // are those of ω'.
  for (int blk = 0; blk < sys.blocks(); ++blk) {
    const Body& body = scene_.bodies[static_cast<std::size_t>(sys.body_of_block[blk])];
    sys.v1.segment<3>(6 * blk + 3) = gyroscopic_omega(body, sys.dt);
  }
  sys.b = compute_b(sys.upsilon, sys.J, sys.v1, sys.Minv, sys.fext, sys.dt);
}

bool Simulation::forms_A(Eigen::Index rows) const {
  const RowSettings settings = scene_.world.rows();
  const bool cones = is_cone(settings.friction) && settings.mu > 0.0;  // 5.4
  const SolverSettings& solver = scene_.solver;
  return observer_ != nullptr || reads_A(solver.method, cones) ||
         (solver.method == kExactMethod && rows < solver.options().direct.interior_from_rows);
}

int Simulation::continued_rows(const System& sys) const {
  return static_cast<int>(std::count_if(sys.ids.begin(), sys.ids.end(), [&](std::uint64_t id) {
    return warm_.find(id) != warm_.end();
  }));
}

VecX Simulation::initial_lambda(const System& sys) const { return warm_lambda(sys, warm_); }

VecX Simulation::last_lambda(const System& sys) const { return warm_lambda(sys, warm_, false); }

VecX Simulation::warm_lambda(const System& sys, const WarmStart& warm, bool scaled) const {
  VecX lambda = VecX::Zero(sys.rows());
  for (int k = 0; k < sys.rows(); ++k) {
    const auto row = static_cast<std::size_t>(k);
    const auto it = warm.find(sys.ids[row]);
    if (it == warm.end()) continue;
    lambda(k) =
        scaled ? warm_guess(it->second, scene_.solver.warm_factor(sys.kind[row])) : it->second;
  }
  return lambda;
}

SolverOptions Simulation::step_options(const SolverSettings& settings) const {
  SolverOptions options = settings.options();
  options.seed = settings.seed + static_cast<std::uint64_t>(steps_);  // new permutations each step
  options.direct.memory = exact_memory_;
  return options;
}

SolverSummary Simulation::solve_system(const System& sys,
                                       const VecX& b,
                                       VecX& lambda,
                                       const SolverSettings& settings) const {
  return solve_coulomb(sys.problem(b), sys.coulomb(), lambda, step_options(settings));
}

VecX Simulation::position_velocities(const System& sys, const VecX& lambda, StepReport& report) {
  // Start from this step's velocity λ plus last step's push increment λ_position − λ: the
  // two systems differ only by the push (8.1). (4.1 cm top drift against 6.1 cm from the last
  // λ_position, 10-box stack, 20 sweeps.) The increment takes the rows' warm-start factors.
  VecX lambda_position = position_guess(sys, lambda);
  {
    const StageTimer solve(report.times.solve);
    add_substep(report.position_solver,
                solve_position_system(sys, lambda_position, step_options(scene_.solver)));  // 8.1
  }
  const VecX v_position = compute_v2(sys, lambda_position);  // (12.3.1), with the position λ
  check_divergence(sys,
                   scene_.bodies,
                   scene_.world,
                   lambda_position,
                   v_position,
                   steps_,
                   "position system (8.1)");
  warm_position_.clear();
  for (int k = 0; k < sys.rows(); ++k)
    warm_position_[sys.ids[static_cast<std::size_t>(k)]] = lambda_position(k) - lambda(k);
  return v_position;
}

void Simulation::integrate(const System& sys,
                           const VecX& v2,
                           const VecX& v_move,
                           StageTimes& times) {
  const StageTimer timer(times.integrate);
  const double dt = sys.dt;  // the Δt the system was assembled with (6.2.4)
  const Integrator integrator = scene_.world.integrator;
  for (int blk = 0; blk < sys.blocks(); ++blk) {
    Body& body = scene_.bodies[static_cast<std::size_t>(sys.body_of_block[blk])];
    const Vec3 v = v2.segment<3>(6 * blk), omega = v2.segment<3>(6 * blk + 3);
    const Vec3 v_lin = v_move.segment<3>(6 * blk), v_ang = v_move.segment<3>(6 * blk + 3);
    switch (integrator) {
      case Integrator::Paper:
        body.set_velocity(v, omega);               // p = m v2, l = I ω2 (3.1)
        advance_position(body, v_lin, v_ang, dt);  // (3.2)
        break;
      case Integrator::Gyroscopic:
        advance_position(body, v_lin, v_ang, dt);  // (3.2)
        body.set_velocity(v, omega);               // ω2 kept through the turn: l = I' ω2
        break;
      case Integrator::Midpoint: {
        const Quat q = midpoint_turn(body, v_ang, dt);  // from l = I ω_move
        body.set_velocity(v, omega);                    // l = I ω2, kept through the turn
        advance_position(body, v_lin, Vec3::Zero(), dt);
        body.q = q;
        break;
      }
    }
    body.f.setZero();
    body.tau.setZero();
  }
}

void Simulation::remember(const System& sys, const VecX& lambda) {
  warm_.clear();
  for (int k = 0; k < sys.rows(); ++k) warm_[sys.ids[static_cast<std::size_t>(k)]] = lambda(k);
}

double Simulation::energy() const {
  double e = 0.0;
  for (const Body& body : scene_.bodies) {
    if (body.is_static) continue;
    e += body.kinetic_energy() - body.m * scene_.world.gravity.dot(body.x);
  }
  return e;
}

double Simulation::max_constraint_error() const {
  double e = 0.0;
  for (const DistanceConstraint& dc : scene_.distances) {
    e = std::max(e, std::abs(distance_violation(dc, scene_.bodies)));
  }
  return e;
}

std::vector<std::string> column_labels(const Scene& scene, const System& sys) {
  static const char* const coords[6] = {"vx", "vy", "vz", "wx", "wy", "wz"};
  std::vector<std::string> labels;
  for (int body : sys.body_of_block)
    for (const char* c : coords)
      labels.push_back(scene.bodies[static_cast<std::size_t>(body)].name + "." + c);
  return labels;
}

}  // namespace cbps
