// Each rank's rows of a generated system (include/cbps/distributed/generate.hpp). No PETSc or
// MPI here: the rank and the job's size come from the caller.
#include "cbps/distributed/generate.hpp"

#include <algorithm>
#include <vector>

#include "cbps/error.hpp"
#include "cbps/rows/build_rows.hpp"
#include "cbps/scene/builtin.hpp"
#include "cbps/system/system.hpp"

namespace cbps::distributed {

void split_ownership(long count, int rank, int size, long& begin, long& end) {
  const long share = count / size;
  const long extra = count % size;
  begin = rank * share + std::min<long>(rank, extra);
  end = begin + share + (rank < extra ? 1 : 0);
}

LocalSystem generate_chain(const std::map<std::string, std::string>& values, int rank, int size) {
  const auto it = values.find("n");
  std::size_t used = 0;
  long n = 0;
  try {
    if (it != values.end()) n = std::stol(it->second, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (it == values.end() || used != it->second.size() || n < 1)
    throw InputError("generate chain: n must be a whole number of links >= 1");
  if (n < size)
    throw InputError("generate chain: " + std::to_string(n) + " links on " + std::to_string(size) +
                     " ranks; give every rank at least one link (more rows or fewer ranks)");
  long begin = 0;
  long end = 0;
  split_ownership(n, rank, size, begin, end);

  // This rank's part of the scene, its rows and its system, by the serial path's own code: the
  // scene builder, the row stage (5.2) and the assembly (6.1, 6.2.9), at step 0.
  const Scene part = build_chain_range(values, begin, end);
  std::vector<Row> rows;
  build_rows(part.bodies, part.distances, {}, part.world.rows(), rows);
  const System sys =
      assemble_system(part.bodies, rows, part.world.gravity, part.world.dt, part.world.push);
  // Every link is movable: block i of the part is its body i, global link lowest + i.
  const long lowest = std::max(begin - 1, 0L);
  if (sys.blocks() != static_cast<int>(part.bodies.size()) || sys.rows() != end - begin)
    throw ComputationError("generate chain: the part's system has " + std::to_string(sys.blocks()) +
                           " blocks and " + std::to_string(sys.rows()) + " rows where " +
                           std::to_string(part.bodies.size()) + " and " +
                           std::to_string(end - begin) + " were expected");

  LocalSystem local;
  local.description = "generated chain, n = " + std::to_string(n) + ", step 0";
  local.total_rows = n;  // one distance row per joint (5.2)
  local.total_columns = 6 * n;
  local.first_row = begin;
  local.first_column = 6 * begin;
  local.owned_columns = 6 * (end - begin);
  const long offset = 6 * lowest;  // global column of the part's column 0

  // J: the part's rows, its columns moved to their global place.
  std::vector<Triplet> entries;
  entries.reserve(static_cast<std::size_t>(sys.J.nonZeros()));
  for (Eigen::Index i = 0; i < sys.J.outerSize(); ++i)
    for (SpMatRow::InnerIterator e(sys.J, i); e; ++e)
      entries.emplace_back(static_cast<int>(i), static_cast<int>(offset + e.col()), e.value());
  local.J.resize(sys.J.rows(), local.total_columns);
  local.J.setFromTriplets(entries.begin(), entries.end());

  // Minv: the diagonal blocks of the links this rank owns (not the shared neighbour's, which
  // the rank before owns), rows and columns in global numbering.
  entries.clear();
  for (Eigen::Index j = 0; j < sys.Minv.outerSize(); ++j)
    for (SpMat::InnerIterator e(sys.Minv, j); e; ++e) {
      const long row = offset + e.row();
      if (row < local.first_column || row >= local.first_column + local.owned_columns) continue;
      entries.emplace_back(static_cast<int>(row - local.first_column),
                           static_cast<int>(offset + e.col()),
                           e.value());
    }
  local.Minv.resize(local.owned_columns, local.total_columns);
  local.Minv.setFromTriplets(entries.begin(), entries.end());

  // b, cmin, cmax: row by row as the part's system has them (b's row k needs only the bodies of
  // row k, both in the part).
  local.b = sys.b;
  local.cmin = sys.cmin;
  local.cmax = sys.cmax;
  return local;
}

}  // namespace cbps::distributed
