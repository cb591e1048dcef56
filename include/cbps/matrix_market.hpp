// Matrix Market files (NIST format), readable by scipy.io.mmread: coordinate for sparse
// matrices, array for vectors. Infinite bounds are written as inf / -inf.
#pragma once

#include <string>

#include "cbps/types.hpp"

namespace cbps {

/// Writes a sparse matrix as "%%MatrixMarket matrix coordinate real general". The comment
/// line (may be empty) goes after the header. Throws std::runtime_error if the file fails.
void write_matrix_market(const std::string& path, const SpMat& M, const std::string& comment);

/// Writes a vector as an n×1 "%%MatrixMarket matrix array real general".
void write_matrix_market(const std::string& path, const VecX& v, const std::string& comment);

}  // namespace cbps
