// The convergence study of `cbps converge`: one system (a scene's step, or a stored problem)
// solved by each solver spec from the same guess, with the error after every sweep against the
// iterations and the sweeps' run time (docs/convergence.md).
//
// After every sweep it records the wall time of the sweeps so far (the recording itself is not
// timed), the natural-map residual (6.2), the error against the direct solution (lambda where A
// is positive definite, else only the unique v2 of 12.3.1) and the QP objective
// ½ λᵀ A λ − bᵀ λ. The direct path (6.2) is one point: its time and residual. With
// record_every K only every K-th sweep (and the guess and the last sweep) is kept; the
// milestones are still taken from every sweep.
#pragma once

#include <cmath>
#include <cstddef>
#include <functional>
#include <iterator>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "cbps/io/stored_problem.hpp"
#include "cbps/scene/scene.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/studies/solver_spec.hpp"
#include "cbps/system/system.hpp"

namespace cbps {

/// The residuals the summary reports the first sweep and time for, N.
inline constexpr double kConvergenceMilestones[] = {1e-3, 1e-6, 1e-10};

/// The system under study and what is known about its answer. With constraint-force mixing
/// (the stored cfm) the problem studied is that of A + eps E, the one the step solved; A stays
/// J Minv Jᵀ and eps travels in each solver's options (study_options).
struct ConvergenceSystem {
  std::string name;
  std::optional<long> step;  ///< a scene's step; none for a stored problem
  StoredProblem stored;      ///< A, b, cmin, cmax; J, Minv, v1, fext, dt when known; cfm
  /// The previous step's lambda by row id as it was (scenes after step 0), else 0, N: each
  /// spec's warm-start factors scale it once (7).
  VecX previous_lambda;
  VecX lambda_star, v2_star;   ///< the reference (solve_reference)
  bool lambda_unique = false;  ///< A + eps E numerically definite: lambda* is the answer

  bool has_bodies() const { return stored.has_bodies(); }
  /// The problem the solvers are handed (A = J Minv Jᵀ; each applies the cfm itself).
  BoxedProblem problem() const { return stored.problem(); }
  /// The natural-map residual of lambda for the problem of A + eps E (6.2), N.
  double residual(const VecX& lambda) const {
    return natural_map_residual(problem(), lambda, stored.cfm);
  }
  VecX v2(const VecX& lambda) const {
    return compute_v2(stored.v1, stored.Minv, stored.J, lambda, stored.fext, stored.dt);
  }
};

/// A stored problem (a `cbps matrices` folder or a Siconos file) to study; InputError when its
/// A is not symmetric (the direct path, the reference, solves the QP of 6.2).
ConvergenceSystem convergence_system(const std::string& path);
/// The system of step `at_step` of `scene` (Simulation::build_system, with A) to study, with
/// the simulation's last lambda, named `name`. The steps before it by the scene's method, or by
/// the exact path where that method does not take the scene's cones; progress on stderr as
/// step_to's ("cbps converge: stepping to ...") unless `quiet`. InputError under Coulomb's box
/// with mu > 0: its bounds move with lambda, so the step is not one boxed problem.
ConvergenceSystem convergence_system(Scene scene,
                                     const std::string& name,
                                     long at_step,
                                     bool quiet);

/// The reference: the direct path from lambda = 0 into s.lambda_star (and v2_star); lambda is
/// unique when A + eps E is numerically definite, as the direct path judges it (CHOLMOD's
/// rcond ≥ kDefiniteRcond). A singular A can still factor in floating point: four contacts per
/// face give rcond ~1e-17.
SolverSummary solve_reference(ConvergenceSystem& s);

/// One recorded point of a run.
struct ConvergenceSample {
  int iteration = 0;
  double time_s = 0.0, residual = 0.0, lambda_error = NAN, velocity_error = NAN, objective = 0.0;
};

/// The first sweep and time at which the residual reached a milestone; iteration −1: not yet.
struct ConvergenceMilestone {
  int iteration = -1;
  double time_s = 0.0;
};

/// One spec's run.
struct ConvergenceRun {
  SolverSpec spec;
  std::vector<ConvergenceSample> samples;  ///< the guess, every K-th sweep, the last
  std::string stopped;                     ///< why the sweeps ended
  /// A peer (peers.hpp) exposes no iterates: its samples are the guess and its final point.
  bool final_point_only = false;
  std::string peer_status;      ///< the peer's own word on its answer, empty for cbps's methods
  double convert_time_s = 0.0;  ///< a peer's conversion to its storage (in the final time)
  ConvergenceMilestone reached[std::size(kConvergenceMilestones)];
  void reach(int iteration, double time_s, double residual) {
    for (std::size_t i = 0; i < std::size(kConvergenceMilestones); ++i)
      if (reached[i].iteration < 0 && residual <= kConvergenceMilestones[i])
        reached[i] = {iteration, time_s};
  }
};

/// How long each run may sweep, and what it keeps.
struct ConvergenceLimits {
  int iterations = 100000;  ///< max sweeps per spec
  /// Which sweeps convergence.csv keeps (recorded_sweep): every K-th, or 0 (kRecordLog): every
  /// sweep to 100, then 100 a decade.
  int record_every = 1;
  double tolerance = SolveSettings{}.tolerance;  ///< stop at this residual, N
  double time_limit = 10.0;                      ///< max sweep time per spec, s
  std::uint64_t seed = 0;                        ///< of random row orders
  /// Called every 1000 sweeps with (spec, sweeps, time s, residual N); may be empty.
  std::function<void(const SolverSpec&, int, double, double)> progress;
};

/// ConvergenceLimits::record_every for log-spaced samples (`--record-every log`, converge's
/// default): 100,000 sweeps are 400 rows a solver, not 100,000 (36 MB for the chain study).
inline constexpr int kRecordLog = 0;
/// Whether sweep k (>= 1) is one of the recorded: k a multiple of record_every, or with kRecordLog
/// every k up to 100 and then the first k of each hundredth of a decade (k where
/// floor(100 log10 k) steps).
bool recorded_sweep(int k, int record_every);

/// The sample at lambda: residual, errors against the reference, objective (6.2).
ConvergenceSample measure(const ConvergenceSystem& s,
                          const VecX& lambda,
                          int iteration,
                          double time_s);

/// An iterative spec from the warm-start guess, sweep by sweep (the solvers as `cbps run` uses
/// them; they time their sweeps and hand each iterate out of the clock). InputError when the
/// spec needs what the system lacks (J and Minv, row kinds).
ConvergenceRun run_iterative(const ConvergenceSystem& s,
                             const SolverSpec& spec,
                             const ConvergenceLimits& limits);
/// An exact spec (direct, active set, Lemke) from lambda = 0: one point, stopped by its own
/// termination, or "residual tolerance" where it stopped short of its floor within the limits'
/// tolerance.
ConvergenceRun run_exact(const ConvergenceSystem& s,
                         const SolverSpec& spec,
                         const ConvergenceLimits& limits);
/// A peer (siconos:NAME, bullet:NAME) from lambda = 0 with the limits' iterations and
/// tolerance: the guess and its final point, marked final_point_only (none of them hands out its
/// iterates), with its conversion and solve time.
ConvergenceRun run_peer(const ConvergenceSystem& s,
                        const SolverSpec& spec,
                        const ConvergenceLimits& limits);

/// How a tao:TYPE spec runs: PETSc/TAO in this process (distributed/tao_studies.hpp), which only
/// a build with PETSc has; empty where none may be given.
using ConvergenceTao = std::function<ConvergenceRun(
    const ConvergenceSystem&, const SolverSpec&, const ConvergenceLimits&)>;

/// Any spec, as its kind runs: tao:TYPE by `tao`, a peer by run_peer, an exact method by
/// run_exact, an iterative one by run_iterative.
ConvergenceRun run_spec(const ConvergenceSystem& s,
                        const SolverSpec& spec,
                        const ConvergenceLimits& limits,
                        const ConvergenceTao& tao = {});

/// The specs whose own guess already solves the system (residual ≤ tolerance): they show no
/// convergence. The message for it, empty when none.
std::string solved_by_guess_warning(const ConvergenceSystem& s,
                                    const std::vector<ConvergenceRun>& runs,
                                    double tolerance);

/// summary.json (docs/outputs.md).
nlohmann::json convergence_summary(const ConvergenceSystem& s,
                                   const SolverSummary& reference,
                                   const std::vector<ConvergenceRun>& runs,
                                   const ConvergenceLimits& limits,
                                   const std::string& warning);
/// convergence.csv: one line per recorded sample.
std::string convergence_csv(const std::vector<ConvergenceRun>& runs);
/// A milestone's key in summary.json's "reached": "0.001", "1e-06", "1e-10".
std::string milestone_key(double residual);

}  // namespace cbps
