// What the PETSc files of src/distributed/ (tao.cpp, exact.cpp) share: PETSc errors as the CLI
// contract wants them, reductions over the ranks, a rank's rows as a distributed matrix, a
// distributed vector gathered onto rank 0. Private to src/distributed/; the only header that
// includes PETSc.
#pragma once

#include <petscmat.h>

#include <cmath>
#include <limits>

#include "cbps/base/types.hpp"
#include "cbps/solvers/exact/interior_point.hpp"

namespace cbps::distributed {

/// A PETSc error as the contract wants it: ComputationError (exit 1) in a job of one rank; in a
/// job of several the other ranks may be waiting in a collective call this rank will never
/// reach, so the whole job is aborted with exit code 1 instead of hanging.
void check(PetscErrorCode code, const char* call);

#define CBPS_PETSC_CHECK(call) ::cbps::distributed::check((call), #call)

/// Sums, maxima and minima over the ranks (MPI_Allreduce); a NaN on any rank makes the maximum
/// and the minimum NaN.
class MpiReduction final : public RowReduction {
 public:
  double sum(double x) const override {
    double y = 0.0;
    ++calls_;
    MPI_Allreduce(&x, &y, 1, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD);
    return y;
  }
  double max(double x) const override { return extreme(x, MPI_MAX); }
  double min(double x) const override { return extreme(x, MPI_MIN); }
  /// MPI_Allreduce calls so far (each of one or two doubles): not PETSc's, so not in its log.
  long calls() const { return calls_; }

 private:
  mutable long calls_ = 0;

  double extreme(double x, MPI_Op op) const {
    ++calls_;
    const bool nan = std::isnan(x);
    const double in[2] = {nan ? 1.0 : 0.0, nan ? 0.0 : (op == MPI_MAX ? x : -x)};
    double out[2] = {0.0, 0.0};
    MPI_Allreduce(in, out, 2, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD);
    if (out[0] > 0.0) return std::numeric_limits<double>::quiet_NaN();
    return op == MPI_MAX ? out[1] : -out[1];
  }
};

/// This rank's rows `local` (global columns) as its rows of a MATAIJ of `columns` global
/// columns, of which this rank owns [column_begin, column_begin + owned_columns): the rows of
/// the whole matrix are the ranks' `local` in rank order. Collective.
Mat matrix_from_rows(const SpMatRow& local, long columns, long column_begin, long owned_columns);

/// The whole of v on rank 0 (empty elsewhere); PETSc's ±PETSC_INFINITY back to ±kInf.
/// Collective.
VecX gather_vector(Vec v);

/// The whole of A on rank 0 (0×0 elsewhere): each rank's rows as triplets, gathered. Small
/// matrices only (--write-system). Collective.
SpMat gather_matrix(Mat A);

}  // namespace cbps::distributed
