// Matrix Market files (NIST format), readable by scipy.io.mmread: coordinate for sparse
// matrices, array for vectors. Infinite bounds are written as inf / -inf. The readers take back
// what the writers (and scipy.io.mmwrite) write.
#pragma once

#include <istream>
#include <string>
#include <utility>

#include "cbps/base/types.hpp"

namespace cbps {

/// The largest number of rows or columns read: a sparse matrix allocates per row and column
/// before its entries are read, so a larger size is more likely a corrupt header than a problem.
inline constexpr long kMaxMatrixMarketSize = 10'000'000;

/// Writes a sparse matrix as "%%MatrixMarket matrix coordinate real general". The comment
/// line (may be empty) goes after the header. Throws std::runtime_error if the file fails.
void write_matrix_market(const std::string& path, const SpMat& M, const std::string& comment);

/// Writes a vector as an n×1 "%%MatrixMarket matrix array real general".
void write_matrix_market(const std::string& path, const VecX& v, const std::string& comment);

/// Reads a "%%MatrixMarket matrix coordinate real general" (or "symmetric", expanded to both
/// triangles; "integer" is read as real) sparse matrix. Duplicate entries are summed, as
/// scipy does. Throws InputError "<path>: line L: <why>" on a missing file, a bad header, wrong
/// counts, more than kMaxMatrixMarketSize rows or columns, an index out of range, a token that
/// is not a number, or NaN (also duplicates summing to NaN, inf + -inf).
SpMat read_matrix_market_sparse(const std::string& path);

/// Reads an n×1 "%%MatrixMarket matrix array real general" vector; inf, -inf, Inf and Infinity
/// are read as ±∞. Throws InputError "<path>: line L: <why>" as read_matrix_market_sparse.
VecX read_matrix_market_vector(const std::string& path);

/// A vector from a file that is either a Matrix Market array (read_matrix_market_vector: a
/// first line "%%MatrixMarket") or plain text, one number a line (blank lines and lines starting
/// with '#' or '%' skipped). Every entry must be finite (a given lambda, w). Throws InputError
/// "<path>: line L: <why>" as read_matrix_market_vector, and on an entry that is not finite.
VecX read_vector_file(const std::string& path);
VecX parse_vector_text(std::istream& in, const std::string& source);

/// read_matrix_market_sparse from a stream; `source` names it in errors ("<source>: line L: ").
SpMat parse_matrix_market_sparse(std::istream& in, const std::string& source);

/// read_matrix_market_vector from a stream; `source` names it in errors.
VecX parse_matrix_market_vector(std::istream& in, const std::string& source);

/// Rows [first, last) of a matrix or vector: the part one rank of a distributed job keeps
/// (docs/distributed.md, "Reading a folder by rows").
struct RowRange {
  long first = 0;
  long last = 0;
};

/// The rows and columns the size line of the Matrix Market file `path` declares (its header
/// and size line checked as the readers check them; the entries not read).
std::pair<long, long> read_matrix_market_size(const std::string& path);

/// The rows `keep` of the file's sparse matrix, as a (keep.last − keep.first) × columns matrix
/// (row r of it is row keep.first + r of the file's). Every line is parsed and checked as by
/// read_matrix_market_sparse, only the kept rows' entries are stored, and only their duplicate
/// sums are checked (each row's check belongs to the rank that keeps it). Throws InputError
/// also when `keep` is not inside the file's rows.
SpMat read_matrix_market_sparse_rows(const std::string& path, RowRange keep);

/// The entries `keep` of the file's n×1 vector, checked as read_matrix_market_vector; only
/// those stored.
VecX read_matrix_market_vector_rows(const std::string& path, RowRange keep);

/// read_matrix_market_sparse_rows and read_matrix_market_vector_rows from a stream; `source`
/// names it in errors.
SpMat parse_matrix_market_sparse_rows(std::istream& in, const std::string& source, RowRange keep);
VecX parse_matrix_market_vector_rows(std::istream& in, const std::string& source, RowRange keep);

}  // namespace cbps
