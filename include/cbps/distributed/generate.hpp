// A problem too large for one process, generated per rank (issue 18, docs/distributed.md): each
// rank of an MPI job builds only its own rows of the system of 6.1–6.2, with global row and
// column numbering, by the library code of the serial path (the scene's builder, build_rows,
// assemble_system). No PETSc here: src/distributed/tao.cpp turns a LocalSystem into PETSc's
// distributed J, Minv and A = J Minv Jᵀ.
//
//   Symbol   This rank's part                      Unit
//   J        rows [first_row, first_row + rows)    1 (linear), m (angular)
//            of J, every one of the 6n columns
//   Minv     rows [first_column, first_column      kg⁻¹, kg⁻¹ m⁻²
//            + owned_columns): its own bodies' diagonal blocks
//   b        its rows of b (6.2.9)                 m/s²
//   cmin     its rows                              N
//   cmax     its rows                              N
#pragma once

#include <map>
#include <string>

#include "cbps/types.hpp"

namespace cbps::distributed {

/// This rank's rows of the system of one step (6.1, 6.2.9), in global numbering.
struct LocalSystem {
  std::string description;  ///< e.g. "generated chain, n = 1000000, step 0"
  long total_rows = 0;      ///< c, rows of the whole system
  long total_columns = 0;   ///< 6n, columns of the whole J
  long first_row = 0;       ///< global index of this rank's first row
  long first_column = 0;    ///< global index of this rank's first column of J (row of Minv)
  long owned_columns = 0;   ///< columns of J (rows of Minv) this rank owns: 6 per owned body
  SpMatRow J;               ///< rows()×6n: this rank's rows of J, global columns (6.1)
  SpMatRow Minv;            ///< owned_columns×6n: this rank's rows of Minv (6.1.2)
  VecX b;                   ///< this rank's rows of b = upsilon/dt − J (v1/dt + Minv fext)
  VecX cmin;                ///< this rank's rows of cmin (5.1)
  VecX cmax;                ///< this rank's rows of cmax (5.1)
  long rows() const { return static_cast<long>(b.size()); }
};

/// The contiguous share [begin, end) of `count` items that rank `rank` of `size` owns: the
/// first count % size ranks one more than the others (PETSc's PetscSplitOwnership's split).
void split_ownership(long count, int rank, int size, long& begin, long& end);

/// Rank `rank` of `size`'s part of the built-in `chain` of `values` (NAME=VALUE overrides, n
/// its links) at step 0: the joints (rows) and links (bodies, 6 columns each) split_ownership
/// gives it, built with the one neighbour link it shares with the rank before; row k is joint k,
/// column block k link k, as `cbps matrices chain --step 0` numbers them. Throws InputError for
/// a bad parameter or more ranks than links.
LocalSystem generate_chain(const std::map<std::string, std::string>& values, int rank, int size);

}  // namespace cbps::distributed
