// The exact path (solvers/exact/direct.hpp) under MPI: `mpirun -n R cbps lcp FOLDER --solver
// direct` (docs/distributed.md, "The exact path under MPI"). Each rank holds its rows of J, b,
// cmin and cmax and its bodies' rows of Minv (LocalSystem, generate.hpp); A is never formed. The
// interior point and the crossover are the library's (solvers/exact/interior_point.hpp), run on
// each rank's rows with sums and extremes taken over all ranks; their Newton systems are solved
// in body space, (A + D)⁻¹ r = D⁻¹ (r − J u), u = (M + Jᵀ D⁻¹ J)⁻¹ Jᵀ D⁻¹ r (Woodbury), with
// H = M + Jᵀ D⁻¹ J assembled from every rank's rows into PETSc's distributed MATAIJ and factored
// by SuperLU_dist across the ranks (LU without row permutation: H is symmetric positive
// definite). Not MUMPS: Siconos' library in the same program brings MUMPS's sequential build,
// whose symbols take the place of the parallel one's (each rank would factor alone). Built only
// with PETSc (CBPS_HAVE_PETSC); src/distributed/exact.cpp includes PETSc, nothing here names its
// types.
//
//   Symbol   Shape   Unit          In PETSc
//   J        c×6n    (5.1)         MATAIJ, rows as the vectors of λ, columns by body
//   Minv     6n×6n   kg⁻¹, kg⁻¹m⁻² MATAIJ, rows and columns by body
//   H        6n×6n   kg, kg m²     MATAIJ, factored by SuperLU_dist (MATSOLVERSUPERLU_DIST)
//   b        c       m/s²          this rank's rows, Eigen (the interior point's vectors)
//   lambda   c       N             this rank's rows; gathered onto rank 0 at the end
#pragma once

#include <string>

#include "cbps/distributed/generate.hpp"
#include "cbps/distributed/tao.hpp"
#include "cbps/solvers/solver.hpp"
#include "cbps/system/unit_free.hpp"

namespace cbps::distributed {

/// What the exact path under MPI returned.
struct DirectResult {
  VecX lambda;  ///< c, N: on rank 0 the whole answer, on the other ranks empty
  /// the natural-map residual met options.tolerance read in N and as a unit-free residual
  /// (UnitFreeTarget::both, as on one process), or may_stop's floor
  bool solved = false;
  double residual = 0.;  ///< natural-map residual of 6.2 at lambda, N (the same on every rank)
  /// The unit-free residual of lambda (system/unit_free.hpp) from every rank's rows, the
  /// verdict's (the same on every rank).
  UnitFreeResidual unit_free;
  double scale = 0.;   ///< max(1, ‖b‖∞, max A_kk) (scale_of: max |A_ij| = max A_kk, A ⪰ 0)
  int iterations = 0;  ///< interior-point iterations
  int crossover = 0;   ///< the crossover's proximal steps (0: the interior point sufficed)
  int solves = 0;      ///< the crossover's solves with the Newton system
  long moved = 0;      ///< rows the crossover moved between free and bound
  int factorizations = 0;  ///< numeric factorizations of H (SuperLU_dist)
  long updates = 0;        ///< rows joining or leaving by low-rank corrections instead
  /// The interior point's and crossover's reductions over the ranks (MPI_Allreduce of one or
  /// two doubles: sums, maxima, minima); PETSc's own are in its log (-log_view).
  long reductions = 0;
  long local_rows = 0;    ///< rows of λ this rank holds
  long local_bodies = 0;  ///< bodies this rank holds (its rows of Minv and H)
  std::string message;    ///< one line for the report
  /// solve_direct_local with `gather`: J, Minv, b, cmin, cmax on rank 0 (A not formed).
  GatheredSystem gathered;
};

/// The exact path on `local` (read_folder_factors): the interior point from the box's centre,
/// then, unless it met the tolerance, the crossover that runs on rows spread over ranks
/// (bulk_crossover). options.tolerance, options.direct (max_interior, interior_mu, proximal,
/// max_outer_iterations, epsilon_floor) as on one process; local.cfm is added to D (the boxed
/// problem of A + eps E, as `cbps lcp` solves a folder with cfm.txt); local.M its bodies' mass
/// matrices (read_folder_factors checks and inverts Minv's blocks). Collective: every rank
/// calls it. With `gather`, the problem is also gathered onto rank 0 (DirectResult::gathered;
/// small sizes only, --write-system). A PETSc error aborts the job as every distributed path does
/// (ComputationError on one rank).
DirectResult solve_direct_local(const MpiSession& session,
                                LocalSystem& local,
                                const SolverOptions& options,
                                bool gather = false);

/// How far the folder's A is from its J Minv Jᵀ + cfm E over all ranks (factors_gap's measure,
/// system/boxed_problem.hpp; `local` read with factors_read: its rows of A, with cfm's eps, of
/// J and its bodies' rows of Minv): each rank forms its rows of J (Minv (Jᵀ x)) with two sums
/// over the ranks of a 6n vector, and the maxima are taken over the ranks. Collective; the same
/// result on every rank.
FactorsGap factors_gap_across_ranks(const LocalSystem& local);

}  // namespace cbps::distributed
