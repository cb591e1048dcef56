// A problem too large for one process, generated per rank (issue 18, docs/distributed.md): each
// rank of an MPI job builds only its own rows of the system of 6.1–6.2, with global row and
// column numbering, by the library code of the serial path (the scene's builder, build_rows,
// assemble_system). No PETSc here: src/distributed/tao.cpp turns a LocalSystem into PETSc's
// distributed A.
//
// A row k of A = J Minv Jᵀ (6.2.9) needs the rows of J that share a body with row k, and those
// bodies' blocks of Minv: the rank builds its rows together with that halo (for the chain, the
// joint on either side) and keeps only its own rows of A, b, cmin and cmax. The halo is built
// twice (by both ranks beside it) instead of exchanged; J and Minv live only while one chunk of
// rows is assembled.
//
//   Symbol   This rank's part                               Unit
//   A        rows [first_row, first_row + rows), every      kg⁻¹
//            one of the c columns (6.2.9)
//   b        its rows of b (6.2.9)                          m/s²
//   cmin     its rows                                       N
//   cmax     its rows                                       N
#pragma once

#include <map>
#include <string>

#include "cbps/types.hpp"

namespace cbps::distributed {

/// This rank's rows of the system of one step (6.1, 6.2.9), in global numbering.
struct LocalSystem {
  std::string description;  ///< e.g. "generated chain, n = 1000000, step 0"
  long total_rows = 0;      ///< c, rows of the whole system
  long total_columns = 0;   ///< 6n, columns of the whole J (6.1), never stored
  long first_row = 0;       ///< global index of this rank's first row
  SpMatRow A;               ///< rows()×c: this rank's rows of A = J Minv Jᵀ (6.2.9), kg⁻¹
  VecX b;                   ///< this rank's rows of b = upsilon/dt − J (v1/dt + Minv fext)
  VecX cmin;                ///< this rank's rows of cmin (5.1)
  VecX cmax;                ///< this rank's rows of cmax (5.1)
  long rows() const { return static_cast<long>(b.size()); }
};

/// The contiguous share [begin, end) of `count` items that rank `rank` of `size` owns: the
/// first count % size ranks one more than the others (PETSc's PetscSplitOwnership's split).
void split_ownership(long count, int rank, int size, long& begin, long& end);

/// Rank `rank` of `size`'s part of the built-in `chain` of `values` (NAME=VALUE overrides, n
/// its links) at step 0: the joints (rows) split_ownership gives it, built with the joint on
/// either side (the halo: joint k's row of A couples it to joints k − 1 and k + 1 only) and the
/// links those joints join; row k is joint k, as `cbps matrices chain --step 0` numbers them.
/// Throws InputError for a bad parameter or more ranks than links.
LocalSystem generate_chain(const std::map<std::string, std::string>& values, int rank, int size);

}  // namespace cbps::distributed
