// A scene: bodies, constraints, world settings and solver settings. JSON scene files
// (scene_json.hpp) and the built-in parametric scenes (builtin.hpp) both produce this struct,
// so the solver never sees where a scene came from.
#pragma once

#include <algorithm>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cbps/body/body.hpp"
#include "cbps/rows/build_rows.hpp"
#include "cbps/rows/distance.hpp"
#include "cbps/solvers/solver.hpp"

namespace cbps {

/// The contact margin of JSON scene files and built-in scenes unless they say otherwise, m: a
/// resting contact that separates by a rounding error within a step keeps its row, so its rows
/// do not flicker from step to step (box-on-plane: 12 rows every step, not 12, 6 or 9).
inline constexpr double kSceneContactMargin = 1e-3;

/// The contact persistence of JSON scene files and built-in scenes unless they say otherwise, m
/// (World::contact_persistence): Bullet's contact breaking threshold, 0.02 m
/// (gContactBreakingThreshold, btPersistentManifold.cpp).
inline constexpr double kSceneContactPersistence = 0.02;

/// How a step advances time (World::scheme, docs/schemes.md): the paper's one solve per step,
/// or a substepping scheme of the engines PGS is compared with. Every scheme poses each substep
/// as the paper's system (6.2.9) with dt/N; the contact manifolds (4) are found once a step and
/// their points carried with the bodies between substeps.
enum class Scheme {
  Paper,     ///< one system per step (3.2, 6.2.9, 7.1.1), the default
  Tgs,       ///< Tonge's temporal Gauss-Seidel: N substeps of dt/N, the rigid rows as in Paper
  SoftStep,  ///< Catto's soft step (Box2D v3): soft push system, then a rigid relax, N substeps
  Xpbd       ///< Macklin et al.'s XPBD in its linear form: beta 1, compliance, cold substeps
};

/// The schemes' names in Scheme order (scene files' "scheme", --scheme).
const std::vector<std::string>& scheme_names();
/// The scheme of that name (scheme_names()); nullopt for any other.
std::optional<Scheme> scheme_named(const std::string& name);

/// The substeps of tgs, soft-step and xpbd when a scene file or the command line names the
/// scheme without them (Box2D v3's default substep count, 4).
inline constexpr int kSchemeSubsteps = 4;

/// A scheme's settings (World::scheme; docs/schemes.md gives each its source).
struct SchemeSettings {
  Scheme kind = Scheme::Paper;
  int substeps = 1;  ///< N: each step is N substeps of dt/N (1 for Paper)
  /// soft-step: the contact rows' stiffness, Hz, at most a quarter of the substep rate N/dt
  /// (Box2D v3's contactHertz, 30); twice this against a static body (its staticSoftness).
  double contact_hertz = 30.0;
  double contact_damping_ratio = 10.0;  ///< soft-step: contact damping ratio (Box2D v3: 10)
  double joint_hertz = 60.0;            ///< soft-step: distance rows' stiffness, Hz (Box2D v3: 60)
  double joint_damping_ratio = 2.0;     ///< soft-step: distance rows' damping ratio (Box2D v3: 2)
  /// soft-step: the most a contact's push asks, m/s (Box2D v3's contactPushMaxVelocity, 3)
  double max_push_speed = 3.0;
  /// xpbd: every row's compliance alpha, m/N (kg⁻¹ s² per unit of lambda); 0: rigid rows
  double compliance = 0.0;
  /// tgs, soft-step, xpbd: contacts are found once a step, so pairs up to this far apart are
  /// kept (as gaps, rows that let the gap close within a substep and no more), m: a pair that
  /// closes during the step's substeps has its rows. Box2D v3's speculative distance, 4 linear
  /// slops = 0.02 m. The world's contact_margin when that is larger.
  double speculative_distance = 0.02;
};

struct World {
  Vec3 gravity{0.0, -9.81, 0.0};  ///< g, m/s² (y is up)
  double dt = 1.0 / 240.0;        ///< time step, s
  double beta = 0.2;              ///< Baumgarte push factor (5.2.3, 5.3), dimensionless in [0, 1]
  PushMode push = PushMode::Original;
  Integrator integrator = Integrator::Paper;  ///< how a step turns the bodies (body.hpp)
  SchemeSettings scheme;                      ///< how a step advances time (docs/schemes.md)
  double mu = 0.0;                            ///< friction coefficient (5.4); 0: no friction rows
  /// Every contact's friction law (5.4, base/friction_law.hpp; scene keys `friction` and `cone`)
  FrictionLaw friction = FrictionLaw::PaperBox;
  double restitution = 0.0;            ///< epsilon of 8.2.1, in [0, 1]
  double restitution_threshold = 0.1;  ///< approach speed below which no bounce (8.2), m/s
  /// Contacts kept up to this separation (4), m. 0 here for scenes built in code (the stress
  /// catalogue, tests); scene files and built-in scenes default to kSceneContactMargin.
  double contact_margin = 0.0;
  /// Contact persistence, m (7, collision/persistence.hpp): a contact point found within this
  /// distance of where a point of the same pair sat on both bodies last step continues that
  /// point, so its rows keep their ids and their warm start. 0: off, a point is known again only
  /// by its clipping feature id (ContactPoint::feature). 0 here for scenes built in code; scene
  /// files and built-in scenes default to kSceneContactPersistence.
  double contact_persistence = 0.0;
  /// A step diverges when a body's speed |v| or spin |omega| exceeds these (or any value turns
  /// non-finite): the run stops there with a DivergenceError naming step, body and row.
  double divergence_speed = 1e4;  ///< m/s
  double divergence_spin = 1e4;   ///< rad/s

  /// The settings of the row stage (5.2–5.4) taken from this world.
  RowSettings rows() const;
  /// How far apart a pair's contact points are kept (4), m: the contact margin, or under a
  /// substepping scheme the larger of it and the scheme's speculative distance.
  double detection_margin() const {
    return scheme.kind == Scheme::Paper ? contact_margin
                                        : std::max(contact_margin, scheme.speculative_distance);
  }
  /// The method a scene of this world solves with when none is named: the paper's PGS (7.1.1),
  /// on friction cones its cone form nsgs (docs/cones.md).
  Method default_method() const { return is_cone(friction) ? kConeSweepMethod : kPaperMethod; }
};

/// A scene's solver, as scene files and `--solver` give it: the settings of every solve a step
/// makes (SolveSettings, solver.hpp, with its defaults) and whether it starts from last step's
/// lambda.
struct SolverSettings : SolveSettings {
  /// Warm-start factor F (7): a step starts each row from F times its lambda of the last step
  /// (matched by row id, Row::id), 0 for a new row. 1: the paper's guess, last step's lambda;
  /// 0: a cold start from lambda = 0. In [0, 1].
  double warm = 1.0;
  /// The factor G of the friction rows (5.4) instead of F, in [0, 1]; unset: F. Bullet's
  /// sequential-impulse solver, for one, keeps 0.85 of the contact impulses and none of the
  /// friction ones.
  std::optional<double> warm_friction;

  /// The options of one solve with these settings; the seed is `seed` as it is (a simulation
  /// adds its step count, so that random orders differ from step to step).
  SolverOptions options() const;
  /// The warm-start factor of a row of this kind: warm_friction (else warm) for friction rows,
  /// warm for the others.
  double warm_factor(RowKind kind) const {
    return kind == RowKind::Friction ? warm_friction.value_or(warm) : warm;
  }
};

/// A row's warm-start guess (7): factor × its last lambda (N), exactly +0 for the factor 0 (a
/// cold start) and exactly the last lambda for the factor 1 (the paper's warm start).
inline double warm_guess(double last_lambda, double factor) {
  return factor == 0.0 ? 0.0 : factor * last_lambda;
}

struct Scene {
  std::string name;
  /// The parameters a built-in scene was made with, as name → value text (for summaries).
  std::vector<std::pair<std::string, std::string>> parameters;
  World world;
  SolverSettings solver;
  double duration = 10.0;  ///< default simulated time, s
  std::vector<Body> bodies;
  std::vector<DistanceConstraint> distances;

  /// True when some pair of bodies may collide: both collide, not both static (4). A scene
  /// without such a pair runs no collision stage.
  bool has_contact_pairs() const;
};

/// Rescales a scene's units (paper 9): lengths by L, masses by M, times by T. Positions,
/// sizes, anchors and lengths ×L; masses ×M; inertia ×M L²; dt and duration ×T; velocities
/// ×L/T; angular velocities ×1/T; gravity ×L/T²; momenta accordingly. beta is unchanged.
Scene rescale_units(const Scene& scene, double L, double M, double T);

}  // namespace cbps
