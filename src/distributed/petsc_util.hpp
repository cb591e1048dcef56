// What the PETSc files of src/distributed/ (tao.cpp, exact.cpp) share: PETSc errors as the CLI
// contract wants them, a rank's rows as a distributed matrix, a distributed vector gathered onto
// rank 0. Private to src/distributed/; the only header that includes PETSc.
#pragma once

#include <petscmat.h>

#include "cbps/base/types.hpp"

namespace cbps::distributed {

/// A PETSc error as the contract wants it: ComputationError (exit 1) in a job of one rank; in a
/// job of several the other ranks may be waiting in a collective call this rank will never
/// reach, so the whole job is aborted with exit code 1 instead of hanging.
void check(PetscErrorCode code, const char* call);

#define CBPS_PETSC_CHECK(call) ::cbps::distributed::check((call), #call)

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
