// Siconos' own text dump of a frictional-contact problem (`*.dat`, the files of Siconos numerics'
// FrictionContact test data), read whole: the local problem
//   u = W r + q,   each contact's (u, r) in Coulomb's law (rows normal, t1, t2),
// and the global one
//   M v = H r + f,   u = Hᵀ v + w,
// held in cbps's convention (6.2): A = W, b = −q, lambda = r, the contacts in cones
// (StoredProblem::cones, law Coulomb); a global problem with v eliminated as FCLIB's
// (fclib_file.hpp: A = Hᵀ M⁻¹ H, b = −(Hᵀ M⁻¹ f + w), J = Hᵀ and M⁻¹ kept for rigid bodies).
//
// The layout is Siconos' (frictionContact_printInFile, globalFrictionContact_printInFile and the
// NumericsMatrix writers NM_write_in_file / SBM_write_in_file in Siconos numerics), a stream of
// whitespace-separated tokens:
//   local    d  nc  W  q[d nc]  mu[nc]
//   global   d  nc  M  H  f[n]  w[d nc]  mu[nc]
// then nothing or one legacy flag 0 or 1 (the isComplete field Siconos wrote until 2010). d is the
// contact's dimension (3; 2 is a 2-D problem, 5 rolling friction: refused by name, as is a file
// with nc numbers after mu, the rolling coefficients). A matrix (NumericsMatrix) is its storage
// type, rows and columns, then
//   0 dense          rows and columns again, the entries column by column (entry (i, j) is the
//                    number i + j·rows; each printed line of a square matrix is a column)
//   1 sparse-block   the block count (0: nothing more, a zero matrix), the block rows and
//                    columns, the cumulative sizes of each, the row-pointer and block-count
//                    lengths, the 0-based block-row pointers and block-column indices, then each
//                    block's number and its values column by column
//   2 CSparse text   not read (printed with 6 significant digits; no test file uses it)
// Local and global files begin alike (d nc storage); after the first matrix a global one holds a
// second, H, whose header (storage type, rows) gives M's rows, and more than the d·nc + nc
// numbers (and flag) of a local one's q and mu: the reader tells them apart so, as the name does
// not (GFC3D_TwoRods1-condensed.dat is local).
#pragma once

#include <istream>
#include <string>

#include "cbps/io/stored_problem.hpp"

namespace cbps {

/// The most rows or columns a matrix of a friction-contact dump may claim, and the most entries
/// of a dense one: beyond these a header is more likely corrupt than a problem.
inline constexpr long kMaxFc3dSize = 1'000'000;
inline constexpr long kMaxFc3dDense = 25'000'000;

/// True when the file's first tokens read as a friction-contact dump, d nc storage rows cols
/// with d ∈ {2, 3, 5}, nc ≥ 1, storage 0 to 2 and rows = cols, rather than an LCP's n 0 n n
/// (its second token, the storage type, is 0 for every LCP cbps reads).
bool looks_like_siconos_fc3d(const std::string& path);

/// Reads a local or global friction-contact dump. Throws InputError "<path>: line L: <why>" on
/// anything else: a 2-D or rolling-friction problem (named), a wrong size, a token that is not
/// a number, a non-finite value, a negative mu, a malformed sparse-block structure, too few
/// numbers or trailing numbers that are not the legacy flag.
StoredProblem read_siconos_fc3d(const std::string& path);
StoredProblem parse_siconos_fc3d(std::istream& in, const std::string& source);

}  // namespace cbps
