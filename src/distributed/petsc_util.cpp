// The shared PETSc helpers of src/distributed/ (petsc_util.hpp).
#include "petsc_util.hpp"

#include <cstdio>
#include <string>
#include <vector>

#include "cbps/base/error.hpp"

namespace cbps::distributed {

void check(PetscErrorCode code, const char* call) {
  if (code == 0) return;
  const char* text = nullptr;
  PetscErrorMessage(code, &text, nullptr);
  const std::string message = std::string("PETSc: ") + call + " failed: " +
                              (text != nullptr ? text : "error " + std::to_string(code));
  int initialized = 0;
  int size = 1;
  MPI_Initialized(&initialized);
  if (initialized) MPI_Comm_size(PETSC_COMM_WORLD, &size);
  if (size > 1) {
    std::fprintf(stderr, "cbps: %s (aborting all %d ranks)\n", message.c_str(), size);
    MPI_Abort(PETSC_COMM_WORLD, 1);
  }
  throw ComputationError(message);
}

Mat matrix_from_rows(const SpMatRow& local, long columns, long column_begin, long owned_columns) {
  Mat M = nullptr;
  CBPS_PETSC_CHECK(MatCreate(PETSC_COMM_WORLD, &M));
  CBPS_PETSC_CHECK(MatSetSizes(M,
                               static_cast<PetscInt>(local.rows()),
                               static_cast<PetscInt>(owned_columns),
                               PETSC_DETERMINE,
                               static_cast<PetscInt>(columns)));
  // MATAIJ: MATMPIAIJ on more than one rank, MATSEQAIJ on one, where PETSc's default
  // preconditioner (ILU, inside the Newton and interior-point types' KSP) exists only for the
  // sequential format; on more ranks the default is block Jacobi with ILU on each rank's block.
  CBPS_PETSC_CHECK(MatSetType(M, MATAIJ));
  std::vector<PetscInt> diagonal(static_cast<std::size_t>(local.rows()), 0);
  std::vector<PetscInt> off_diagonal(static_cast<std::size_t>(local.rows()), 0);
  for (Eigen::Index i = 0; i < local.outerSize(); ++i)
    for (SpMatRow::InnerIterator it(local, i); it; ++it) {
      const bool own_column = it.col() >= column_begin && it.col() < column_begin + owned_columns;
      ++(own_column ? diagonal : off_diagonal)[static_cast<std::size_t>(i)];
    }
  CBPS_PETSC_CHECK(MatMPIAIJSetPreallocation(M, 0, diagonal.data(), 0, off_diagonal.data()));
  CBPS_PETSC_CHECK(MatSeqAIJSetPreallocation(M, 0, diagonal.data()));
  PetscInt row_begin = 0;
  PetscInt row_end = 0;
  CBPS_PETSC_CHECK(MatGetOwnershipRange(M, &row_begin, &row_end));
  std::vector<PetscInt> cols;
  std::vector<PetscScalar> values;
  for (Eigen::Index i = 0; i < local.outerSize(); ++i) {
    cols.clear();
    values.clear();
    for (SpMatRow::InnerIterator it(local, i); it; ++it) {
      cols.push_back(static_cast<PetscInt>(it.col()));
      values.push_back(it.value());
    }
    const PetscInt row = row_begin + static_cast<PetscInt>(i);
    CBPS_PETSC_CHECK(MatSetValues(
        M, 1, &row, static_cast<PetscInt>(cols.size()), cols.data(), values.data(), INSERT_VALUES));
  }
  CBPS_PETSC_CHECK(MatAssemblyBegin(M, MAT_FINAL_ASSEMBLY));
  CBPS_PETSC_CHECK(MatAssemblyEnd(M, MAT_FINAL_ASSEMBLY));
  return M;
}

VecX gather_vector(Vec v) {
  Vec on_0 = nullptr;
  VecScatter to_0 = nullptr;
  CBPS_PETSC_CHECK(VecScatterCreateToZero(v, &to_0, &on_0));
  CBPS_PETSC_CHECK(VecScatterBegin(to_0, v, on_0, INSERT_VALUES, SCATTER_FORWARD));
  CBPS_PETSC_CHECK(VecScatterEnd(to_0, v, on_0, INSERT_VALUES, SCATTER_FORWARD));
  PetscInt size = 0;
  CBPS_PETSC_CHECK(VecGetLocalSize(on_0, &size));
  VecX x(size);
  const PetscScalar* all = nullptr;
  CBPS_PETSC_CHECK(VecGetArrayRead(on_0, &all));
  for (PetscInt i = 0; i < size; ++i)
    x[i] = all[i] >= PETSC_INFINITY ? kInf : all[i] <= PETSC_NINFINITY ? -kInf : all[i];
  CBPS_PETSC_CHECK(VecRestoreArrayRead(on_0, &all));
  VecScatterDestroy(&to_0);
  VecDestroy(&on_0);
  return x;
}

SpMat gather_matrix(Mat A) {
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  PetscInt begin = 0;
  PetscInt end = 0;
  PetscInt rows = 0;
  PetscInt columns = 0;
  CBPS_PETSC_CHECK(MatGetOwnershipRange(A, &begin, &end));
  CBPS_PETSC_CHECK(MatGetSize(A, &rows, &columns));
  std::vector<double> mine;  // (row, column, value) triples
  for (PetscInt i = begin; i < end; ++i) {
    PetscInt count = 0;
    const PetscInt* cols = nullptr;
    const PetscScalar* values = nullptr;
    CBPS_PETSC_CHECK(MatGetRow(A, i, &count, &cols, &values));
    for (PetscInt k = 0; k < count; ++k)
      mine.insert(mine.end(), {double(i), double(cols[k]), values[k]});
    CBPS_PETSC_CHECK(MatRestoreRow(A, i, &count, &cols, &values));
  }
  int size = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  const int count = static_cast<int>(mine.size());
  std::vector<int> counts(static_cast<std::size_t>(size), 0);
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, PETSC_COMM_WORLD);
  std::vector<int> displacements(static_cast<std::size_t>(size), 0);
  for (int r = 1; r < size; ++r) displacements[r] = displacements[r - 1] + counts[r - 1];
  std::vector<double> all(rank == 0 ? static_cast<std::size_t>(displacements.back() + counts.back())
                                    : 0);
  MPI_Gatherv(mine.data(),
              count,
              MPI_DOUBLE,
              all.data(),
              counts.data(),
              displacements.data(),
              MPI_DOUBLE,
              0,
              PETSC_COMM_WORLD);
  if (rank != 0) return SpMat();
  std::vector<Triplet> triplets;
  for (std::size_t k = 0; k + 2 < all.size(); k += 3)
    triplets.emplace_back(static_cast<int>(all[k]), static_cast<int>(all[k + 1]), all[k + 2]);
  SpMat whole(rows, columns);
  whole.setFromTriplets(triplets.begin(), triplets.end());
  return whole;
}

}  // namespace cbps::distributed
