// The time step (paper 3.2 with 4, 5, 6.2, 7, 8 and 12.3): the stages in order,
//   Collision (4) → Rows (5.2–5.4) → Assembly (6.1, 6.2.9) → Solve (7.1.1 / 6.2) →
//   [PositionSystem (8.1)] → Integrate (12.3.1, 3.2),
// with the divergence guard (guard.hpp) after every solve.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "cbps/collision/collision.hpp"
#include "cbps/collision/persistence.hpp"
#include "cbps/scene/scene.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/system/system.hpp"

namespace cbps {

/// The stages of one step, in the order they run (after Box2D's b2SolverStageType); each is
/// named with the paper's equations by stage_name. The rows stage is reported by kind.
enum class Stage {
  Collision,     ///< 4: broad phase, narrow phase → contact manifolds
  DistanceRows,  ///< 5.2: distance rows
  ContactRows,   ///< 5.3: contact rows
  FrictionRows,  ///< 5.4: friction rows
  Assembly,      ///< 6.1, 6.2.9: J, Minv, v1, fext, A, b
  /// 6.1, 6.2.9 without A: J, Minv, v1, fext, b, when nothing of the step reads A
  /// (Simulation::forms_A)
  AssemblyWithoutA,
  Solve,           ///< 7.1.1 / 6.2: lambda (the velocity system of 8.1 under the improved push)
  PositionSystem,  ///< 8.1: the position system (improved push only)
  Integrate        ///< 12.3.1, 3.2: v2, momenta, positions
};

/// A stage's name as summaries give it, e.g. "collision (4)", "solve_pgs (7.1.1)",
/// "velocity_system_pgs (8.1)"; `method` and `push` name the solve stages.
std::string stage_name(Stage stage, Method method, PushMode push);

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
  /// Rows that continue a row of the last step (the same row id, Row::id), so their lambda
  /// starts from last step's (7); the others start from 0.
  int warm_rows = 0;
  int contacts = 0;  ///< contact points found this step (4)
  /// The friction the step's system solved (System::contacts): its contacts with friction rows,
  /// the smallest and largest of their mu (0 with none) and the law their rows carry.
  int friction_contacts = 0;
  double mu_min = 0.0, mu_max = 0.0;
  FrictionLaw law = FrictionLaw::PaperBox;
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

  /// One step of dt, stage by stage (Stage): contacts (4) → rows (5.2–5.4) → system (6.1,
  /// 6.2.9) → lambda (7) → v2 (12.3.1) → [the position system, 8.1] → positions (3.2) and
  /// momenta p = m v2, l = I omega2.
  /// Throws DivergenceError naming the step, body and row when lambda or v2 turn non-finite or
  /// a body's speed or spin exceeds World::divergence_speed / divergence_spin; the bodies then
  /// stay as they were before the step.
  StepReport step();

  /// The rows of the current state, into `rows` (storage reused), after collision detection
  /// (4), whose manifolds go to `manifolds`: build_rows (rows/build_rows.hpp) with the scene's
  /// world.
  void build_rows(std::vector<Row>& rows,
                  std::vector<Manifold>& manifolds,
                  StageTimes* times = nullptr) const;
  std::vector<Row> build_rows() const;
  /// The system of the current state, not solved (6.1, 6.2.9), as a new System: under a
  /// substepping scheme (World::scheme) the first substep's, with dt = h and the scheme's rows
  /// and softness (step/scheme.hpp).
  System build_system() const;
  /// The same, assembled into the simulation's own System, whose storage is reused from step
  /// to step; step() calls this, so A is formed only when forms_A() (build_system() always
  /// forms it). The reference stays valid until the next assemble() or step().
  const System& assemble(StageTimes* times = nullptr);
  /// The warm-start guess for a system (7): last step's lambda by row id times the row's
  /// warm-start factor (SolverSettings::warm, warm_friction), else 0.
  VecX initial_lambda(const System& sys) const;
  /// Last step's lambda by row id as it was (no factor), else 0.
  VecX last_lambda(const System& sys) const;
  /// The position system's starting guess (8.1): the velocity system's lambda plus last step's
  /// push increment lambda_position − lambda by row id (times the rows' warm-start factors).
  VecX position_guess(const System& sys, const VecX& lambda) const {
    return lambda + warm_lambda(sys, warm_position_);
  }
  /// Solves A lambda = b of `sys` with the scene's solver settings, from the guess in lambda;
  /// `b` is sys.b, or the position system's right-hand side (8.1). Coulomb friction rows
  /// (5.4) get their bounds ±mu lambda_normal from lambda (solve_coulomb).
  SolverSummary solve_system(const System& sys, const VecX& b, VecX& lambda) const {
    return solve_system(sys, b, lambda, scene_.solver);
  }
  SolverSummary solve_system(const System& sys, VecX& lambda) const {
    return solve_system(sys, sys.b, lambda, scene_.solver);
  }
  /// The solver options of this step from `settings`: its seed advanced by the steps done, the
  /// direct path's memory of the steps before (SolverOptions::Direct::memory).
  SolverOptions step_options(const SolverSettings& settings) const;
  /// The same with other solver settings (e.g. the direct path for a cross-check).
  SolverSummary solve_system(const System& sys,
                             const VecX& b,
                             VecX& lambda,
                             const SolverSettings& settings) const;
  /// The stages the last step ran, in order, by stage_name.
  const std::vector<std::string>& stages() const { return stages_; }
  /// The contact manifolds of the last step (4).
  const std::vector<Manifold>& manifolds() const { return manifolds_; }

  /// Whether a step of `rows` rows forms A = J Minv Jᵀ (6.2.9): only when something reads it,
  /// the method (reads_A: every one but matrix-free and direct on boxes), an observer, or the
  /// direct path below its interior_from_rows (500), whose active-set path factors A itself
  /// (there forming A once in the assembly is cheaper than in each system's solve). The step's
  /// System has A empty otherwise, and its stages name the assembly "without A".
  bool forms_A(Eigen::Index rows) const;

  /// Called inside every step with the step's system, its lambda and v2 (for cross-checks).
  /// The system it sees has A formed.
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
  using WarmStart = std::unordered_map<std::uint64_t, double>;  ///< row id → lambda, N

  /// One step of a substepping scheme (tgs, soft-step, xpbd; step/scheme.hpp): contacts found
  /// once (4), then N substeps of h = dt/N, each the paper's stages on the manifolds carried
  /// with the bodies (carry_contacts).
  StepReport scheme_step();
  /// One substep's solves and integration (Integrate, 3.2) of the system in sys_.
  void substep(StepReport& report);
  /// A substep's system from `manifolds` (the scheme's rows, dt = h, softness), into `rows` and
  /// `sys`; A formed when forms_A says, when the scheme softens rows, or always_form_A.
  void substep_system(const std::vector<Manifold>& manifolds,
                      std::vector<Row>& rows,
                      System& sys,
                      bool always_form_A,
                      StageTimes* times) const;
  /// Collision detection (4): the manifolds of the bodies' pairs within the contact margin.
  void detect_contacts(std::vector<Manifold>& manifolds, StageTimes* times) const;
  /// The stage list of this step, by stage_name.
  void name_stages();
  /// The velocities a step starts from: the bodies' own (v1 as assembled), or under
  /// Integrator::Gyroscopic the angular parts after Bullet's step, with b (6.2.9) of them.
  void start_velocities(System& sys) const;
  /// The position system of the improved push factor (8.1, solve_position_system), from the
  /// velocity system's lambda: the velocities that move the bodies this step, guarded.
  VecX position_velocities(const System& sys, const VecX& lambda, StepReport& report);
  /// Momenta from v2 with this step's inertia, then positions moved by v_move (3.2).
  void integrate(const System& sys, const VecX& v2, const VecX& v_move, StageTimes& times);
  /// The step's rows, contact points and deepest penetration, into the report.
  void report_contacts(const System& sys, StepReport& report) const;
  /// StepReport::cfm_acceleration_error: eps max |lambda_k|, m/s² (0 without CFM).
  double cfm_acceleration_error(const System& sys, const VecX& lambda) const;
  /// How the divergence guard names the system solved for v2.
  static const char* system_name(PushMode push);
  /// lambda by row id, for the next step's warm start (7).
  void remember(const System& sys, const VecX& lambda);
  /// Contact persistence is on (World::contact_persistence > 0) and the scene has contacts.
  bool persistence() const { return collision_stage_ && scene_.world.contact_persistence > 0.0; }
  /// The rows of `sys` whose id was a row of the last step (StepReport::warm_rows).
  int continued_rows(const System& sys) const;
  /// The values of `warm` by row id (0 for a row it lacks), times each row's warm-start factor
  /// when `scaled` (warm_guess).
  VecX warm_lambda(const System& sys, const WarmStart& warm, bool scaled = true) const;

  Scene scene_;
  double t_ = 0.0;
  long steps_ = 0;
  WarmStart warm_;  ///< row id → last lambda, N
  /// What the direct path keeps from step to step (SolverOptions::Direct::memory).
  std::shared_ptr<ExactMemory> exact_memory_;
  /// row id → last λ_position − λ, N: the position system's push increment (8.1)
  WarmStart warm_position_;
  /// Last step's contact points, for contact persistence (World::contact_persistence).
  ContactMemory contacts_;
  Observer observer_;
  bool collision_stage_ = false;  ///< the scene has a pair that may collide
  std::vector<std::string> stages_;
  bool A_formed_ = true;  ///< the last assembly formed A (forms_A)
  std::vector<Manifold> manifolds_;
  std::vector<Row> rows_;  ///< this step's rows, kept for their storage
  System sys_;             ///< this step's system, kept for its storage
};

/// Column labels of J: "<body>.vx" … "<body>.wz" for each movable body of `sys` (6.1.1), named
/// as in `scene`.
std::vector<std::string> column_labels(const Scene& scene, const System& sys);

}  // namespace cbps
