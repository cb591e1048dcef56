// Each rank's rows of a generated system (include/cbps/distributed/generate.hpp). No PETSc or
// MPI here: the rank and the job's size come from the caller.
#include "cbps/distributed/generate.hpp"

#include <algorithm>
#include <vector>

#include "cbps/base/error.hpp"
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
  local.b.resize(end - begin);
  local.cmin.resize(end - begin);
  local.cmax.resize(end - begin);
  local.A.resize(end - begin, local.total_rows);
  local.A.reserve(3 * (end - begin));  // joint k couples to joints k − 1, k, k + 1

  // This rank's joints in chunks of kChunk (the scene part, its labelled rows and its whole
  // System are several times the size of the rows kept: only one chunk's are alive at a time).
  // Each chunk by the serial path's own code: the scene builder, the row stage (5.2) and the
  // assembly (6.1, 6.2.9), at step 0, over the chunk's joints and one halo joint on either side
  // (the halo rows of the part's A are incomplete and dropped). A is filled row by row in order
  // (Eigen's startVec / insertBack: no triplets).
  constexpr long kChunk = 4096;
  for (long first = begin; first < end; first += kChunk) {
    const long last = std::min(end, first + kChunk);
    const long halo_first = std::max(first - 1, 0L);  // joints [halo_first, halo_last)
    const long halo_last = std::min(last + 1, n);
    const Scene part = build_chain_range(values, halo_first, halo_last);
    std::vector<Row> rows;
    build_rows(part.bodies, part.distances, {}, part.world.rows(), rows);
    const System sys =
        assemble_system(part.bodies, rows, part.world.gravity, part.world.dt, part.world.push);
    if (sys.rows() != halo_last - halo_first)
      throw ComputationError("generate chain: the part's system has " + std::to_string(sys.rows()) +
                             " rows where " + std::to_string(halo_last - halo_first) +
                             " were expected");
    // Row i of the part is joint halo_first + i; the chunk's own rows are [first, last).
    const SpMatRow A_rows(sys.A);
    for (long k = first; k < last; ++k) {
      const Eigen::Index i = k - halo_first;
      const Eigen::Index row = k - begin;
      local.A.startVec(row);
      for (SpMatRow::InnerIterator e(A_rows, i); e; ++e)
        local.A.insertBack(row, halo_first + e.col()) = e.value();
      local.b[row] = sys.b[i];
      local.cmin[row] = sys.cmin[i];
      local.cmax[row] = sys.cmax[i];
    }
  }
  local.A.finalize();
  return local;
}

}  // namespace cbps::distributed
