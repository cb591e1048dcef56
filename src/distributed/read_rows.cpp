// Each rank's rows of a stored problem (include/cbps/distributed/generate.hpp): the parallel
// read of `cbps lcp FOLDER --solver tao:TYPE` under mpirun. No PETSc or MPI here.
#include <filesystem>
#include <string>
#include <vector>

#include "cbps/base/error.hpp"
#include "cbps/distributed/generate.hpp"
#include "cbps/io/matrix_market.hpp"
#include "cbps/io/stored_problem.hpp"
#include "cbps/solvers/exact/interior_point.hpp"

namespace cbps::distributed {

namespace {

/// cfm's eps added to row i's diagonal entry (column first_row + i), kg⁻¹: with_cfm's A + eps E
/// on this rank's rows.
void add_cfm(LocalSystem& local) {
  if (local.cfm == 0.0) return;
  for (long i = 0; i < local.rows(); ++i) local.A.coeffRef(i, local.first_row + i) += local.cfm;
  local.A.makeCompressed();
}

/// b, cmin and cmax have the c rows of `matrix` (A or J), as read_problem checks.
void check_vector_sizes(const std::string& dir, long c, const char* matrix) {
  for (const char* name : {"b.mtx", "cmin.mtx", "cmax.mtx"}) {
    const std::string path = (std::filesystem::path(dir) / name).string();
    const long n = read_matrix_market_size(path).first;
    if (n != c)
      throw InputError(path + ": has " + std::to_string(n) + " rows, " + matrix + " has " +
                       std::to_string(c));
  }
}

/// This rank's rows `mine` of b, cmin and cmax (their bounds checked) and cfm.txt's eps.
void read_vectors(LocalSystem& local, const std::string& dir, RowRange mine) {
  const auto file = [&](const char* name) { return (std::filesystem::path(dir) / name).string(); };
  local.b = read_matrix_market_vector_rows(file("b.mtx"), mine);
  local.cmin = read_matrix_market_vector_rows(file("cmin.mtx"), mine);
  local.cmax = read_matrix_market_vector_rows(file("cmax.mtx"), mine);
  check_bounds(local.b,
               local.cmin,
               local.cmax,
               file("cmin.mtx"),
               file("cmax.mtx"),
               file("b.mtx"),
               mine.first);
  local.cfm = read_cfm(dir);
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
  check_vector_sizes(dir, c, "A");
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
  read_vectors(local, dir, mine);
  add_cfm(local);
  return local;
}

LocalSystem read_folder_factors(const std::string& dir, int rank, int size) {
  namespace fs = std::filesystem;
  const auto file = [&](const char* name) { return (fs::path(dir) / name).string(); };
  for (const char* name : {"J.mtx", "Minv.mtx"}) {
    std::error_code ec;
    if (!fs::is_regular_file(file(name), ec))
      throw InputError(file(name) +
                       ": missing; the exact path under MPI works in body space and "
                       "needs the folder's J and Minv (cbps matrices writes them)");
  }
  const auto [c, columns] = read_matrix_market_size(file("J.mtx"));
  if (columns % 6 != 0)
    throw InputError(file("J.mtx") + ": " + std::to_string(columns) +
                     " columns, not 6 per body (6.1)");
  const auto [minv_rows, minv_columns] = read_matrix_market_size(file("Minv.mtx"));
  if (minv_rows != columns || minv_columns != columns)
    throw InputError(file("Minv.mtx") + ": " + std::to_string(minv_rows) + " x " +
                     std::to_string(minv_columns) + ", J has " + std::to_string(columns) +
                     " columns");
  check_vector_sizes(dir, c, "J");
  long first = 0;
  long last = 0;
  split_ownership(c, rank, size, first, last);
  const RowRange mine{first, last};
  long first_body = 0;
  long last_body = 0;
  split_ownership(columns / 6, rank, size, first_body, last_body);

  LocalSystem local;
  local.description = dir;
  local.total_rows = c;
  local.total_columns = columns;
  local.first_row = first;
  local.J = SpMatRow(read_matrix_market_sparse_rows(file("J.mtx"), mine));
  local.first_body = first_body;
  local.bodies = last_body - first_body;
  local.Minv = SpMatRow(
      read_matrix_market_sparse_rows(file("Minv.mtx"), RowRange{6 * first_body, 6 * last_body}));
  local.M = body_masses(local, file("Minv.mtx"));
  read_vectors(local, dir, mine);
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
