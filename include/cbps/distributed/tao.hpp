// The boxed problem of 6.2 on PETSc/TAO under MPI: `cbps lcp PROBLEM --solver tao:TYPE`, run
// alone or as `mpirun -n N cbps lcp ...` (docs/distributed.md). Built only when PETSc is found
// (CMake option CBPS_PETSC; the macro CBPS_HAVE_PETSC); only src/distributed/'s .cpp files (and
// its private petsc_util.hpp) include PETSc or MPI, so nothing here names a PETSc type. kTaoTypes,
// is_tao_type and tao_type_list are here for every build (the CLI's --help names the types either
// way).
//
// With A symmetric positive semidefinite (A = J Minv Jᵀ, 6.2.9) the boxed problem is the
// bound-constrained quadratic program
//   minimise f(lambda) = ½ lambdaᵀ A lambda − bᵀ lambda   subject to cmin ≤ lambda ≤ cmax,
// whose gradient is w = A lambda − b (6.2): its first-order (KKT) conditions are exactly the
// complementarity conditions of 6.2, so any TAO bound-constrained minimiser solves it.
//
//   Symbol   Shape   Unit   In PETSc
//   A        c×c     kg⁻¹   MATMPIAIJ, distributed by rows (each rank inserts only its own)
//   b        c       m/s²   VECMPI with A's row layout
//   cmin     c       N      VECMPI, −∞ as PETSC_NINFINITY
//   cmax     c       N      VECMPI, +∞ as PETSC_INFINITY
//   lambda   c       N      VECMPI (TAO's solution), gathered onto rank 0 at the end
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "cbps/system/boxed_problem.hpp"
#include "cbps/system/unit_free.hpp"

namespace cbps::distributed {

/// TAO's bound-constrained methods offered as `--solver tao:TYPE`, by TAO's own names:
/// quadratic only (bqpip, gpcg), Newton with a trust region (tron, bntr) or line search (bnls),
/// quasi-Newton (bqnls, blmvm) and nonlinear conjugate gradient (bncg).
inline constexpr const char* kTaoTypes[] = {
    "bqpip", "gpcg", "tron", "bncg", "bqnls", "blmvm", "bnls", "bntr"};

/// True when `type` is one of kTaoTypes.
inline bool is_tao_type(std::string_view type) {
  for (const char* t : kTaoTypes)
    if (type == t) return true;
  return false;
}
/// "tao:TYPE" (or "tao", "tao:...") asks for PETSc/TAO.
inline bool is_tao_solver(std::string_view text) {
  return text == "tao" || text.substr(0, 4) == "tao:";
}
/// kTaoTypes as "bqpip, gpcg, ..., bntr" for messages and --help.
inline std::string tao_type_list() {
  std::string list;
  for (const char* t : kTaoTypes) list += (list.empty() ? "" : ", ") + std::string(t);
  return list;
}

/// PETSc and MPI for one process of an MPI job: PetscInitialize when made, PetscFinalize when
/// destroyed. Make one, only on the path that uses it: the other commands never touch MPI.
/// Without mpirun the process is an MPI job of one rank (singleton start). PETSc's own signal
/// handlers stay off (cbps handles Ctrl-C itself); options may come from the environment
/// variable PETSC_OPTIONS (e.g. "-tao_monitor").
class MpiSession {
 public:
  MpiSession();
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }
  /// Collective: the lowest rank on which `failed` is true, or size() when none is.
  int first_failing_rank(bool failed) const;
  /// Collective: the `value` of rank `root`, on every rank.
  int broadcast(int value, int root = 0) const;
  /// Collective: every rank's `value` on rank 0, in rank order (empty on the other ranks).
  std::vector<double> gather(double value) const;
  /// Collective: the sum of `value` over the ranks before this one (0 on rank 0), and in
  /// `total` over every rank (an exclusive prefix sum: numbering rows built per rank).
  long sum_before(long value, long& total) const;

 private:
  int rank_ = 0;
  int size_ = 1;
};

/// What the monitor hands on after one TAO iteration (TaoOptions::monitor).
struct TaoIterate {
  int iteration = 0;      ///< TAO's iteration count (0: the start, before the first step)
  double residual = 0.0;  ///< natural-map residual of 6.2 on the distributed vectors, N
  /// Seconds since solve_tao_local was called (putting A into PETSc included), less the time spent
  /// in the monitor itself (its residual and the callback).
  double time_s = 0.0;
};

/// Called by the monitor after every TAO iteration with the iterate and this rank's rows of
/// lambda (N; on one rank the whole lambda). Return false to stop TAO (TAO_DIVERGED_USER).
using TaoMonitor = std::function<bool(const TaoIterate& at, const VecX& lambda_own_rows)>;

/// What `--solver tao:TYPE`, `--iterations` and `--tolerance` ask of TAO.
struct TaoOptions {
  std::string type;            ///< one of kTaoTypes
  int max_iterations = 10000;  ///< TaoSetMaximumIterations
  double tolerance = 1e-10;    ///< natural-map residual to stop at, and TAO's gatol, N
  /// When set, a TAO monitor (TaoSetMonitor) forms the natural-map residual after every
  /// iteration and calls this; `cbps converge` and `cbps profile` record TAO's history by it.
  /// One MatMult and a few vector operations per iteration, outside TaoIterate::time_s. An
  /// exception it throws stops TAO and is rethrown by solve_tao.
  TaoMonitor monitor;
};

/// A whole problem gathered onto rank 0 (small sizes only: --write-system).
struct GatheredSystem {
  SpMat A;     ///< c×c, kg⁻¹ (the exact path: formed on rank 0 from J and Minv)
  VecX b;      ///< c, m/s²
  VecX cmin;   ///< c, N (±kInf for no bound)
  VecX cmax;   ///< c, N
  SpMatRow J;  ///< c×6n (the exact path's problems; empty for TAO's)
  SpMat Minv;  ///< 6n×6n, block diagonal
};

/// What TAO returned, with the command's own measure of it.
struct TaoResult {
  VecX lambda;               ///< c, N: on rank 0 the whole solution, on the other ranks empty
  int iterations = 0;        ///< TAO's iterations (TaoGetSolutionStatus)
  std::string reason;        ///< TAO's converged reason, e.g. "CONVERGED_GATOL", "DIVERGED_MAXITS"
  bool converged = false;    ///< TAO's own claim: reason > 0
  double tao_residual = 0.;  ///< TAO's own stopping measure at the end (TaoGetSolutionStatus)
  std::string stop;          ///< what stopped it: "TAO's own test" or cbps's test, with numbers
  /// The natural-map residual ‖lambda − clamp(lambda − w, cmin, cmax)‖∞ of 6.2, N, formed on the
  /// distributed vectors (PETSc's MatMult, VecPointwiseMax/Min, VecNorm); the same on every rank.
  double residual = 0.;
  /// The unit-free residual of lambda (system/unit_free.hpp) from every rank's rows of the
  /// distributed vectors, the verdict's; the same on every rank.
  UnitFreeResidual unit_free;
  long local_rows = 0;  ///< rows of A owned by this rank
  /// solve_tao_local: scale_of's max(1, ‖b‖∞, max |A_ij|) on the distributed A and b.
  double scale = 0.;
  /// solve_tao_local with LocalSystem::check_symmetric: max |A − Aᵀ| on the distributed A; when
  /// it is above kSymmetryTolerance max(1, max |A_ij|) (require_symmetric's test), `asymmetric` is
  /// set and TAO is not run.
  double asymmetry = 0.;
  bool asymmetric = false;
  /// solve_tao_local with `gather`: the whole problem on rank 0 (empty elsewhere).
  GatheredSystem gathered;
};

/// Solves the boxed problem (A symmetric positive semidefinite) by TAO's `options.type` from
/// lambda = 0, A's symmetry checked by the caller (require_symmetric). Collective: every rank
/// calls it with the whole problem and keeps only its rows (rows_of, generate.hpp), then
/// solve_tao_local, the one path of every TAO solve (`cbps lcp` calls it directly, with each
/// rank holding only its rows). TAO stops after
/// options.max_iterations, or by its own test: its measure ≤ options.tolerance (gatol;
/// grtol = gttol = 0; for the gradient types a 2-norm of the gradient without the components
/// TAO takes as held at a bound, for bqpip its mean primal and dual infeasibility), or by
/// cbps's test after each iteration: the natural-map residual ≤ options.tolerance (the test of
/// every cbps solver; TAO_CONVERGED_USER). The caller judges the result by
/// TaoResult::residual. A PETSc error throws ComputationError on one rank and aborts the MPI
/// job on more.
TaoResult solve_tao(const MpiSession& session,
                    const BoxedProblem& problem,
                    const TaoOptions& options);

struct LocalSystem;  // cbps/distributed/generate.hpp

/// solve_tao for a problem each rank holds only its rows of (LocalSystem, generate.hpp:
/// generated or read by rows): each rank puts its rows of A (6.2.9) into PETSc's MPIAIJ and its
/// rows of b, cmin and cmax into the vectors: no rank holds more than its rows and PETSc's
/// communication buffers. With local.check_symmetric, A's symmetry is measured first
/// (TaoResult::asymmetric). Then the same TAO solve. With `gather`, A, b, cmin and cmax are
/// also gathered onto rank 0 (TaoResult::gathered; small sizes only). local.A is released
/// (emptied) once PETSc holds it. Collective.
TaoResult solve_tao_local(const MpiSession& session,
                          LocalSystem& local,
                          const TaoOptions& options,
                          bool gather);

}  // namespace cbps::distributed
