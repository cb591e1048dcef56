// Siconos' friction-contact dumps (io/siconos_fc3d.hpp): the tokens in Siconos' order, every
// structure checked before anything is allocated from it.
#include "cbps/io/siconos_fc3d.hpp"

#include <algorithm>
#include <fstream>
#include <set>
#include <utility>
#include <vector>

#include "cbps/base/error.hpp"
#include "cbps/base/numbers.hpp"
#include "cbps/io/input_file.hpp"
#include "global_problem.hpp"
#include "token_reader.hpp"

namespace cbps {

namespace {

constexpr const char* kExpected = "a Siconos .dat text file (or a cbps matrices folder)";

/// A size read from the file: an integer in [lo, hi], else a failure naming it.
long read_size(TokenReader& in, const std::string& what, long lo, long hi) {
  const long value = in.next_integer(what);
  if (value < lo || value > hi)
    in.fail(in.line(),
            what + " = " + std::to_string(value) + " is outside " + std::to_string(lo) + " … " +
                std::to_string(hi));
  return value;
}

/// The dense form's entries, column by column.
void read_dense(TokenReader& in, const std::string& name, long rows, long cols, SpMat& M) {
  for (const auto& [what, expected] :
       {std::pair<const char*, long>{"rows (again)", rows}, {"columns (again)", cols}}) {
    const long size = in.next_integer(name + " " + what);
    if (size != expected)
      in.fail(in.line(),
              name + " " + what + " = " + std::to_string(size) + ", not " +
                  std::to_string(expected) + " as its header says");
  }
  if (rows * cols > kMaxFc3dDense || static_cast<std::size_t>(rows * cols) > in.remaining())
    in.fail(in.line(),
            name + ": a dense " + std::to_string(rows) + " x " + std::to_string(cols) +
                " matrix needs " + std::to_string(rows * cols) + " numbers; the file has " +
                std::to_string(in.remaining()) + " tokens left");
  std::vector<Triplet> entries;
  for (long j = 0; j < cols; ++j)
    for (long i = 0; i < rows; ++i) {
      const double v = in.next_number(
          [&] { return name + "(" + std::to_string(i) + ", " + std::to_string(j) + ")"; });
      if (v != 0.0) entries.emplace_back(i, j, v);
    }
  M.setFromTriplets(entries.begin(), entries.end());
}

/// `count` cumulative sizes ending at `total`, strictly increasing: each block's first index.
std::vector<long> read_cumulative(
    TokenReader& in, const std::string& what, long count, long total, const std::string& name) {
  std::vector<long> start{0};
  for (long k = 0; k < count; ++k) {
    const long end = in.next_integer(what + "[" + std::to_string(k) + "]");
    if (end <= start.back() || end > total)
      in.fail(in.line(),
              name + ": " + what + "[" + std::to_string(k) + "] = " + std::to_string(end) +
                  " does not increase from " + std::to_string(start.back()) + " within " +
                  std::to_string(total));
    start.push_back(end);
  }
  if (start.back() != total)
    in.fail(in.line(),
            name + ": " + what + " ends at " + std::to_string(start.back()) + ", not at the " +
                std::to_string(total) + " of its header");
  return start;
}

/// The sparse-block form (Siconos' SparseBlockStructuredMatrix, block-CSR, 0-based).
void read_sparse_block(TokenReader& in, const std::string& name, long rows, long cols, SpMat& M) {
  const long blocks = read_size(in, name + " block count", 0, kMaxFc3dSize);
  if (blocks == 0) return;  // Siconos writes nothing more: a zero matrix
  const long block_rows = read_size(in, name + " block rows", 1, rows);
  const long block_cols = read_size(in, name + " block columns", 1, cols);
  const std::vector<long> row0 = read_cumulative(in, "row sizes", block_rows, rows, name);
  const std::vector<long> col0 = read_cumulative(in, "column sizes", block_cols, cols, name);
  const long filled1 = read_size(in, name + " row-pointer length", 1, block_rows + 1);
  const long filled2 = read_size(in, name + " stored-block count", blocks, blocks);
  std::vector<long> pointer(static_cast<std::size_t>(filled1));
  for (long k = 0; k < filled1; ++k) {
    pointer[std::size_t(k)] = in.next_integer(name + " row pointer");
    const long before = k == 0 ? 0 : pointer[std::size_t(k - 1)];
    if (pointer[std::size_t(k)] < before || pointer[std::size_t(k)] > filled2 ||
        (k == 0 && pointer[0] != 0))
      in.fail(in.line(),
              name + ": row pointer " + std::to_string(k) + " = " +
                  std::to_string(pointer[std::size_t(k)]) +
                  " (they start at 0, never decrease and end at " + std::to_string(filled2) + ")");
  }
  if (pointer.back() != filled2)
    in.fail(in.line(),
            name + ": the row pointers end at " + std::to_string(pointer.back()) + ", not at the " +
                std::to_string(filled2) + " blocks stored");
  std::vector<long> column(static_cast<std::size_t>(filled2));
  for (long b = 0; b < filled2; ++b)
    column[std::size_t(b)] =
        read_size(in, name + " block column of block " + std::to_string(b), 0, block_cols - 1);
  std::set<std::pair<long, long>> seen;
  std::vector<Triplet> entries;
  for (long i = 0; i + 1 < filled1; ++i)
    for (long b = pointer[std::size_t(i)]; b < pointer[std::size_t(i + 1)]; ++b) {
      const long j = column[std::size_t(b)];
      if (!seen.insert({i, j}).second)
        in.fail(in.line(),
                name + ": block (" + std::to_string(i) + ", " + std::to_string(j) +
                    ") is stored twice");
      const long echo = in.next_integer(name + " block number");
      if (echo != b)
        in.fail(in.line(),
                name + ": block number " + std::to_string(echo) + " where block " +
                    std::to_string(b) + " was expected");
      const long r = row0[std::size_t(i + 1)] - row0[std::size_t(i)];
      const long c = col0[std::size_t(j + 1)] - col0[std::size_t(j)];
      if (static_cast<std::size_t>(r * c) > in.remaining())
        in.fail(in.line(), name + ": block " + std::to_string(b) + " runs past the end of file");
      for (long q = 0; q < c; ++q)
        for (long p = 0; p < r; ++p) {
          const double v = in.next_number([&] {
            return name + " block " + std::to_string(b) + " entry (" + std::to_string(p) + ", " +
                   std::to_string(q) + ")";
          });
          if (v != 0.0) entries.emplace_back(row0[std::size_t(i)] + p, col0[std::size_t(j)] + q, v);
        }
    }
  M.setFromTriplets(entries.begin(), entries.end());
}

/// One NumericsMatrix: its storage type, rows and columns, then the storage's own form.
SpMat read_matrix(TokenReader& in, const std::string& name) {
  const long storage = in.next_integer(name + " storage type");
  if (storage == 2)
    in.fail(in.line(),
            name +
                ": storage type 2 (CSparse's text form, 6 significant digits) is not read; "
                "write the problem with dense (0) or sparse-block (1) storage, or as FCLIB");
  if (storage != 0 && storage != 1)
    in.fail(
        in.line(),
        name + ": unknown storage type " + std::to_string(storage) + " (0 dense, 1 sparse-block)");
  const long rows = read_size(in, name + " rows", 1, kMaxFc3dSize);
  const long cols = read_size(in, name + " columns", 1, kMaxFc3dSize);
  SpMat M(rows, cols);
  if (storage == 0)
    read_dense(in, name, rows, cols, M);
  else
    read_sparse_block(in, name, rows, cols, M);
  return M;
}

/// `count` numbers (count ≤ kMaxFc3dSize, checked with the sizes they follow).
VecX read_numbers(TokenReader& in, const std::string& name, long count) {
  VecX v(count);
  for (long k = 0; k < count; ++k)
    v(k) = in.next_number([&] { return name + "[" + std::to_string(k) + "]"; });
  return v;
}

std::vector<double> read_mu(TokenReader& in, long contacts) {
  const VecX mu = read_numbers(in, "mu", contacts);
  for (long i = 0; i < contacts; ++i)
    if (mu(i) < 0.0)
      in.fail(in.line(), "mu[" + std::to_string(i) + "] = " + number_text(mu(i)) + " < 0");
  return {mu.data(), mu.data() + mu.size()};
}

/// After mu: nothing, or the legacy flag 0 or 1; nc numbers are a rolling-friction file.
void expect_end(TokenReader& in, long contacts) {
  const std::size_t left = in.remaining();
  if (left == 0) return;
  const Token& t = *in.peek();
  if (left == 1 && (t.text == "0" || t.text == "1")) return;  // the pre-2010 isComplete flag
  if (left == static_cast<std::size_t>(contacts) && in.leading_numbers() == left)
    in.fail(t.line,
            std::to_string(left) +
                " numbers after mu, one per contact: a rolling-friction problem (Siconos' "
                "RollingFrictionContactProblem, its rolling coefficients), which cbps does not "
                "solve");
  in.fail(t.line,
          "'" + t.text + "' and " + std::to_string(left - 1) +
              " more tokens after mu, where the problem ends (at most the legacy flag 0 or 1)");
}

StoredProblem read_local(TokenReader& in, const SpMat& W, long contacts) {
  const long m = 3 * contacts;
  StoredProblem p;
  p.A = W;
  p.b = -read_numbers(in, "q", m);
  const std::vector<double> mu = read_mu(in, contacts);
  expect_end(in, contacts);
  in_cones(p, m, 0, mu);
  p.without_jacobian = "a Siconos friction-contact file carries no J and Minv";
  return p;
}

StoredProblem read_global(TokenReader& in, const SpMat& M, long contacts) {
  const long m = 3 * contacts, n = M.rows();
  if (M.cols() != n)
    in.fail(in.line(),
            "M is " + std::to_string(n) + " x " + std::to_string(M.cols()) +
                ": a global problem's M is square (read as global: after the first matrix the "
                "file does not hold the numbers of a local problem's q and mu)");
  const int line_M = in.line();
  const SpMat H = read_matrix(in, "H");
  if (H.rows() != n || H.cols() != m)
    in.fail(in.line(),
            "H is " + std::to_string(H.rows()) + " x " + std::to_string(H.cols()) + "; M's " +
                std::to_string(n) + " rows by 3 columns per contact (" + std::to_string(m) +
                ") expected");
  GlobalProblem g;
  g.M = M;
  g.H = H;
  g.G.resize(n, 0);
  g.f = read_numbers(in, "f (Siconos' q)", n);
  g.w = read_numbers(in, "w (Siconos' b)", m);
  g.mu = read_mu(in, contacts);
  expect_end(in, contacts);
  StoredProblem p = eliminate_velocities(g, [&](const std::string& why) {
    in.fail(line_M, "M (the matrix ending on this line): " + why);
  });
  return p;
}

}  // namespace

bool looks_like_siconos_fc3d(const std::string& path) {
  std::ifstream in(path);
  long d = 0, second = 0, third = -1, rows = 0, cols = -1;
  if (!(in >> d >> second >> third >> rows >> cols)) return false;
  // The first matrix (W, or a global problem's M) is square.
  return (d == 2 || d == 3 || d == 5) && second >= 1 && third >= 0 && third <= 2 && rows == cols;
}

StoredProblem parse_siconos_fc3d(std::istream& stream, const std::string& source) {
  TokenReader in(stream, source);
  const long d = in.next_integer("d (the dimension of a contact)");
  if (d == 2)
    in.fail(in.line(), "d = 2: a 2-D friction-contact problem; cbps reads 3-D contact (d = 3)");
  if (d == 5)
    in.fail(in.line(),
            "d = 5: a rolling-friction problem (Siconos' RollingFrictionContactProblem), which "
            "cbps does not solve; it reads 3-D Coulomb friction (d = 3)");
  if (d != 3) in.fail(in.line(), "d = " + std::to_string(d) + ": cbps reads 3-D contact (d = 3)");
  const long contacts = read_size(in, "nc (the number of contacts)", 1, kMaxFc3dSize / 3);
  const long m = 3 * contacts;
  const SpMat first = read_matrix(in, "W (M if global)");
  // A local file holds q and mu (m + nc numbers) after its W, at most nc more (rolling, refused)
  // or the legacy flag; a global one a second matrix, H, whose header gives M's rows, and three
  // vectors.
  const Token* storage = in.peek(0);
  const Token* rows = in.peek(1);
  const bool global = storage != nullptr && rows != nullptr &&
                      (storage->text == "0" || storage->text == "1" || storage->text == "2") &&
                      rows->text == std::to_string(first.rows()) &&
                      in.remaining() > static_cast<std::size_t>(m + 2 * contacts + 1);
  const bool local = !global && first.rows() == m && first.cols() == m;
  if (!local && !global)
    in.fail(in.line(),
            "W is " + std::to_string(first.rows()) + " x " + std::to_string(first.cols()) +
                "; a local problem of nc = " + std::to_string(contacts) + " contacts has a " +
                std::to_string(m) + " x " + std::to_string(m) + " W");
  return local ? read_local(in, first, contacts) : read_global(in, first, contacts);
}

StoredProblem read_siconos_fc3d(const std::string& path) {
  std::ifstream in = open_text_file(path, kExpected);
  return parse_siconos_fc3d(in, path);
}

}  // namespace cbps
