// Each rank's rows of a generated system (include/cbps/distributed/generate.hpp). No PETSc or
// MPI here: the rank and the job's size come from the caller.
#include "cbps/distributed/generate.hpp"

#include <algorithm>
#include <vector>

#include "cbps/base/error.hpp"
#include "cbps/collision/collision.hpp"
#include "cbps/rows/build_rows.hpp"
#include "cbps/scene/builtin.hpp"
#include "cbps/solvers/exact/interior_point.hpp"
#include "cbps/system/system.hpp"

namespace cbps::distributed {

namespace {

/// Pyramid boxes generated at a time (the scene part, its rows and its System are several times
/// the size of what is kept: only one chunk's are alive at a time); at least a whole bottom row.
constexpr long kPyramidChunk = 1024;

/// A rank's rows of a generated contact scene as they are built, chunk after chunk: J's rows
/// (global columns), b, cmin, cmax; its bodies' rows of Minv and mass matrices.
struct RowsBuilt {
  std::vector<SpMatRow> J;  ///< each chunk's rows of J, its columns from `column` on
  std::vector<long> column;
  std::vector<double> b, cmin, cmax;
  std::vector<Triplet> Minv;  ///< (6 · local body + i, global column, value)

  /// The rows and movable bodies of one chunk's System whose movable bodies are the boxes
  /// [first_box, ...) and whose first `own` of them are this rank's (local body `local_body`
  /// on): every row of `sys` is this rank's.
  void add(const System& sys, long first_box, long own, long local_body) {
    J.push_back(sys.J);
    column.push_back(6 * first_box);
    for (Eigen::Index k = 0; k < sys.J.rows(); ++k) {
      b.push_back(sys.b(k));
      cmin.push_back(sys.cmin(k));
      cmax.push_back(sys.cmax(k));
    }
    for (Eigen::Index j = 0; j < sys.Minv.outerSize(); ++j)
      for (SpMat::InnerIterator e(sys.Minv, j); e; ++e)
        if (e.row() < 6 * own)
          Minv.emplace_back(int(6 * local_body + e.row()), int(6 * first_box + e.col()), e.value());
  }

  /// Into `local`: J (rows in the order added), b, cmin, cmax, Minv and M (body_mass of each
  /// 6×6 block).
  void finish(LocalSystem& local) && {
    long rows = 0;
    long entries = 0;
    for (const SpMatRow& part : J) {
      rows += part.rows();
      entries += part.nonZeros();
    }
    local.J.resize(rows, local.total_columns);
    local.J.reserve(entries);
    long row = 0;
    for (std::size_t p = 0; p < J.size(); ++p) {
      for (Eigen::Index k = 0; k < J[p].rows(); ++k, ++row) {
        local.J.startVec(row);
        for (SpMatRow::InnerIterator e(J[p], k); e; ++e)
          local.J.insertBack(row, column[p] + e.col()) = e.value();
      }
      J[p] = SpMatRow();  // released as soon as copied
    }
    local.J.finalize();
    local.b = Eigen::Map<const VecX>(b.data(), rows);
    local.cmin = Eigen::Map<const VecX>(cmin.data(), rows);
    local.cmax = Eigen::Map<const VecX>(cmax.data(), rows);
    local.Minv.resize(6 * local.bodies, local.total_columns);
    local.Minv.setFromTriplets(Minv.begin(), Minv.end());
    local.M = body_masses(local, local.description);
  }
};

}  // namespace

void split_ownership(long count, int rank, int size, long& begin, long& end) {
  const long share = count / size;
  const long extra = count % size;
  begin = rank * share + std::min<long>(rank, extra);
  end = begin + share + (rank < extra ? 1 : 0);
}

std::vector<Mat6> body_masses(const LocalSystem& local, const std::string& source) {
  std::vector<Mat6> M(std::size_t(local.bodies));
  std::vector<Mat6> blocks(std::size_t(local.bodies), Mat6::Zero());
  for (Eigen::Index i = 0; i < local.Minv.rows(); ++i)
    for (SpMatRow::InnerIterator it(local.Minv, i); it; ++it) {
      const long body = (local.first_body * 6 + i) / 6;
      if (it.col() / 6 != body)
        throw InputError(source + ": the entry at row " +
                         std::to_string(local.first_body * 6 + i + 1) + ", column " +
                         std::to_string(it.col() + 1) +
                         " (1-based, as in the file) couples two bodies; body space needs Minv "
                         "block diagonal (6.1.2)");
      blocks[std::size_t(body - local.first_body)](i % 6, it.col() % 6) = it.value();
    }
  for (long B = 0; B < local.bodies; ++B)
    if (!body_mass(blocks[std::size_t(B)], M[std::size_t(B)]))
      throw InputError(source + ": the 6x6 block of body " +
                       std::to_string(local.first_body + B + 1) + " (rows " +
                       std::to_string(6 * (local.first_body + B) + 1) + " to " +
                       std::to_string(6 * (local.first_body + B) + 6) +
                       "; bodies and rows counted from 1, as in the file) is not symmetric "
                       "positive definite; body space needs M = Minv^-1");
  return M;
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

LocalSystem generate_pyramid(const std::map<std::string, std::string>& values, int rank, int size) {
  const long base = pyramid_base(values);
  const long boxes = base * (base + 1) / 2;
  long begin = 0;
  long end = 0;
  split_ownership(boxes, rank, size, begin, end);
  long first_of_1 = 0;  // rank 1's first box: rank 0 holds the boxes before it
  long unused = 0;
  split_ownership(boxes, std::min(1, size - 1), size, first_of_1, unused);
  // The ground's contacts come first in the serial numbering (pairs (ground, box) in ascending
  // order): they are all rank 0's rows only when rank 0 holds the whole bottom row.
  if (size > 1 && first_of_1 < base)
    throw InputError("generate pyramid: base " + std::to_string(base) + " (" +
                     std::to_string(boxes) + " boxes) on " + std::to_string(size) +
                     " ranks; rank 0 must hold the whole bottom row: a larger base or fewer "
                     "ranks");

  LocalSystem local;
  local.description = "generated pyramid, base " + std::to_string(base) + " (" +
                      std::to_string(boxes) + " boxes), step 0";
  local.total_columns = 6 * boxes;
  local.first_body = begin;
  local.bodies = end - begin;
  RowsBuilt built;
  // This rank's boxes in chunks, each by the serial path's own code (the scene builder,
  // collision (4), the row stage (5.3, 5.4) and the assembly (6.1, 6.2.9) without A) over the
  // chunk's boxes and the halo: the boxes resting on them, at most `base` further on in the
  // numbering. The contacts kept are the pairs (a, b), a < b, whose a is a box of the chunk or,
  // for the bottom row, the ground: in the serial numbering (pairs in ascending order) these are
  // consecutive rows, and the ranks' rows follow one another in rank order.
  const long chunk = std::max(kPyramidChunk, base);
  for (long first = begin; first < end; first += chunk) {
    const long last = std::min(end, first + chunk);
    const Scene part = build_pyramid_range(values, first, std::min(boxes, last + base));
    const int own_end = 1 + static_cast<int>(last - first);  // part bodies 1 … own_end − 1
    std::vector<Manifold> kept;
    for (Manifold& m : detect_contacts(part.bodies, part.world.contact_margin)) {
      if (m.a == 0 && (rank != 0 || m.b >= own_end))
        throw ComputationError("generate pyramid: " + part.bodies[std::size_t(m.b)].name +
                               " touches the ground but is not among rank 0's first boxes");
      if (m.a < own_end) kept.push_back(std::move(m));
    }
    std::vector<Row> rows;
    build_rows(part.bodies, part.distances, kept, part.world.rows(), rows);
    const System sys = assemble_system(
        part.bodies, rows, part.world.gravity, part.world.dt, part.world.push, false);
    built.add(sys, first, last - first, first - begin);
  }
  std::move(built).finish(local);
  local.total_rows = local.rows();  // until numbered across the ranks (generate.hpp)
  return local;
}

}  // namespace cbps::distributed
