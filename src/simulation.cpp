// The time step (paper 3.2 with 4, 5, 6.2 and 8).
#include "cbps/simulation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "cbps/contact.hpp"
#include "cbps/error.hpp"

namespace cbps {

Simulation::Simulation(Scene scene)
    : scene_(std::move(scene)), collision_stage_(scene_.has_contact_pairs()) {}

namespace {

using Clock = std::chrono::steady_clock;

/// Seconds since `start`, and `start` moved to now.
double lap(Clock::time_point& start) {
  const auto now = Clock::now();
  const double s = std::chrono::duration<double>(now - start).count();
  start = now;
  return s;
}

}  // namespace

void Simulation::build_rows(std::vector<Row>& rows,
                            std::vector<Manifold>& manifolds,
                            StageTimes* times) const {
  auto clock = Clock::now();
  const World& w = scene_.world;
  const bool improved = w.push == PushMode::Improved;
  rows.resize(scene_.distances.size());
  for (std::size_t k = 0; k < scene_.distances.size(); ++k) {
    Row& row = rows[k];
    row = distance_row(scene_.distances[k], scene_.bodies, w.beta, w.dt, k);
    if (improved) row.upsilon = 0.0;  // 8.1: the push term only in the position system
  }
  manifolds.clear();
  if (!collision_stage_) {
    if (times != nullptr) times->rows = lap(clock);
    return;
  }
  const double distance_rows = lap(clock);
  const auto pairs = broad_phase(scene_.bodies, w.contact_margin);  // (4, step 1)
  const double broad = lap(clock);
  manifolds = narrow_phase(scene_.bodies, pairs, w.contact_margin);  // (4, step 2)
  if (times != nullptr) {
    times->broad_phase = broad;
    times->narrow_phase = lap(clock);
  }
  for (std::size_t index = 0; index < manifolds.size(); ++index) {
    const Manifold& m = manifolds[index];
    Vec3 t1, t2;
    tangent_basis(m.n, t1, t2);
    const double bound = paper_friction_bound(m, scene_.bodies, w.mu, w.gravity);
    for (const ContactPoint& point : m.points) {
      Row contact = contact_row(m, point, scene_.bodies);  // (5.3)
      const double approach = row_velocity(contact, scene_.bodies);
      const auto bias = [&](bool push) {
        return contact_bias(
            point.depth, approach, w.beta, w.dt, w.restitution, w.restitution_threshold, push);
      };
      contact.upsilon = bias(!improved);
      contact.upsilon_position = bias(true);  // restitution in both systems (8.2)
      contact.manifold = static_cast<int>(index);
      const int normal = static_cast<int>(rows.size());
      rows.push_back(std::move(contact));
      if (w.mu <= 0.0) continue;  // no friction rows at mu = 0
      int k = 1;
      for (const Vec3& t : {t1, t2}) {
        Row friction = friction_row(m, point, k++, t, bound, scene_.bodies);  // (5.4)
        friction.manifold = static_cast<int>(index);
        if (w.friction == FrictionModel::Coulomb) {
          friction.normal_row = normal;
          friction.mu = w.mu;
          friction.cmin = 0.0;  // the bounds ±mu lambda_normal are set by the solve
          friction.cmax = 0.0;
        }
        rows.push_back(std::move(friction));
      }
    }
  }
  if (times != nullptr) times->rows = distance_rows + lap(clock);
}

std::vector<Row> Simulation::build_rows() const {
  std::vector<Row> rows;
  std::vector<Manifold> manifolds;
  build_rows(rows, manifolds);
  return rows;
}

System Simulation::build_system() const {
  return assemble_system(scene_.bodies, build_rows(), scene_.world.gravity, scene_.world.dt);
}

const System& Simulation::assemble(StageTimes* times) {
  build_rows(rows_, manifolds_, times);
  auto clock = Clock::now();
  assemble_system(scene_.bodies, rows_, scene_.world.gravity, scene_.world.dt, sys_);
  if (times != nullptr) times->assembly = lap(clock);
  return sys_;
}

VecX Simulation::initial_lambda(const System& sys) const { return warm_lambda(sys, warm_); }

VecX Simulation::warm_lambda(const System& sys,
                             const std::unordered_map<std::uint64_t, double>& warm) const {
  VecX lambda = VecX::Zero(sys.rows());
  if (!scene_.solver.warm_start) return lambda;
  for (int k = 0; k < sys.rows(); ++k) {
    const auto it = warm.find(sys.ids[static_cast<std::size_t>(k)]);
    if (it != warm.end()) lambda(k) = it->second;
  }
  return lambda;
}

namespace {

/// Coulomb bounds (5.4) from lambda: cmin = −mu lambda_n, cmax = mu lambda_n for each friction
/// row with a normal row. Returns the largest change of a bound, N.
double update_coulomb_bounds(const System& sys, const VecX& lambda, VecX& lo, VecX& hi) {
  double change = 0.0;
  for (int k = 0; k < sys.rows(); ++k) {
    const int n = sys.normal_row[static_cast<std::size_t>(k)];
    if (n < 0) continue;
    const double bound = sys.mu(k) * std::max(0.0, lambda(n));
    change = std::max(change, std::abs(bound - hi(k)));
    lo(k) = -bound;
    hi(k) = bound;
  }
  return change;
}

}  // namespace

void bounds_at(const System& sys, const VecX& lambda, VecX& lo, VecX& hi) {
  lo = sys.cmin;
  hi = sys.cmax;
  update_coulomb_bounds(sys, lambda, lo, hi);
}

double system_residual(const System& sys, const VecX& b, const VecX& lambda, double cfm) {
  VecX lo, hi;
  bounds_at(sys, lambda, lo, hi);
  return natural_map_residual(sys.A, b, lo, hi, lambda, cfm);
}

bool has_coulomb_rows(const System& sys) {
  return std::any_of(sys.normal_row.begin(), sys.normal_row.end(), [](int n) { return n >= 0; });
}

SolverSummary Simulation::solve_system(const System& sys,
                                       const VecX& b,
                                       VecX& lambda,
                                       const SolverSettings& settings) const {
  SolverOptions options;
  options.max_iterations = settings.iterations;
  options.residual_tolerance = settings.tolerance;
  options.delta_tolerance = settings.delta_tolerance;
  options.relaxation = settings.relaxation;
  options.split_islands = settings.split_islands;
  options.row_blocks = &sys.manifold;  // block PGS: one block per contact manifold
  options.order = settings.order;
  options.seed = settings.seed + static_cast<std::uint64_t>(steps_);  // new permutations each step
  // Constraint-force mixing: the solvers work on A + eps E (sys.A stays J Minv Jᵀ), formed here
  // once per solve rather than by solve() on every call of the Coulomb loops below; the
  // matrix-free form puts eps on its own diagonal.
  const bool matrix_free = settings.method == "matrix-free";
  const SpMat regularised =
      settings.cfm != 0.0 && !matrix_free ? with_cfm(sys.A, settings.cfm) : SpMat();
  const SpMat& A = regularised.nonZeros() > 0 ? regularised : sys.A;
  options.cfm = matrix_free ? settings.cfm : 0.0;
  const auto run = [&](const VecX& lo, const VecX& hi, VecX& l, const SolverOptions& o) {
    if (matrix_free) return solve_matrix_free(sys.J, sys.Minv, b, lo, hi, l, o);
    return solve(settings.method, A, b, lo, hi, l, o);
  };
  if (!has_coulomb_rows(sys)) return run(sys.cmin, sys.cmax, lambda, options);

  VecX lo = sys.cmin, hi = sys.cmax;
  if (lambda.size() != sys.rows()) lambda = VecX::Zero(sys.rows());
  SolverSummary total;
  if (settings.method == "direct") {
    // A fixed point of the bounds: solve the boxed LCP, move the bounds to ±mu lambda_n, again.
    const double scale = std::max(1.0, b.size() > 0 ? b.lpNorm<Eigen::Infinity>() : 0.0);
    int rounds = 0;
    double change = kInf;
    while (rounds < 100) {
      change = update_coulomb_bounds(sys, lambda, lo, hi);
      if (rounds > 0 && change <= 1e-12 * scale) break;
      const SolverSummary s = run(lo, hi, lambda, options);
      ++rounds;
      total.iterations += s.iterations;
      total.factorizations += s.factorizations;
      total.pivots += s.pivots;
      total.islands = s.islands;
      total.singular = total.singular || s.singular;
      total.termination = s.termination;
      if (!s.ok()) break;
    }
    if (change > 1e-12 * scale && total.termination == Termination::Direct)
      total.termination = Termination::NotConverged;
    total.residual = natural_map_residual(A, b, lo, hi, lambda);  // A + eps E when cfm > 0
    std::ostringstream msg;
    msg << "direct with Coulomb bounds: fixed point in " << rounds << " rounds (last bound change "
        << change << " N), " << total.factorizations << " factorizations, residual "
        << total.residual << " N";
    total.message = msg.str();
    return total;
  }
  // PGS and Jacobi: the bounds follow lambda before every sweep.
  SolverOptions one = options;
  one.max_iterations = 1;
  one.split_islands = false;
  total.termination = Termination::MaxIterations;
  while (total.iterations < settings.iterations) {
    update_coulomb_bounds(sys, lambda, lo, hi);
    one.seed = options.seed * 1000003u + static_cast<std::uint64_t>(total.iterations);
    const SolverSummary s = run(lo, hi, lambda, one);
    total.iterations += s.iterations;
    total.residual = s.residual;
    total.delta = s.delta;
    if (s.termination != Termination::MaxIterations) {
      total.termination = s.termination;
      break;
    }
  }
  std::ostringstream msg;
  msg << to_string(total.termination) << " after " << total.iterations
      << " sweeps with Coulomb bounds, residual " << total.residual << " N";
  total.message = msg.str();
  return total;
}

namespace {

/// The body of a row: the first movable body its j_c acts on, −1 if none.
int body_of_row(const System& sys, int k) {
  for (SpMatRow::InnerIterator it(sys.J, k); it; ++it)
    return sys.body_of_block[static_cast<std::size_t>(it.col() / 6)];
  return -1;
}

/// The row whose impulse on column block `blk` is largest, |lambda_k| ‖j_k restricted to the
/// block‖, −1 if no row acts on it: the row a diverging body is most likely driven by.
int strongest_row_on(const System& sys, const VecX& lambda, int blk) {
  int best = -1;
  double largest = -1.0;
  for (int k = 0; k < sys.rows(); ++k) {
    double norm2 = 0.0;
    for (SpMatRow::InnerIterator it(sys.J, k); it; ++it)
      if (it.col() / 6 == blk) norm2 += it.value() * it.value();
    if (norm2 == 0.0) continue;
    const double impulse = std::abs(lambda(k)) * std::sqrt(norm2);
    if (!(impulse <= largest)) {  // NaN wins: it is the row to name
      largest = impulse;
      best = k;
    }
  }
  return best;
}

/// The divergence guard, run on every solve of every step: any lambda or v2 entry that is not
/// finite, or a body whose speed |v| or spin |omega| exceeds the scene's limits
/// (World::divergence_speed, divergence_spin), stops the run with a DivergenceError naming the
/// step, the body and the row, before the step's positions move.
void check_divergence(const System& sys,
                      const std::vector<Body>& bodies,
                      const World& world,
                      const VecX& lambda,
                      const VecX& v2,
                      long step,
                      const char* system) {
  const auto row_text = [&](int k) {
    std::ostringstream text;
    text << "row " << k << " (" << sys.labels[static_cast<std::size_t>(k)]
         << "), lambda = " << lambda(k) << " N";
    return text.str();
  };
  const auto body_text = [&](int body) {
    std::ostringstream text;
    text << "body " << body << " (" << bodies[static_cast<std::size_t>(body)].name << ")";
    return text.str();
  };
  const double t = static_cast<double>(step) * world.dt;
  for (int k = 0; k < sys.rows(); ++k) {
    if (std::isfinite(lambda(k))) continue;
    const int body = body_of_row(sys, k);
    std::ostringstream msg;
    msg << "step " << step << " (t = " << t << " s), " << system << ": " << row_text(k)
        << " is not finite";
    if (body >= 0) msg << "; it acts on " << body_text(body);
    throw DivergenceError(msg.str(), step, body, k);
  }
  for (int blk = 0; blk < sys.blocks(); ++blk) {
    const double speed = v2.segment<3>(6 * blk).norm();
    const double spin = v2.segment<3>(6 * blk + 3).norm();
    const bool finite = std::isfinite(speed) && std::isfinite(spin);
    if (finite && speed <= world.divergence_speed && spin <= world.divergence_spin) continue;
    const int body = sys.body_of_block[static_cast<std::size_t>(blk)];
    const int row = strongest_row_on(sys, lambda, blk);
    std::ostringstream msg;
    msg << "step " << step << " (t = " << t << " s), " << system << ": " << body_text(body);
    if (!finite) {
      msg << " has a velocity that is not finite";
    } else if (speed > world.divergence_speed) {
      msg << " moves at " << speed << " m/s, beyond divergence_speed " << world.divergence_speed
          << " m/s";
    } else {
      msg << " spins at " << spin << " rad/s, beyond divergence_spin " << world.divergence_spin
          << " rad/s";
    }
    if (row >= 0) {
      msg << "; the largest constraint impulse on it is " << row_text(row);
    } else {
      msg << "; no constraint row acts on it";
    }
    throw DivergenceError(msg.str(), step, body, row);
  }
}

}  // namespace

StepReport Simulation::step() {
  const auto start = std::chrono::steady_clock::now();
  const double dt = scene_.world.dt;
  const bool improved = scene_.world.push == PushMode::Improved;
  StepReport report;
  stages_.clear();

  // 1. Collision detection (4), constraint rows (5.2–5.4), the system A λ = b (6.1, 6.2.9).
  if (collision_stage_) stages_.emplace_back("collision (4)");
  if (!scene_.distances.empty()) stages_.emplace_back("distance_rows (5.2)");
  if (collision_stage_) stages_.emplace_back("contact_rows (5.3)");
  if (collision_stage_ && scene_.world.mu > 0.0) stages_.emplace_back("friction_rows (5.4)");
  stages_.emplace_back("assembly (6.1, 6.2.9)");
  const System& sys = assemble(&report.times);
  report.rows = sys.rows();
  for (const Manifold& m : manifolds_) {
    report.contacts += static_cast<int>(m.points.size());
    for (const ContactPoint& point : m.points)
      report.max_penetration = std::max(report.max_penetration, point.depth);
  }

  // 2. λ by the chosen solver (7), from last step's λ (warm start).
  const std::string& method = scene_.solver.method;
  stages_.push_back(improved ? "velocity_system_" + method + " (8.1)"
                             : "solve_" + method + (method == "direct" ? " (6.2)" : " (7.1.1)"));
  auto clock = Clock::now();
  VecX lambda = initial_lambda(sys);
  report.solver = solve_system(sys, lambda);
  report.times.solve = lap(clock);

  // 3. New velocities v2 = v1 + Δt M⁻¹ (Jᵀ λ + f_ext) (12.3.1).
  const VecX v2 = compute_v2(sys.v1, sys.Minv, sys.J, lambda, sys.fext, dt);
  report.times.integrate = lap(clock);
  check_divergence(sys,
                   scene_.bodies,
                   scene_.world,
                   lambda,
                   v2,
                   steps_,
                   improved ? "velocity system (8.1)" : "system (6.2)");
  if (observer_) observer_(sys, lambda, v2);  // not timed: a cross-check is not the step
  if (scene_.solver.cfm > 0.0 && sys.rows() > 0)
    report.cfm_acceleration_error = scene_.solver.cfm * lambda.lpNorm<Eigen::Infinity>();

  // 3b. The improved push factor (8.1): the position system, the same A with the push terms
  // in b, gives the velocities that move the bodies this step only.
  VecX v_position;
  if (improved) {
    stages_.push_back("position_system_" + method + " (8.1)");
    clock = Clock::now();
    const VecX b_position =
        compute_b(sys.upsilon_position, sys.J, sys.v1, sys.Minv, sys.fext, dt);  // (6.2.9)
    // Start from this step's velocity λ plus last step's push increment λ_position − λ: the
    // two systems differ only by the push (8.1). (4.1 cm top drift against 6.1 cm from the last
    // λ_position, 10-box stack, 20 sweeps.)
    VecX lambda_position = lambda + warm_lambda(sys, warm_position_);
    report.position_solver = solve_system(sys, b_position, lambda_position);
    report.times.solve += lap(clock);
    v_position = compute_v2(sys.v1, sys.Minv, sys.J, lambda_position, sys.fext, dt);
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
  }

  // 4. Momenta from v2 with this step's inertia, then positions advance (3.2).
  clock = Clock::now();
  stages_.emplace_back("integrate (12.3.1, 3.2)");
  const VecX& v_move = improved ? v_position : v2;
  for (int blk = 0; blk < sys.blocks(); ++blk) {
    Body& body = scene_.bodies[static_cast<std::size_t>(sys.body_of_block[blk])];
    body.set_velocity(v2.segment<3>(6 * blk), v2.segment<3>(6 * blk + 3));  // p = m v2, l = I ω2
    advance_position(body, v_move.segment<3>(6 * blk), v_move.segment<3>(6 * blk + 3), dt);
    body.f.setZero();
    body.tau.setZero();
  }

  // 5. Keep λ for the next step's warm start, by row identity.
  warm_.clear();
  for (int k = 0; k < sys.rows(); ++k) warm_[sys.ids[static_cast<std::size_t>(k)]] = lambda(k);
  report.times.integrate += lap(clock);

  ++steps_;
  t_ = static_cast<double>(steps_) * dt;  // not a running sum: no drift over long runs
  report.max_constraint_error = max_constraint_error();
  report.wall_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
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

}  // namespace cbps
