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

  LocalSystem local;
  local.description = "generated chain, n = " + std::to_string(n) + ", step 0";
  local.total_rows = n;  // one distance row per joint (5.2)
  local.total_columns = 6 * n;
  local.first_row = begin;
  local.first_column = 6 * begin;
  local.owned_columns = 6 * (end - begin);
  local.b.resize(end - begin);
  local.cmin.resize(end - begin);
  local.cmax.resize(end - begin);
  local.J.resize(end - begin, local.total_columns);
  local.J.reserve(12 * (end - begin));  // a distance row between two links: 2 × 6 entries
  local.Minv.resize(local.owned_columns, local.total_columns);
  local.Minv.reserve(6 * local.owned_columns);  // at most a full 6×6 block a link

  // This rank's joints in chunks of kChunk (the scene part, its labelled rows and its whole
  // System are several times the size of the rows kept: only one chunk's are alive at a time).
  // Each chunk by the serial path's own code: the scene builder, the row stage (5.2) and the
  // assembly (6.1, 6.2.9), at step 0. J and Minv are filled row by row in order (Eigen's
  // startVec / insertBack: no triplets).
  constexpr long kChunk = 4096;
  for (long first = begin; first < end; first += kChunk) {
    const long last = std::min(end, first + kChunk);
    const Scene part = build_chain_range(values, first, last);
    std::vector<Row> rows;
    build_rows(part.bodies, part.distances, {}, part.world.rows(), rows);
    const System sys =
        assemble_system(part.bodies, rows, part.world.gravity, part.world.dt, part.world.push);
    // Every link is movable: block i of the part is its body i, global link lowest + i.
    const long lowest = std::max(first - 1, 0L);
    if (sys.blocks() != static_cast<int>(part.bodies.size()) || sys.rows() != last - first)
      throw ComputationError(
          "generate chain: the part's system has " + std::to_string(sys.blocks()) + " blocks and " +
          std::to_string(sys.rows()) + " rows where " + std::to_string(part.bodies.size()) +
          " and " + std::to_string(last - first) + " were expected");
    const long offset = 6 * lowest;  // global column of the part's column 0

    // J: the chunk's rows, its columns moved to their global place (still ascending).
    for (Eigen::Index i = 0; i < sys.J.outerSize(); ++i) {
      const Eigen::Index row = first - begin + i;
      local.J.startVec(row);
      for (SpMatRow::InnerIterator e(sys.J, i); e; ++e)
        local.J.insertBack(row, offset + e.col()) = e.value();
    }
    // Minv: the diagonal blocks of the chunk's own links [first, last) (not the link before,
    // which the chunk or rank before owns), rows and columns in global numbering.
    const SpMatRow Minv_rows(sys.Minv);
    for (Eigen::Index i = 0; i < Minv_rows.outerSize(); ++i) {
      const long global = offset + i;
      if (global < 6 * first || global >= 6 * last) continue;
      const Eigen::Index row = global - local.first_column;
      local.Minv.startVec(row);
      for (SpMatRow::InnerIterator e(Minv_rows, i); e; ++e)
        local.Minv.insertBack(row, offset + e.col()) = e.value();
    }
    // b, cmin, cmax: row by row as the part's system has them (b's row k needs only the bodies
    // of row k, both in the part).
    local.b.segment(first - begin, last - first) = sys.b;
    local.cmin.segment(first - begin, last - first) = sys.cmin;
    local.cmax.segment(first - begin, last - first) = sys.cmax;
  }
  local.J.finalize();
  local.Minv.finalize();
  return local;
}

}  // namespace cbps::distributed
