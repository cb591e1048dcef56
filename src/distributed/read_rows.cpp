// Each rank's rows of a stored problem (include/cbps/distributed/generate.hpp): the parallel
// read of `cbps lcp FOLDER --solver tao:TYPE` under mpirun. No PETSc or MPI here.
#include <filesystem>

#include "cbps/base/error.hpp"
#include "cbps/distributed/generate.hpp"
#include "cbps/io/matrix_market.hpp"
#include "cbps/io/stored_problem.hpp"

namespace cbps::distributed {

namespace {

/// cfm's eps added to row i's diagonal entry (column first_row + i), kg⁻¹: with_cfm's A + eps E
/// on this rank's rows.
void add_cfm(LocalSystem& local) {
  if (local.cfm == 0.0) return;
  for (long i = 0; i < local.rows(); ++i) local.A.coeffRef(i, local.first_row + i) += local.cfm;
  local.A.makeCompressed();
}

}  // namespace

LocalSystem read_folder_rows(const std::string& dir, int rank, int size) {
  namespace fs = std::filesystem;
  const auto file = [&](const char* name) { return (fs::path(dir) / name).string(); };
  // The sizes first, checked as read_problem checks them, so every rank splits the same c.
  const auto [c, columns] = read_matrix_market_size(file("A.mtx"));
  if (columns != c)
    throw InputError(file("A.mtx") + ": A is " + std::to_string(c) + " x " +
                     std::to_string(columns) + ", not square");
  for (const char* name : {"b.mtx", "cmin.mtx", "cmax.mtx"}) {
    const long n = read_matrix_market_size(file(name)).first;
    if (n != c)
      throw InputError(file(name) + ": has " + std::to_string(n) + " rows, A has " +
                       std::to_string(c));
  }
  long first = 0;
  long last = 0;
  split_ownership(c, rank, size, first, last);
  const RowRange mine{first, last};

  LocalSystem local;
  local.description = dir;
  local.total_rows = c;
  local.first_row = first;
  local.check_symmetric = true;
  local.A = SpMatRow(read_matrix_market_sparse_rows(file("A.mtx"), mine));
  local.b = read_matrix_market_vector_rows(file("b.mtx"), mine);
  local.cmin = read_matrix_market_vector_rows(file("cmin.mtx"), mine);
  local.cmax = read_matrix_market_vector_rows(file("cmax.mtx"), mine);
  check_bounds(
      local.b, local.cmin, local.cmax, file("cmin.mtx"), file("cmax.mtx"), file("b.mtx"), first);
  local.cfm = read_cfm(dir);
  add_cfm(local);
  return local;
}

LocalSystem rows_of(
    const BoxedProblem& problem, double cfm, const std::string& description, int rank, int size) {
  long first = 0;
  long last = 0;
  split_ownership(problem.rows(), rank, size, first, last);
  LocalSystem local;
  local.description = description;
  local.total_rows = problem.rows();
  local.first_row = first;
  local.check_symmetric = true;
  local.A = SpMatRow(problem.A).middleRows(first, last - first);
  local.b = problem.b.segment(first, last - first);
  local.cmin = problem.cmin.segment(first, last - first);
  local.cmax = problem.cmax.segment(first, last - first);
  local.cfm = cfm;
  add_cfm(local);
  return local;
}

}  // namespace cbps::distributed
