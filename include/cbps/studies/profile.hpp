// Performance profiles (Dolan & Moré, Math. Program. 91, 2002) of solvers over a problem
// library (scripts/make_problem_library.py): the study behind `cbps profile`.
//
// Every solver runs on every problem from lambda = 0. After each sweep the unit-free residual
// (system/unit_free.hpp: each row's natural map with its own step 1/A_kk over the force scale),
// the one measure `cbps lcp`'s verdict and the tests judge answers by, is taken; the first sweep
// and time at which it falls to 1e-4, 1e-8 and 1e-10 (the tolerances of Acary, Brémond & Huber
// 2018's profiles) are the solver's costs there (not reached within the budget: a failure,
// ratio ∞). Time is the wall time from the call of solve() to the
// end of that sweep less the time spent measuring, so a method's setup (ADMM's factorization)
// counts. A measurement whose time is below kRepeatBelow is taken again, kRepeats times in
// all and more while the runs add up to less than kRepeatSpan (kMostRepeats at most), and each
// time kept is the least of the runs (best_of_runs), for every solver alike. The
// exact paths (direct, active-set) are one solve each, told 1e-10 as their tolerance
// (as `cbps lcp` tells them by default): their cost at a tolerance is
// the solve's time if its final residual meets it. They have no sweeps, so they are in the time
// profiles only. A peer reports only its final point: a pivoting one runs once, like the exact
// paths; an iterative one (siconos:pgs, bullet:pgs) runs once per tolerance, told it, and its
// sweeps and time there are that run's (not the finest run's at every tolerance).
#pragma once

#include <cmath>
#include <cstddef>
#include <functional>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cbps/io/stored_problem.hpp"
#include "cbps/studies/performance_profile.hpp"
#include "cbps/studies/solver_spec.hpp"
#include "cbps/system/unit_free.hpp"

namespace cbps {

/// The unit-free residuals whose first sweep and time are the costs.
inline constexpr double kProfileTolerances[] = {1e-4, 1e-8, 1e-10};
inline constexpr std::size_t kProfileTolerancesCount = std::size(kProfileTolerances);
/// The tau at which the summary reports rho_s(tau).
inline constexpr double kProfileTaus[] = {1.0, 2.0, 10.0};

/// One problem of the library as its index (library.json) describes it.
struct ProfileEntry {
  std::string name;
  std::string path;   ///< absolute: a `cbps matrices` folder or a Siconos .dat file
  std::string exact;  ///< absolute: the direct path's lambda (lambda.mtx); empty: not known
  nlohmann::json index;
};

/// The index of LIBRARY (a folder holding library.json, or that file): its problems, only the
/// quick ones with `quick`. A folder without library.json is a folder of problems: its FCLIB
/// files (.hdf5, .h5), Siconos .dat files and `cbps matrices` folders, in name order, with no
/// lambda* (ProfileEntry::exact empty; `quick` is then an error). InputError naming the file for
/// anything missing or malformed.
std::vector<ProfileEntry> read_library(const std::string& library, bool quick);

/// A problem loaded for the solvers, with what is known about its answer. With a cfm.txt the
/// problem is that of A + eps E (the one the step solved); A stays J Minv Jᵀ and eps travels in
/// the solvers' options (study_options).
struct ProfileProblem {
  StoredProblem stored;
  VecX exact;             ///< the library's lambda*, N (empty: not known)
  bool definite = false;  ///< rank A = rows: lambda* unique, so ‖λ − λ*‖ means something
  bool symmetric = true;  ///< A symmetric to symmetry_tolerance (measured once, when read)
  double scale = 1.0;     ///< scale_of(A + eps E, b): the data's size, reported, not a measure
  /// With the row kinds and manifolds of the folder's labels.json (read_problem).
  BoxedProblem problem() const { return stored.problem(); }
  /// The unit-free residual of lambda for the problem of A + eps E (system/unit_free.hpp), the
  /// profile's measure.
  double relative(const VecX& lambda) const {
    return unit_free_residual(problem(), lambda, stored.cfm).relative;
  }
};

/// Reads an entry's problem and lambda* (where the entry has one); InputError when lambda* does
/// not fit. A method that needs a symmetric A is "not applicable" on a problem without one.
ProfileProblem load_profile_problem(const ProfileEntry& e);

/// The first sweep and time at which the relative residual reached a tolerance; −1: never.
struct ProfileReached {
  long iterations = -1;
  double time_s = 0.0;
};

/// One solver on one problem.
struct ProfileMeasurement {
  std::string status;  ///< "solved" (1e-10 reached) or why it stopped short
  long iterations = 0;
  double time_s = 0.0;
  double residual = NAN;      ///< relative, at the end
  double lambda_error = NAN;  ///< ‖λ − λ*‖∞ at the end, N, where lambda* is unique
  ProfileReached reached[kProfileTolerancesCount];
  /// A peer (peers.hpp): its final point only (no iterates), its own word, its conversion time
  /// (in time_s, which is its conversion and solve: the process around Siconos not counted).
  bool final_point_only = false;
  std::string peer_status;
  double convert_time_s = 0.0;
  void reach(long iteration, double time, double relative_residual) {
    for (std::size_t i = 0; i < kProfileTolerancesCount; ++i)
      if (reached[i].iterations < 0 && relative_residual <= kProfileTolerances[i])
        reached[i] = {iteration, time};
  }
};

/// The budget of one solver on one problem.
struct ProfileLimits {
  int budget_iterations = 100000;  ///< sweeps (TAO's iterations for tao:TYPE)
  double time_limit = 1.0;         ///< s
};

/// A measurement shorter than this (s) is taken kRepeats times in all, and beyond that until its
/// runs add up to kRepeatSpan (s) or kMostRepeats runs; its times are the least of the runs. A
/// solve of a millisecond or less varies from run to run by up to twice its time (caches, pages
/// and the allocator met for the first time: the first solver run on Siconos' Rover4609, 15
/// rows, took 0.64 ms in a profile and 0.29 ms as the best of 5 runs), and the least of five
/// runs by half its time from one process to the next (OneObject-i100000-499 under `direct`:
/// 1.2 ms in three profiles, 1.8 ms in two, where 300 solves in one process are never below
/// 1.1 ms).
inline constexpr double kRepeatBelow = 0.1;
inline constexpr int kRepeats = 5;
inline constexpr double kRepeatSpan = 0.02;
inline constexpr int kMostRepeats = 20;

/// `run` (a measurement from lambda = 0) once, then, while its time is below kRepeatBelow, again
/// up to kRepeats runs in all, and on while the runs add up to less than kRepeatSpan, up to
/// kMostRepeats: the first run's statuses, sweeps and residuals (the runs are deterministic),
/// each time (the total and each tolerance's) the least of the runs that reached it at the same
/// sweep.
ProfileMeasurement best_of_runs(const std::function<ProfileMeasurement()>& run);

/// The final relative residual and lambda error of lambda.
void finish_measurement(ProfileMeasurement& m, const ProfileProblem& p, const VecX& lambda);
/// An iterative spec from lambda = 0, sweep by sweep, within the limits.
ProfileMeasurement profile_iterative(const ProfileProblem& p,
                                     const SolverSpec& spec,
                                     const ProfileLimits& o);
/// An exact spec: one solve, stopped at the time limit.
ProfileMeasurement profile_exact(const ProfileProblem& p,
                                 const SolverSpec& spec,
                                 const ProfileLimits& o);
/// A peer (siconos:NAME, bullet:NAME) from lambda = 0 with the budget's iterations: a pivoting
/// one solves once, told the finest tolerance times the scale, and its final point counts for
/// every tolerance it meets; an iterative one solves once per tolerance, told it, and each run's
/// iterations and time count where its point meets a tolerance. "not applicable: ..."
/// where the peer cannot take the problem (peer_refusal).
ProfileMeasurement profile_peer(const ProfileProblem& p,
                                const SolverSpec& spec,
                                const ProfileLimits& o);

/// How a tao:TYPE spec is measured: PETSc/TAO in this process (distributed/tao_studies.hpp),
/// which only a build with PETSc has; empty where none may be given.
using ProfileTao = std::function<ProfileMeasurement(
    const ProfileProblem&, const SolverSpec&, const ProfileLimits&)>;

/// Any spec, as its kind is measured: tao:TYPE by `tao`, a peer by profile_peer, an iterative
/// method by profile_iterative, an exact one by profile_exact.
ProfileMeasurement profile_spec(const ProfileProblem& p,
                                const SolverSpec& spec,
                                const ProfileLimits& limits,
                                const ProfileTao& tao = {});

/// One profile: a tolerance, a cost (time or sweeps) and the solvers it compares.
struct Profile {
  double tolerance = 0.0;
  std::string measure;               ///< "time" or "sweeps"
  std::vector<std::size_t> solvers;  ///< indices into the specs
  CostTable ratios;                  ///< [problem][position in solvers]
};

/// The profile at tolerance index t of time (or sweeps) over runs[problem][spec].
Profile make_profile(double tolerance,
                     std::size_t t,
                     bool sweeps,
                     const std::vector<SolverSpec>& specs,
                     const std::vector<std::vector<ProfileMeasurement>>& runs);

/// summary.txt: per tolerance, per solver the problems solved and rho_s(tau) at 1, 2, 10 for
/// time and sweeps.
std::string profile_summary_text(const std::vector<ProfileEntry>& entries,
                                 const std::vector<SolverSpec>& specs,
                                 const std::vector<Profile>& profiles,
                                 const ProfileLimits& o,
                                 double wall_time_s);

/// profile.json's entry of one profile.
nlohmann::json profile_json(const Profile& profile, const std::vector<SolverSpec>& specs);

/// profile.json (format cbps-profile/1, docs/outputs.md) and profile.csv of a finished study.
struct ProfileReport {
  nlohmann::json json;
  std::string csv;
};
ProfileReport profile_report(const std::string& library,
                             bool quick,
                             const ProfileLimits& limits,
                             double wall_time_s,
                             const std::vector<ProfileEntry>& entries,
                             const std::vector<ProfileProblem>& problems,
                             const std::vector<SolverSpec>& specs,
                             const std::vector<std::vector<ProfileMeasurement>>& runs,
                             const std::vector<Profile>& profiles);

/// InputError (exit 2) when two specs of --solvers would draw the same curve: the same text
/// twice (`pgs,pgs`) or two texts for the same solver (`pgs,psor:1`, `pgs,pgs:warm=off`).
void refuse_duplicates(const std::vector<SolverSpec>& specs, const std::string& list);

}  // namespace cbps
