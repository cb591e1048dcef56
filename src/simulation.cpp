// The time step (paper 3.2 with 6.2).
#include "cbps/simulation.hpp"

#include <chrono>
#include <cmath>
#include <sstream>

#include "cbps/error.hpp"

namespace cbps {

Simulation::Simulation(Scene scene) : scene_(std::move(scene)) {}

void Simulation::build_rows(std::vector<Row>& rows) const {
  rows.resize(scene_.distances.size());
  for (std::size_t k = 0; k < scene_.distances.size(); ++k) {
    rows[k] =
        distance_row(scene_.distances[k], scene_.bodies, scene_.world.beta, scene_.world.dt, k);
  }
}

std::vector<Row> Simulation::build_rows() const {
  std::vector<Row> rows;
  build_rows(rows);
  return rows;
}

System Simulation::build_system() const {
  return assemble_system(scene_.bodies, build_rows(), scene_.world.gravity, scene_.world.dt);
}

const System& Simulation::assemble() {
  build_rows(rows_);
  assemble_system(scene_.bodies, rows_, scene_.world.gravity, scene_.world.dt, sys_);
  return sys_;
}

VecX Simulation::initial_lambda(const System& sys) const {
  VecX lambda = VecX::Zero(sys.rows());
  if (!scene_.solver.warm_start) return lambda;
  for (int k = 0; k < sys.rows(); ++k) {
    const auto it = warm_.find(sys.ids[static_cast<std::size_t>(k)]);
    if (it != warm_.end()) lambda(k) = it->second;
  }
  return lambda;
}

SolverSummary Simulation::solve_system(const System& sys, VecX& lambda) const {
  SolverOptions options;
  options.max_iterations = scene_.solver.iterations;
  options.residual_tolerance = scene_.solver.tolerance;
  options.delta_tolerance = scene_.solver.delta_tolerance;
  options.relaxation = scene_.solver.relaxation;
  return solve(scene_.solver.method, sys.A, sys.b, sys.cmin, sys.cmax, lambda, options);
}

namespace {

/// Names the first non-finite entry of v2 by step and body, or of lambda by row.
void check_finite(const System& sys,
                  const std::vector<Body>& bodies,
                  const VecX& lambda,
                  const VecX& v2,
                  long step) {
  for (int k = 0; k < sys.rows(); ++k) {
    if (!std::isfinite(lambda(k))) {
      std::ostringstream msg;
      msg << "step " << step << ": lambda of row " << k << " ("
          << sys.labels[static_cast<std::size_t>(k)] << ") is " << lambda(k);
      throw ComputationError(msg.str());
    }
  }
  for (Eigen::Index i = 0; i < v2.size(); ++i) {
    if (!std::isfinite(v2(i))) {
      const int body = sys.body_of_block[static_cast<std::size_t>(i / 6)];
      std::ostringstream msg;
      msg << "step " << step << ": velocity of body " << body << " ("
          << bodies[static_cast<std::size_t>(body)].name << ") is not finite";
      throw ComputationError(msg.str());
    }
  }
}

}  // namespace

StepReport Simulation::step() {
  const auto start = std::chrono::steady_clock::now();
  const double dt = scene_.world.dt;
  StepReport report;

  // 1. Constraint rows of the current state (5.2) and the system A λ = b (6.1, 6.2.9).
  const System& sys = assemble();
  report.rows = sys.rows();

  // 2. λ by the chosen solver (7), from last step's λ (warm start).
  VecX lambda = initial_lambda(sys);
  report.solver = solve_system(sys, lambda);

  // 3. New velocities v2 = v1 + Δt M⁻¹ (Jᵀ λ + f_ext) (12.3.1).
  const VecX v2 = compute_v2(sys.v1, sys.Minv, sys.J, lambda, sys.fext, dt);
  check_finite(sys, scene_.bodies, lambda, v2, steps_);
  if (observer_) observer_(sys, lambda, v2);

  // 4. Momenta from v2 with this step's inertia, then positions advance with v2 (3.2).
  for (int blk = 0; blk < sys.blocks(); ++blk) {
    Body& body = scene_.bodies[static_cast<std::size_t>(sys.body_of_block[blk])];
    const Vec3 v = v2.segment<3>(6 * blk);
    const Vec3 omega = v2.segment<3>(6 * blk + 3);
    body.set_velocity(v, omega);  // p = m v2, l = I omega2
    advance_position(body, v, omega, dt);
    body.f.setZero();
    body.tau.setZero();
  }

  // 5. Keep λ for the next step's warm start, by row identity.
  warm_.clear();
  for (int k = 0; k < sys.rows(); ++k) warm_[sys.ids[static_cast<std::size_t>(k)]] = lambda(k);

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
