// The boxed problem of 6.2 as a bound-constrained quadratic program on PETSc/TAO under MPI
// (include/cbps/distributed/tao.hpp).
//
// References for the methods (docs/distributed.md has the list): the TAO users manual (PETSc
// 3.18, "TAO: Optimization Solvers", the bound-constrained and quadratic solvers) and the papers
// each method follows there.
#include "cbps/distributed/tao.hpp"

#include <petsctao.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <string>
#include <vector>

#include "cbps/base/error.hpp"
#include "cbps/distributed/generate.hpp"
#include "cbps/io/stored_problem.hpp"
#include "cbps/system/unit_free.hpp"
#include "petsc_util.hpp"

namespace cbps::distributed {

namespace {

/// PETSc objects freed when the solve leaves, in any way.
struct Objects {
  Mat A = nullptr;
  Vec b = nullptr, cmin = nullptr, cmax = nullptr, lambda = nullptr, w = nullptr, t = nullptr;
  Vec diagonal = nullptr;         ///< A_kk, this rank's rows (the unit-free residual's steps)
  double largest_diagonal = 0.0;  ///< max_k A_kk over every rank
  double row_sum = 0.0;           ///< max_i Σ_k |A_ik| over every rank (the rounding floor's)
  double b_norm = 0.0;            ///< ‖b‖∞
  Vec lambda_on_0 = nullptr;
  VecScatter to_0 = nullptr;
  Tao tao = nullptr;
  ~Objects() {
    TaoDestroy(&tao);
    VecScatterDestroy(&to_0);
    for (Vec* v : {&b, &cmin, &cmax, &lambda, &w, &t, &diagonal, &lambda_on_0}) VecDestroy(v);
    MatDestroy(&A);
  }
};

/// What TAO's callbacks need: the problem's distributed objects and cbps's stopping test.
struct Quadratic {
  Objects* o = nullptr;
  double tolerance = 0.0;  ///< stop at this natural-map residual, N (aimed_tolerance)
  std::string stop;        ///< why cbps's test stopped TAO (empty: TAO's own test did)
};

/// f(lambda) = ½ lambdaᵀ A lambda − bᵀ lambda and its gradient w = A lambda − b (6.2), the
/// residual velocity's rate of the boxed problem, m/s².
PetscErrorCode objective_and_gradient(Tao, Vec lambda, PetscReal* f, Vec w, void* context) {
  const Objects* o = static_cast<const Quadratic*>(context)->o;
  PetscScalar lambda_A_lambda = 0.0;
  PetscScalar b_lambda = 0.0;
  PetscFunctionBeginUser;
  PetscCall(MatMult(o->A, lambda, w));  // w = A lambda
  PetscCall(VecDot(lambda, w, &lambda_A_lambda));
  PetscCall(VecDot(o->b, lambda, &b_lambda));
  *f = 0.5 * lambda_A_lambda - b_lambda;
  PetscCall(VecAXPY(w, -1.0, o->b));  // w = A lambda − b
  PetscFunctionReturn(0);
}

/// The Hessian of f is A itself, assembled once: nothing to recompute.
PetscErrorCode hessian(Tao, Vec, Mat, Mat, void*) {
  PetscFunctionBeginUser;
  PetscFunctionReturn(0);
}

/// A bound for TAO: ±∞ as PETSc's ±PETSC_INFINITY, which its bound-constrained methods read as
/// "no bound".
PetscScalar bound_for_tao(double x) {
  if (x == kInf) return PETSC_INFINITY;
  if (x == -kInf) return PETSC_NINFINITY;
  return x;
}

/// The natural-map residual of 6.2 on the distributed vectors, N:
///   ‖lambda − clamp(lambda − w, cmin, cmax)‖∞,  w = A lambda − b,
/// the formula of natural_map_residual (system/boxed_problem.hpp) written with PETSc's vector
/// operations (clamp = VecPointwiseMax with cmin, then VecPointwiseMin with cmax). NaN when any
/// term is (the 2-norm carries a NaN that the maximum may skip). The same value on every rank.
PetscErrorCode distributed_natural_map_residual(const Objects& o, Vec lambda, double* residual) {
  PetscReal largest = 0.0;
  PetscReal two_norm = 0.0;
  PetscFunctionBeginUser;
  PetscCall(MatMult(o.A, lambda, o.w));
  PetscCall(VecAXPY(o.w, -1.0, o.b));            // w = A lambda − b
  PetscCall(VecWAXPY(o.t, -1.0, o.w, lambda));   // t = lambda − w
  PetscCall(VecPointwiseMax(o.t, o.t, o.cmin));  // max(t, cmin)
  PetscCall(VecPointwiseMin(o.t, o.t, o.cmax));  // min(·, cmax)
  PetscCall(VecAYPX(o.t, -1.0, lambda));         // lambda − clamp(lambda − w, cmin, cmax)
  PetscCall(VecNorm(o.t, NORM_INFINITY, &largest));
  PetscCall(VecNorm(o.t, NORM_2, &two_norm));
  *residual = std::isnan(two_norm) ? std::numeric_limits<double>::quiet_NaN() : largest;
  PetscFunctionReturn(0);
}

/// The unit-free residual of lambda (system/unit_free.hpp) from this rank's rows of the
/// distributed vectors, with w = A lambda − b as distributed_natural_map_residual leaves it in
/// o.w; the same on every rank (its maxima over the ranks).
UnitFreeResidual distributed_unit_free(const Objects& o, Vec lambda) {
  PetscInt n = 0;
  CBPS_PETSC_CHECK(VecGetLocalSize(o.w, &n));
  const Vec vectors[] = {o.w, lambda, o.b, o.cmin, o.cmax, o.diagonal};
  const PetscScalar* at[6] = {};
  for (int i = 0; i < 6; ++i) CBPS_PETSC_CHECK(VecGetArrayRead(vectors[i], &at[i]));
  using Rows = Eigen::Map<const VecX>;
  const UnitFreeResidual mine = unit_free_rows(Rows(at[0], n),
                                               Rows(at[1], n),
                                               Rows(at[2], n),
                                               Rows(at[3], n),
                                               Rows(at[4], n),
                                               Rows(at[5], n),
                                               o.largest_diagonal);
  for (int i = 0; i < 6; ++i) CBPS_PETSC_CHECK(VecRestoreArrayRead(vectors[i], &at[i]));
  const MpiReduction all;
  return unit_free_of(all.max(mine.residual), all.max(mine.scale));
}

/// A's diagonal into o.diagonal and its largest entry, A's largest row sum of |A_ik| and ‖b‖∞,
/// then the tolerance `tolerance` read in N and as a unit-free residual, as the direct path reads
/// it (UnitFreeTarget::both at λ = 0, system/unit_free.hpp): the natural-map residual (N) to stop
/// at, the same on every rank.
double aimed_tolerance(Objects& o, double tolerance) {
  PetscInt first = 0, last = 0;
  CBPS_PETSC_CHECK(MatGetOwnershipRange(o.A, &first, &last));
  double row_sum = 0.0;
  for (PetscInt i = first; i < last; ++i) {
    PetscInt count = 0;
    const PetscScalar* values = nullptr;
    CBPS_PETSC_CHECK(MatGetRow(o.A, i, &count, nullptr, &values));
    double sum = 0.0;
    for (PetscInt k = 0; k < count; ++k) sum += std::abs(values[k]);
    row_sum = std::max(row_sum, sum);
    CBPS_PETSC_CHECK(MatRestoreRow(o.A, i, &count, nullptr, &values));
  }
  PetscReal b_norm = 0.0;
  CBPS_PETSC_CHECK(VecNorm(o.b, NORM_INFINITY, &b_norm));
  o.b_norm = static_cast<double>(b_norm);
  CBPS_PETSC_CHECK(VecDuplicate(o.b, &o.diagonal));
  CBPS_PETSC_CHECK(MatGetDiagonal(o.A, o.diagonal));
  PetscReal largest = 0.0;
  CBPS_PETSC_CHECK(VecMax(o.diagonal, nullptr, &largest));
  o.largest_diagonal = static_cast<double>(largest);
  PetscInt n = 0;
  CBPS_PETSC_CHECK(VecGetLocalSize(o.b, &n));
  const PetscScalar* b = nullptr;
  const PetscScalar* diagonal = nullptr;
  CBPS_PETSC_CHECK(VecGetArrayRead(o.b, &b));
  CBPS_PETSC_CHECK(VecGetArrayRead(o.diagonal, &diagonal));
  UnitFreeTarget target = unit_free_target_rows(
      Eigen::Map<const VecX>(b, n), Eigen::Map<const VecX>(diagonal, n), o.largest_diagonal);
  CBPS_PETSC_CHECK(VecRestoreArrayRead(o.b, &b));
  CBPS_PETSC_CHECK(VecRestoreArrayRead(o.diagonal, &diagonal));
  const MpiReduction all;
  o.row_sum = all.max(row_sum);
  target.rho_b = all.max(target.rho_b);
  target.rho_max = all.max(target.rho_max);
  return target.both(tolerance, VecX());
}

/// TAO's convergence test, then cbps's, after every iteration: TAO's own (gatol, the iteration
/// cap, NaN), else stop when the natural-map residual is ≤ the tolerance, the test every cbps
/// solver stops by, or, with a tolerance, ≤ its rounding floor (direct.hpp's residual_floor: 64 u
/// (max_i Σ_k |A_ik| ‖λ‖∞ + ‖b‖∞), below which no iteration can bring it; the 1,000,000-link
/// chain at 2 ranks ran on for 10 minutes under 8e-20 N) (TAO_CONVERGED_USER).
PetscErrorCode convergence_test(Tao tao, void* context) {
  auto* q = static_cast<Quadratic*>(context);
  TaoConvergedReason reason = TAO_CONTINUE_ITERATING;
  Vec lambda = nullptr;
  double residual = 0.0;
  PetscFunctionBeginUser;
  PetscCall(TaoDefaultConvergenceTest(tao, nullptr));
  PetscCall(TaoGetConvergedReason(tao, &reason));
  if (reason != TAO_CONTINUE_ITERATING) PetscFunctionReturn(0);
  PetscCall(TaoGetSolution(tao, &lambda));
  PetscCall(distributed_natural_map_residual(*q->o, lambda, &residual));
  PetscReal lambda_norm = 0.0;
  PetscCall(VecNorm(lambda, NORM_INFINITY, &lambda_norm));
  const double floor = residual_floor_of(q->o->row_sum, q->o->b_norm, lambda_norm);
  if (residual <= q->tolerance) {
    q->stop = "natural-map residual " + number_text(residual) + " <= " + number_text(q->tolerance) +
              " N (--tolerance read in N and as a unit-free residual)";
    PetscCall(TaoSetConvergedReason(tao, TAO_CONVERGED_USER));
  } else if (q->tolerance > 0.0 && residual <= floor) {
    q->stop = "natural-map residual " + number_text(residual) + " <= its rounding floor " +
              number_text(floor) + " N (the tolerance read in N and as a unit-free residual, " +
              number_text(q->tolerance) + " N, is below it)";
    PetscCall(TaoSetConvergedReason(tao, TAO_CONVERGED_USER));
  }
  PetscFunctionReturn(0);
}

/// What the monitor needs: the objects, the caller's callback and its clock.
struct Monitoring {
  Objects* o = nullptr;
  Quadratic* q = nullptr;
  const TaoOptions* options = nullptr;
  std::chrono::steady_clock::time_point started;  ///< when solve_tao was called
  double monitoring_s = 0.0;                      ///< seconds spent in monitor() so far
  VecX lambda;                                    ///< this rank's rows, handed to the callback
  std::exception_ptr failure;  ///< what the callback threw (not let through PETSc's C frames)
};

/// TaoSetMonitor's callback, after every iteration (and at the start): the natural-map residual
/// of the iterate and the time so far less the monitor's own, handed with this rank's lambda to
/// TaoOptions::monitor, whose false (or exception, rethrown by solve_tao) stops TAO
/// (TAO_DIVERGED_USER).
PetscErrorCode monitor(Tao tao, void* context) {
  auto* m = static_cast<Monitoring*>(context);
  const auto entered = std::chrono::steady_clock::now();
  TaoIterate at;
  at.time_s = std::chrono::duration<double>(entered - m->started).count() - m->monitoring_s;
  PetscInt iteration = 0;
  Vec lambda = nullptr;
  PetscFunctionBeginUser;
  PetscCall(TaoGetIterationNumber(tao, &iteration));
  at.iteration = static_cast<int>(iteration);
  PetscCall(TaoGetSolution(tao, &lambda));
  PetscCall(distributed_natural_map_residual(*m->o, lambda, &at.residual));
  PetscInt local = 0;
  const PetscScalar* own = nullptr;
  PetscCall(VecGetLocalSize(lambda, &local));
  PetscCall(VecGetArrayRead(lambda, &own));
  m->lambda = Eigen::Map<const VecX>(own, local);
  PetscCall(VecRestoreArrayRead(lambda, &own));
  bool go_on = false;
  try {
    go_on = m->options->monitor(at, m->lambda);
  } catch (...) {
    m->failure = std::current_exception();
  }
  if (!go_on) {
    m->q->stop = "the caller's monitor at iteration " + std::to_string(at.iteration);
    PetscCall(TaoSetConvergedReason(tao, TAO_DIVERGED_USER));
  }
  m->monitoring_s +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - entered).count();
  PetscFunctionReturn(0);
}

}  // namespace

MpiSession::MpiSession() {
  // PETSc's own command line (cbps's is CLI11's): no .petscrc file changes a result behind the
  // command line's back, and cbps keeps its own Ctrl-C handling (PETSc's handlers would take
  // the signals cbps's cleanup thread waits for). PETSC_OPTIONS is still read.
  static char program[] = "cbps";
  static char skip_petscrc[] = "-skip_petscrc";
  static char no_signal_handler[] = "-no_signal_handler";
  static char* arguments[] = {program, skip_petscrc, no_signal_handler, nullptr};
  int count = 3;
  char** argv = arguments;
  CBPS_PETSC_CHECK(PetscInitialize(&count, &argv, nullptr, nullptr));
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank_);
  MPI_Comm_size(PETSC_COMM_WORLD, &size_);
}

MpiSession::~MpiSession() { PetscFinalize(); }

int MpiSession::first_failing_rank(bool failed) const {
  const int mine = failed ? rank_ : size_;
  int first = size_;
  MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, PETSC_COMM_WORLD);
  return first;
}

int MpiSession::broadcast(int value, int root) const {
  MPI_Bcast(&value, 1, MPI_INT, root, PETSC_COMM_WORLD);
  return value;
}

namespace {

/// TAO on the distributed problem in `o` (A, b, cmin, cmax set), from lambda = 0; lambda
/// gathered onto rank 0 (c entries there). `started`: when the caller began (distributing A
/// included), the zero of TaoIterate::time_s.
TaoResult solve_objects(const MpiSession& session,
                        Objects& o,
                        const TaoOptions& options,
                        std::chrono::steady_clock::time_point started) {
  for (Vec* v : {&o.w, &o.t}) CBPS_PETSC_CHECK(VecDuplicate(o.b, v));
  CBPS_PETSC_CHECK(MatCreateVecs(o.A, &o.lambda, nullptr));  // A's row layout
  PetscInt begin = 0;
  PetscInt end = 0;
  PetscInt rows = 0;
  CBPS_PETSC_CHECK(VecGetOwnershipRange(o.b, &begin, &end));
  CBPS_PETSC_CHECK(VecGetSize(o.b, &rows));
  CBPS_PETSC_CHECK(VecSet(o.lambda, 0.0));  // the start every cbps solver takes

  Quadratic q;
  q.o = &o;
  q.tolerance = aimed_tolerance(o, options.tolerance);
  CBPS_PETSC_CHECK(TaoCreate(PETSC_COMM_WORLD, &o.tao));
  CBPS_PETSC_CHECK(TaoSetType(o.tao, options.type.c_str()));
  CBPS_PETSC_CHECK(TaoSetSolution(o.tao, o.lambda));
  CBPS_PETSC_CHECK(TaoSetVariableBounds(o.tao, o.cmin, o.cmax));
  CBPS_PETSC_CHECK(TaoSetObjectiveAndGradient(o.tao, nullptr, objective_and_gradient, &q));
  CBPS_PETSC_CHECK(TaoSetHessian(o.tao, o.A, o.A, hessian, &q));
  // Absolute tolerance only: TAO's relative tests would stop a problem whose f is large (or
  // whose first gradient is) long before the natural-map residual is small.
  CBPS_PETSC_CHECK(TaoSetTolerances(o.tao, q.tolerance, 0.0, 0.0));
  CBPS_PETSC_CHECK(TaoSetConvergenceTest(o.tao, convergence_test, &q));
  CBPS_PETSC_CHECK(TaoSetMaximumIterations(o.tao, options.max_iterations));
  // --iterations is the cap; function evaluations (a line search takes several per iteration)
  // get room enough that TAO's own default cap (4000 for bncg) never stops it first.
  const long funcs = std::min<long>(INT_MAX, 100L * options.max_iterations);
  CBPS_PETSC_CHECK(TaoSetMaximumFunctionEvaluations(o.tao, static_cast<PetscInt>(funcs)));
  Monitoring m;
  m.o = &o;
  m.q = &q;
  m.options = &options;
  m.started = started;
  if (options.monitor) CBPS_PETSC_CHECK(TaoSetMonitor(o.tao, monitor, &m, nullptr));
  CBPS_PETSC_CHECK(TaoSetFromOptions(o.tao));  // PETSC_OPTIONS, e.g. -tao_monitor
  CBPS_PETSC_CHECK(TaoSolve(o.tao));
  if (m.failure) std::rethrow_exception(m.failure);

  TaoResult r;
  PetscInt iterations = 0;
  PetscReal f = 0.0, gnorm = 0.0, cnorm = 0.0, xdiff = 0.0;
  TaoConvergedReason reason = TAO_CONTINUE_ITERATING;
  CBPS_PETSC_CHECK(TaoGetSolutionStatus(o.tao, &iterations, &f, &gnorm, &cnorm, &xdiff, &reason));
  r.iterations = static_cast<int>(iterations);
  r.reason = TaoConvergedReasons[reason];
  r.converged = reason > 0;
  r.tao_residual = gnorm;
  r.local_rows = static_cast<long>(end - begin);
  r.stop = q.stop.empty() ? std::string("TAO's own test") : q.stop;
  CBPS_PETSC_CHECK(distributed_natural_map_residual(o, o.lambda, &r.residual));
  r.unit_free = distributed_unit_free(o, o.lambda);

  // lambda onto rank 0.
  CBPS_PETSC_CHECK(VecScatterCreateToZero(o.lambda, &o.to_0, &o.lambda_on_0));
  CBPS_PETSC_CHECK(
      VecScatterBegin(o.to_0, o.lambda, o.lambda_on_0, INSERT_VALUES, SCATTER_FORWARD));
  CBPS_PETSC_CHECK(VecScatterEnd(o.to_0, o.lambda, o.lambda_on_0, INSERT_VALUES, SCATTER_FORWARD));
  if (session.rank() == 0) {
    const PetscScalar* all = nullptr;
    CBPS_PETSC_CHECK(VecGetArrayRead(o.lambda_on_0, &all));
    r.lambda = Eigen::Map<const VecX>(all, rows);
    CBPS_PETSC_CHECK(VecRestoreArrayRead(o.lambda_on_0, &all));
  }
  return r;
}

}  // namespace

std::vector<double> MpiSession::gather(double value) const {
  std::vector<double> all(rank_ == 0 ? static_cast<std::size_t>(size_) : 0);
  MPI_Gather(&value, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, 0, PETSC_COMM_WORLD);
  return all;
}

long MpiSession::sum_before(long value, long& total) const {
  long before = 0;
  MPI_Exscan(&value, &before, 1, MPI_LONG, MPI_SUM, PETSC_COMM_WORLD);
  if (rank_ == 0) before = 0;  // MPI_Exscan leaves rank 0's result undefined
  MPI_Allreduce(&value, &total, 1, MPI_LONG, MPI_SUM, PETSC_COMM_WORLD);
  return before;
}

TaoResult solve_tao(const MpiSession& session,
                    const BoxedProblem& problem,
                    const TaoOptions& options) {
  // This rank's rows of the whole problem, then the one path every TAO solve takes. The caller
  // has checked A's symmetry (require_symmetric) on the whole matrix.
  LocalSystem local = rows_of(problem, 0.0, "", session.rank(), session.size());
  local.check_symmetric = false;
  return solve_tao_local(session, local, options, false);
}

namespace {

/// max over this rank's entries of |A_ij|, then over the ranks.
double largest_entry(Mat A) {
  PetscInt begin = 0;
  PetscInt end = 0;
  CBPS_PETSC_CHECK(MatGetOwnershipRange(A, &begin, &end));
  double mine = 0.0;
  for (PetscInt i = begin; i < end; ++i) {
    PetscInt count = 0;
    const PetscScalar* values = nullptr;
    CBPS_PETSC_CHECK(MatGetRow(A, i, &count, nullptr, &values));
    for (PetscInt k = 0; k < count; ++k) mine = std::max(mine, std::abs(values[k]));
    CBPS_PETSC_CHECK(MatRestoreRow(A, i, &count, nullptr, &values));
  }
  double all = 0.0;
  MPI_Allreduce(&mine, &all, 1, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD);
  return all;
}

}  // namespace

TaoResult solve_tao_local(const MpiSession& session,
                          LocalSystem& local,
                          const TaoOptions& options,
                          bool gather) {
  const auto started = std::chrono::steady_clock::now();  // TaoIterate::time_s counts from here
  if (local.total_rows > INT_MAX)
    throw InputError("--solver tao: " + std::to_string(local.total_rows) +
                     " rows; this PETSc indexes at most " + std::to_string(INT_MAX));
  Objects o;
  // This rank's rows of A = J Minv Jᵀ (6.2.9), generated, read or cut, as its rows of a MATAIJ
  // (MPIAIJ on more than one rank) laid out as the vectors (docs/distributed.md says why not a
  // shell).
  o.A = matrix_from_rows(local.A, local.total_rows, local.first_row, local.rows());
  local.A = SpMatRow();  // PETSc holds it now
  CBPS_PETSC_CHECK(MatCreateVecs(o.A, nullptr, &o.b));
  for (Vec* v : {&o.cmin, &o.cmax}) CBPS_PETSC_CHECK(VecDuplicate(o.b, v));
  PetscInt begin = 0;
  PetscInt end = 0;
  CBPS_PETSC_CHECK(VecGetOwnershipRange(o.b, &begin, &end));
  if (begin != local.first_row || end - begin != local.rows())
    throw ComputationError("PETSc: A's rows [" + std::to_string(begin) + ", " +
                           std::to_string(end) + ") on this rank where its rows are [" +
                           std::to_string(local.first_row) + ", " +
                           std::to_string(local.first_row + local.rows()) + ")");
  // This rank's entries of the vectors, from its rows (local row 0 is global first_row).
  const auto fill = [&](Vec v, const VecX& x, bool as_bound) {
    PetscScalar* values = nullptr;
    CBPS_PETSC_CHECK(VecGetArray(v, &values));
    for (Eigen::Index i = 0; i < x.size(); ++i) values[i] = as_bound ? bound_for_tao(x[i]) : x[i];
    CBPS_PETSC_CHECK(VecRestoreArray(v, &values));
  };
  fill(o.b, local.b, false);
  fill(o.cmin, local.cmin, true);
  fill(o.cmax, local.cmax, true);

  // scale_of (system/boxed_problem.hpp) on the distributed A and b: max(1, ‖b‖∞, max |A_ij|).
  PetscReal b_largest = 0.0;
  CBPS_PETSC_CHECK(VecNorm(o.b, NORM_INFINITY, &b_largest));
  const double A_largest = largest_entry(o.A);
  const double scale = std::max({1.0, static_cast<double>(b_largest), A_largest});
  if (local.check_symmetric) {
    // require_symmetric's test (io/stored_problem.hpp) on the distributed A: TAO minimises
    // ½ λᵀ A λ − bᵀ λ, whose gradient is A λ − b only for a symmetric A.
    Mat difference = nullptr;
    CBPS_PETSC_CHECK(MatTranspose(o.A, MAT_INITIAL_MATRIX, &difference));
    CBPS_PETSC_CHECK(MatAXPY(difference, -1.0, o.A, DIFFERENT_NONZERO_PATTERN));
    const double asymmetry = largest_entry(difference);
    MatDestroy(&difference);
    if (asymmetry > kSymmetryTolerance * std::max(1.0, A_largest)) {
      TaoResult refused;
      refused.asymmetry = asymmetry;
      refused.asymmetric = true;
      refused.scale = scale;
      return refused;
    }
  }
  GatheredSystem gathered;
  if (gather) {
    gathered.A = gather_matrix(o.A);
    gathered.b = gather_vector(o.b);
    gathered.cmin = gather_vector(o.cmin);
    gathered.cmax = gather_vector(o.cmax);
  }
  TaoResult r = solve_objects(session, o, options, started);
  r.scale = scale;
  r.gathered = std::move(gathered);
  return r;
}

}  // namespace cbps::distributed
