// Matrix Market files (NIST format), readable by scipy.io.mmread: coordinate for sparse
// matrices, array for vectors. Infinite bounds are written as inf / -inf. The readers take back
// what the writers (and scipy.io.mmwrite) write.
#pragma once

#include <string>

#include "cbps/types.hpp"

namespace cbps {

/// Writes a sparse matrix as "%%MatrixMarket matrix coordinate real general". The comment
/// line (may be empty) goes after the header. Throws std::runtime_error if the file fails.
void write_matrix_market(const std::string& path, const SpMat& M, const std::string& comment);

/// Writes a vector as an n×1 "%%MatrixMarket matrix array real general".
void write_matrix_market(const std::string& path, const VecX& v, const std::string& comment);

/// Reads a "%%MatrixMarket matrix coordinate real general" (or "symmetric", expanded to both
/// triangles; "integer" is read as real) sparse matrix. Duplicate entries are summed, as
/// scipy does. Throws InputError "<path>: line L: <why>" on a missing file, a bad header, wrong
/// counts, an index out of range, a token that is not a number, or NaN.
SpMat read_matrix_market_sparse(const std::string& path);

/// Reads an n×1 "%%MatrixMarket matrix array real general" vector; inf, -inf, Inf and Infinity
/// are read as ±∞. Throws InputError "<path>: line L: <why>" as read_matrix_market_sparse.
VecX read_matrix_market_vector(const std::string& path);

}  // namespace cbps
