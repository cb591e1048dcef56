// The time step (paper 3.2 with 6.2): build rows, assemble A lambda = b, solve, v2, advance.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <unordered_map>
#include <vector>

#include "cbps/collision.hpp"
#include "cbps/scene.hpp"
#include "cbps/solver.hpp"
#include "cbps/system.hpp"

namespace cbps {

/// The bounds of the system at lambda: cmin, cmax, with each Coulomb friction row's set to
/// ∓mu max(0, lambda_normal) (5.4).
void bounds_at(const System& sys, const VecX& lambda, VecX& lo, VecX& hi);

/// The natural-map residual of the system with right-hand side b at lambda, Coulomb bounds
/// taken at lambda (bounds_at), with constraint-force mixing cfm (kg⁻¹) on A's diagonal, N.
double system_residual(const System& sys, const VecX& b, const VecX& lambda, double cfm);

/// True when some row is a Coulomb friction row (5.4): its bounds ±mu lambda_normal move with
/// lambda, so the step's problem is a fixed point of boxed problems, not one boxed problem.
bool has_coulomb_rows(const System& sys);

/// Wall time of each stage of one step, s.
struct StageTimes {
  double broad_phase = 0.0;   ///< 4, step 1
  double narrow_phase = 0.0;  ///< 4, step 2
  double rows = 0.0;          ///< 5.2–5.4
  double assembly = 0.0;      ///< 6.1, 6.2.9
  double solve = 0.0;         ///< 7 / 6.2 (both systems with the improved push, 8.1)
  double integrate = 0.0;     ///< 12.3.1, 3.2

  StageTimes& operator+=(const StageTimes& o) {
    broad_phase += o.broad_phase;
    narrow_phase += o.narrow_phase;
    rows += o.rows;
    assembly += o.assembly;
    solve += o.solve;
    integrate += o.integrate;
    return *this;
  }
};

struct StepReport {
  int rows = 0;
  int contacts = 0;  ///< contact points found this step (4)
  SolverSummary solver;
  SolverSummary position_solver;      ///< the position system of 8.1 (improved push only)
  double max_constraint_error = 0.0;  ///< after the step, m
  double max_penetration = 0.0;       ///< deepest contact found at the start of the step, m
  /// Constraint-force mixing's effect: (A + eps E) lambda = b misses A lambda = b by eps lambda;
  /// this is eps max |lambda_k|, m/s² (0 without CFM). Times dt it is a velocity error, m/s.
  double cfm_acceleration_error = 0.0;
  double wall_time_s = 0.0;  ///< of the whole step
  StageTimes times;
};

class Simulation {
 public:
  explicit Simulation(Scene scene);

  /// One step of dt: rows (5.2) → system (6.1, 6.2.9) → lambda (7) → v2 (12.3.1) →
  /// positions with v2 (3.2) → momenta p = m v2, l = I omega2.
  /// Throws DivergenceError naming the step, body and row when lambda or v2 turn non-finite or
  /// a body's speed or spin exceeds World::divergence_speed / divergence_spin; the bodies then
  /// stay as they were before the step.
  StepReport step();

  /// The rows of the current state, into `rows` (storage reused): distance rows (5.2) in
  /// constraint order, then for each contact manifold (4) and point its contact row (5.3) and,
  /// when mu > 0, its two friction rows (5.4). The manifolds found go to `manifolds`.
  void build_rows(std::vector<Row>& rows,
                  std::vector<Manifold>& manifolds,
                  StageTimes* times = nullptr) const;
  std::vector<Row> build_rows() const;
  /// The system of the current state, not solved (6.1, 6.2.9), as a new System.
  System build_system() const;
  /// The same, assembled into the simulation's own System, whose storage is reused from step
  /// to step; step() calls this. The reference stays valid until the next assemble() or step().
  const System& assemble(StageTimes* times = nullptr);
  /// The warm-start guess for a system: last step's lambda by row id, else 0.
  VecX initial_lambda(const System& sys) const;
  /// Solves A lambda = b of `sys` with the scene's solver settings, from the guess in lambda;
  /// `b` is sys.b, or the position system's right-hand side (8.1). Coulomb friction rows
  /// (5.4) get their bounds ±mu lambda_normal from lambda: PGS and Jacobi update them before
  /// every sweep, the direct path iterates them to a fixed point.
  SolverSummary solve_system(const System& sys, const VecX& b, VecX& lambda) const {
    return solve_system(sys, b, lambda, scene_.solver);
  }
  SolverSummary solve_system(const System& sys, VecX& lambda) const {
    return solve_system(sys, sys.b, lambda, scene_.solver);
  }
  /// The same with other solver settings (e.g. the direct path for a cross-check).
  SolverSummary solve_system(const System& sys,
                             const VecX& b,
                             VecX& lambda,
                             const SolverSettings& settings) const;
  /// The pipeline stages the last step ran, in order (collision, rows, assembly, solve, …).
  const std::vector<std::string>& stages() const { return stages_; }
  /// The contact manifolds of the last step (4).
  const std::vector<Manifold>& manifolds() const { return manifolds_; }

  /// Called inside every step with the step's system, its lambda and v2 (for cross-checks).
  using Observer = std::function<void(const System&, const VecX& lambda, const VecX& v2)>;
  void set_observer(Observer observer) { observer_ = std::move(observer); }

  const Scene& scene() const { return scene_; }
  std::vector<Body>& bodies() { return scene_.bodies; }
  double time() const { return t_; }
  long steps_done() const { return steps_; }
  /// Kinetic plus gravitational potential energy −m g·x of the movable bodies, J.
  double energy() const;
  /// max |c| over the distance constraints (5.2.2), m.
  double max_constraint_error() const;

 private:
  Scene scene_;
  double t_ = 0.0;
  long steps_ = 0;
  VecX warm_lambda(const System& sys, const std::unordered_map<std::uint64_t, double>& warm) const;
  std::unordered_map<std::uint64_t, double> warm_;  ///< row id → last lambda, N
  /// row id → last λ_position − λ, N: the position system's push increment (8.1)
  std::unordered_map<std::uint64_t, double> warm_position_;
  Observer observer_;
  bool collision_stage_ = false;  ///< the scene has a pair that may collide
  std::vector<std::string> stages_;
  std::vector<Manifold> manifolds_;
  std::vector<Row> rows_;  ///< this step's rows, kept for their storage
  System sys_;             ///< this step's system, kept for its storage
};

}  // namespace cbps
