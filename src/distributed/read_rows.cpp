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

/// This rank's rows `mine` of J.mtx (c × 6n) and its bodies' rows of Minv.mtx (the bodies
/// split_ownership gives rank `rank` of `size`) with their mass matrices; the sizes checked
/// against A's or b's c rows. False, nothing read, when the folder has neither file (a folder of
/// A alone); InputError when it has one without the other or they do not fit.
bool read_factors(LocalSystem& local, const std::string& dir, RowRange mine, int rank, int size) {
  namespace fs = std::filesystem;
  const auto file = [&](const char* name) { return (fs::path(dir) / name).string(); };
  const auto present = [&](const char* name) {
    std::error_code ec;
    return fs::is_regular_file(file(name), ec);
  };
  if (!present("J.mtx") && !present("Minv.mtx")) return false;
  for (const char* name : {"J.mtx", "Minv.mtx"})
    if (!present(name))
      throw InputError(file(name) + ": missing beside " +
                       file(name[0] == 'J' ? "Minv.mtx" : "J.mtx") +
                       "; the folder's J and Minv come together (cbps matrices writes both)");
  const auto [c, columns] = read_matrix_market_size(file("J.mtx"));
  if (c != local.total_rows)
    throw InputError(file("J.mtx") + ": has " + std::to_string(c) + " rows, b has " +
                     std::to_string(local.total_rows));
  if (columns % 6 != 0)
    throw InputError(file("J.mtx") + ": " + std::to_string(columns) +
                     " columns, not 6 per body (6.1)");
  const auto [minv_rows, minv_columns] = read_matrix_market_size(file("Minv.mtx"));
  if (minv_rows != columns || minv_columns != columns)
    throw InputError(file("Minv.mtx") + ": " + std::to_string(minv_rows) + " x " +
                     std::to_string(minv_columns) + ", J has " + std::to_string(columns) +
                     " columns");
  long first_body = 0;
  long last_body = 0;
  split_ownership(columns / 6, rank, size, first_body, last_body);
  local.total_columns = columns;
  local.J = SpMatRow(read_matrix_market_sparse_rows(file("J.mtx"), mine));
  local.first_body = first_body;
  local.bodies = last_body - first_body;
  local.Minv = SpMatRow(
      read_matrix_market_sparse_rows(file("Minv.mtx"), RowRange{6 * first_body, 6 * last_body}));
  local.M = body_masses(local, file("Minv.mtx"));
  return true;
}

/// This rank's rows `mine` of A.mtx, which must be c × c.
void read_A_rows(LocalSystem& local, const std::string& dir, RowRange mine) {
  const std::string path = (std::filesystem::path(dir) / "A.mtx").string();
  const auto [rows, columns] = read_matrix_market_size(path);
  if (rows != local.total_rows || columns != local.total_rows)
    throw InputError(path + ": A is " + std::to_string(rows) + " x " + std::to_string(columns) +
                     ", b has " + std::to_string(local.total_rows) + " rows");
  local.A = SpMatRow(read_matrix_market_sparse_rows(path, mine));
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
  // J and Minv when the folder has them: not solved with, but A must be their J Minv Jᵀ.
  local.factors_read = read_factors(local, dir, mine, rank, size);
  return local;
}

LocalSystem read_folder_factors(const std::string& dir, int rank, int size) {
  namespace fs = std::filesystem;
  const auto file = [&](const char* name) { return (fs::path(dir) / name).string(); };
  // The sizes first, from b (every folder's vectors have the c rows), so every rank splits the
  // same c.
  const long c = read_matrix_market_size(file("b.mtx")).first;
  check_vector_sizes(dir, c, "b");
  long first = 0;
  long last = 0;
  split_ownership(c, rank, size, first, last);
  const RowRange mine{first, last};

  LocalSystem local;
  local.description = dir;
  local.total_rows = c;
  local.first_row = first;
  if (!read_factors(local, dir, mine, rank, size))
    throw InputError(file("J.mtx") +
                     ": missing; the exact path under MPI works in body space and "
                     "needs the folder's J and Minv (cbps matrices writes them)");
  // A is not solved with, but read: it must be the folder's J Minv Jᵀ (check_factors_agree).
  read_A_rows(local, dir, mine);
  local.factors_read = true;
  read_vectors(local, dir, mine);
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
