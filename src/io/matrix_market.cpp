// Matrix Market writer and reader.
#include "cbps/io/matrix_market.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "cbps/base/error.hpp"
#include "cbps/base/numbers.hpp"
#include "cbps/io/input_file.hpp"

namespace cbps {

namespace {

/// Shortest text that reads back to the same double; inf and -inf spelled out.
std::string exact_text(double x) {
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

std::ofstream open_for_writing(const std::string& path) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error(path + ": cannot open for writing");
  return out;
}

void write_comment(std::ofstream& out, const std::string& comment) {
  if (!comment.empty()) out << "% " << comment << "\n";
}

void finish(std::ofstream& out, const std::string& path) {
  out.flush();
  if (!out) throw std::runtime_error(path + ": write failed");
}

}  // namespace

void write_matrix_market(const std::string& path, const SpMat& M, const std::string& comment) {
  std::ofstream out = open_for_writing(path);
  out << "%%MatrixMarket matrix coordinate real general\n";
  write_comment(out, comment);
  out << M.rows() << " " << M.cols() << " " << M.nonZeros() << "\n";
  for (Eigen::Index c = 0; c < M.outerSize(); ++c) {
    for (SpMat::InnerIterator it(M, c); it; ++it) {
      out << it.row() + 1 << " " << it.col() + 1 << " " << exact_text(it.value()) << "\n";
    }
  }
  finish(out, path);
}

void write_matrix_market(const std::string& path, const VecX& v, const std::string& comment) {
  std::ofstream out = open_for_writing(path);
  out << "%%MatrixMarket matrix array real general\n";
  write_comment(out, comment);
  out << v.size() << " 1\n";
  for (Eigen::Index k = 0; k < v.size(); ++k) out << exact_text(v(k)) << "\n";
  finish(out, path);
}

namespace {

/// Reads a Matrix Market text line by line; every error names the source and the line.
class LineReader {
 public:
  LineReader(std::istream& in, const std::string& source) : source_(source), in_(in) {}

  [[noreturn]] void fail(const std::string& why) const {
    throw InputError(source_ + ": line " + std::to_string(line_) + ": " + why);
  }

  /// The header's words, lower case: matrix, format, field, symmetry.
  std::vector<std::string> header() {
    std::string text;
    if (!std::getline(in_, text)) fail("empty file, expected a %%MatrixMarket header");
    line_ = 1;
    std::istringstream words(text);
    std::vector<std::string> w;
    std::string word;
    while (words >> word) {
      std::transform(word.begin(), word.end(), word.begin(), [](unsigned char c) {
        return static_cast<char>(std::tolower(c));
      });
      w.push_back(word);
    }
    if (w.size() != 5 || w[0] != "%%matrixmarket" || w[1] != "matrix")
      fail("expected '%%MatrixMarket matrix <format> <field> <symmetry>', found '" + text + "'");
    w.erase(w.begin(), w.begin() + 2);
    return w;
  }

  /// The tokens of the next line that is neither a comment nor blank; `what` names it if the
  /// file ends first.
  std::vector<std::string> next_line(const std::string& what) {
    std::string text;
    while (std::getline(in_, text)) {
      ++line_;
      std::istringstream words(text);
      std::vector<std::string> tokens;
      std::string token;
      while (words >> token) tokens.push_back(token);
      if (tokens.empty() || tokens[0][0] == '%') continue;
      return tokens;
    }
    fail("end of file where " + what + " was expected");
  }

  /// No data may follow the last entry.
  void expect_end(long count) {
    std::string text;
    while (std::getline(in_, text)) {
      ++line_;
      std::istringstream words(text);
      std::string token;
      if ((words >> token) && token[0] != '%')
        fail("more entries than the " + std::to_string(count) + " the size line declares");
    }
  }

  /// A whole token as a positive integer no larger than `limit`.
  long integer(const std::string& token, const std::string& what, long limit) const {
    errno = 0;
    char* end = nullptr;
    const long value = std::strtol(token.c_str(), &end, 10);
    if (end == token.c_str() || *end != '\0' || errno == ERANGE)
      fail("expected an integer " + what + ", found '" + token + "'");
    if (value < 1 || value > limit)
      fail(what + " " + token + " is out of range 1.." + std::to_string(limit));
    return value;
  }

  /// A whole token as a double; inf, -inf, Inf, Infinity accepted, NaN refused.
  double number(const std::string& token, const std::string& what) const {
    double value = 0.0;
    if (!parse_token(token, value)) fail("expected a number " + what + ", found '" + token + "'");
    if (std::isnan(value)) fail("NaN " + what);
    return value;
  }

  /// The size line's integers (nonnegative; a size of 0 is allowed). The first `dimensions`
  /// of them are rows or columns, at most kMaxMatrixMarketSize; the rest (the entry count) are
  /// only bounded by the entries that follow.
  std::vector<long> sizes(std::size_t count, std::size_t dimensions) {
    const std::vector<std::string> t = next_line("the size line");
    if (t.size() != count)
      fail("the size line needs " + std::to_string(count) + " integers, found " +
           std::to_string(t.size()));
    std::vector<long> v;
    for (const std::string& token : t) {
      errno = 0;
      char* end = nullptr;
      const long value = std::strtol(token.c_str(), &end, 10);
      if (end == token.c_str() || *end != '\0' || errno == ERANGE || value < 0 ||
          value > (1L << 31) - 1)
        fail("expected a size, found '" + token + "'");
      if (v.size() < dimensions && value > kMaxMatrixMarketSize)
        fail("size " + token + " is larger than the " + std::to_string(kMaxMatrixMarketSize) +
             " rows or columns read");
      v.push_back(value);
    }
    return v;
  }

  int line() const { return line_; }

 private:
  std::string source_;
  std::istream& in_;
  int line_ = 0;
};

void check_field(const LineReader& r, const std::string& field) {
  if (field != "real" && field != "integer")
    r.fail("field '" + field + "' is not read (only real or integer)");
}

/// The matrix of `entries`, duplicates summed in file order (as setFromTriplets and scipy sum
/// them), built column by column: the cost is one pass over the columns and a sort of the
/// entries, with no row-sized work (setFromTriplets transposes through a row-major copy, which
/// made an empty 10^7 x 1 matrix take seconds). A duplicate sum of NaN (inf + -inf) is refused
/// at the line of its last entry.
SpMat assemble(const std::vector<Triplet>& entries,
               const std::vector<int>& lines,
               long rows,
               long cols,
               const std::string& source) {
  std::vector<std::size_t> order(entries.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const Triplet& x = entries[a];
    const Triplet& y = entries[b];
    return x.col() != y.col() ? x.col() < y.col() : x.row() < y.row();
  });
  SpMat M(rows, cols);
  M.reserve(static_cast<Eigen::Index>(entries.size()));
  std::size_t k = 0;
  for (Eigen::Index c = 0; c < cols; ++c) {
    M.startVec(c);
    while (k < order.size() && entries[order[k]].col() == c) {
      const Triplet& first = entries[order[k]];
      double sum = first.value();
      int line = lines[order[k]];
      for (++k; k < order.size() && entries[order[k]].col() == c &&
                entries[order[k]].row() == first.row();
           ++k) {
        sum += entries[order[k]].value();
        line = lines[order[k]];
      }
      if (std::isnan(sum))
        throw InputError(source + ": line " + std::to_string(line) + ": duplicate entries at (" +
                         std::to_string(first.row() + 1) + ", " + std::to_string(c + 1) +
                         ") sum to NaN (inf + -inf)");
      M.insertBack(first.row(), c) = sum;
    }
  }
  M.finalize();
  return M;
}

/// Opens `path` for a reader (open_text_file: missing, a folder or binary named as such).
std::ifstream open_for_reading(const std::string& path) {
  return open_text_file(path, "a Matrix Market text file");
}

/// The whole file (keep empty) or the rows `keep` of it, shifted to start at 0.
SpMat parse_sparse(std::istream& in, const std::string& source, const RowRange* keep) {
  LineReader r(in, source);
  const std::vector<std::string> h = r.header();
  if (h[0] != "coordinate") r.fail("expected a coordinate (sparse) matrix, found '" + h[0] + "'");
  check_field(r, h[1]);
  const bool symmetric = h[2] == "symmetric";
  if (!symmetric && h[2] != "general")
    r.fail("symmetry '" + h[2] + "' is not read (only general or symmetric)");
  const std::vector<long> s = r.sizes(3, 2);
  const long rows = s[0], cols = s[1], nnz = s[2];
  if (symmetric && rows != cols) r.fail("a symmetric matrix must be square");
  if (keep && (keep->first < 0 || keep->last > rows || keep->first > keep->last))
    r.fail("rows [" + std::to_string(keep->first) + ", " + std::to_string(keep->last) +
           ") asked of a matrix of " + std::to_string(rows) + " rows");
  const long first = keep ? keep->first : 0;
  const long last = keep ? keep->last : rows;
  const auto kept = [&](long i) { return i >= first && i < last; };
  // No reserve() from the declared count: the file may hold far fewer entries than it claims.
  std::vector<Triplet> entries;
  std::vector<int> lines;  // the line of each entry in `entries`, for the check below
  for (long k = 0; k < nnz; ++k) {
    const std::string what = "entry " + std::to_string(k + 1) + " of " + std::to_string(nnz);
    const std::vector<std::string> t = r.next_line(what);
    if (t.size() != 3)
      r.fail(what + " needs 'row column value', found " + std::to_string(t.size()) + " tokens");
    const long i = r.integer(t[0], "row index", rows) - 1;
    const long j = r.integer(t[1], "column index", cols) - 1;
    const double value = r.number(t[2], "in " + what);
    if (symmetric && j > i) r.fail("a symmetric file holds the lower triangle only (row < column)");
    if (kept(i)) {
      entries.emplace_back(i - first, j, value);
      lines.push_back(r.line());
    }
    if (symmetric && i != j && kept(j)) {
      entries.emplace_back(j - first, i, value);
      lines.push_back(r.line());
    }
  }
  r.expect_end(nnz);
  return assemble(entries, lines, last - first, cols, source);
}

/// The whole vector (keep empty) or its entries `keep`.
VecX parse_vector(std::istream& in, const std::string& source, const RowRange* keep) {
  LineReader r(in, source);
  const std::vector<std::string> h = r.header();
  if (h[0] != "array") r.fail("expected an array (dense) vector, found '" + h[0] + "'");
  check_field(r, h[1]);
  if (h[2] != "general") r.fail("symmetry '" + h[2] + "' is not read for a vector (only general)");
  const std::vector<long> s = r.sizes(2, 2);
  if (s[1] != 1) r.fail("expected an n x 1 vector, found " + std::to_string(s[1]) + " columns");
  if (keep && (keep->first < 0 || keep->last > s[0] || keep->first > keep->last))
    r.fail("rows [" + std::to_string(keep->first) + ", " + std::to_string(keep->last) +
           ") asked of a vector of " + std::to_string(s[0]) + " rows");
  const long first = keep ? keep->first : 0;
  const long last = keep ? keep->last : s[0];
  // Grown entry by entry rather than sized from the declared n, which a short file may not hold.
  std::vector<double> values;
  for (long k = 0; k < s[0]; ++k) {
    const std::string what = "entry " + std::to_string(k + 1) + " of " + std::to_string(s[0]);
    const std::vector<std::string> t = r.next_line(what);
    if (t.size() != 1)
      r.fail(what + " needs one number, found " + std::to_string(t.size()) + " tokens");
    const double value = r.number(t[0], "in " + what);
    if (k >= first && k < last) values.push_back(value);
  }
  r.expect_end(s[0]);
  return Eigen::Map<const VecX>(values.data(), static_cast<Eigen::Index>(values.size()));
}

}  // namespace

SpMat parse_matrix_market_sparse(std::istream& in, const std::string& source) {
  return parse_sparse(in, source, nullptr);
}

VecX parse_matrix_market_vector(std::istream& in, const std::string& source) {
  return parse_vector(in, source, nullptr);
}

SpMat read_matrix_market_sparse(const std::string& path) {
  std::ifstream in = open_for_reading(path);
  return parse_matrix_market_sparse(in, path);
}

VecX read_matrix_market_vector(const std::string& path) {
  std::ifstream in = open_for_reading(path);
  return parse_matrix_market_vector(in, path);
}

VecX parse_vector_text(std::istream& in, const std::string& source) {
  std::string first;
  const std::streampos start = in.tellg();
  std::getline(in, first);
  in.clear();
  in.seekg(start);
  VecX v;
  if (first.rfind("%%MatrixMarket", 0) == 0) {
    v = parse_matrix_market_vector(in, source);
    for (Eigen::Index k = 0; k < v.size(); ++k)
      if (!std::isfinite(v(k)))
        throw InputError(source + ": entry " + std::to_string(k + 1) + " is not finite");
    return v;
  }
  std::vector<double> values;
  std::string text;
  for (long line = 1; std::getline(in, text); ++line) {
    std::istringstream words(text);
    std::vector<std::string> tokens;
    for (std::string token; words >> token;) tokens.push_back(token);
    if (tokens.empty() || tokens[0][0] == '#' || tokens[0][0] == '%') continue;
    const std::string where = source + ": line " + std::to_string(line) + ": ";
    double value = 0.0;
    if (tokens.size() != 1 || !parse_token(tokens[0], value))
      throw InputError(where + "expected one number, found '" + text + "'");
    if (!std::isfinite(value)) throw InputError(where + "'" + tokens[0] + "' is not finite");
    if (values.size() >= static_cast<std::size_t>(kMaxMatrixMarketSize))
      throw InputError(where + "more than " + std::to_string(kMaxMatrixMarketSize) + " numbers");
    values.push_back(value);
  }
  return Eigen::Map<const VecX>(values.data(), static_cast<Eigen::Index>(values.size()));
}

VecX read_vector_file(const std::string& path) {
  std::ifstream in = open_for_reading(path);
  return parse_vector_text(in, path);
}

std::pair<long, long> read_matrix_market_size(const std::string& path) {
  std::ifstream in = open_for_reading(path);
  LineReader r(in, path);
  const std::vector<std::string> h = r.header();
  check_field(r, h[1]);
  if (h[0] == "coordinate") {
    const std::vector<long> s = r.sizes(3, 2);
    return {s[0], s[1]};
  }
  if (h[0] != "array") r.fail("expected a coordinate or array matrix, found '" + h[0] + "'");
  const std::vector<long> s = r.sizes(2, 2);
  return {s[0], s[1]};
}

SpMat parse_matrix_market_sparse_rows(std::istream& in, const std::string& source, RowRange keep) {
  return parse_sparse(in, source, &keep);
}

VecX parse_matrix_market_vector_rows(std::istream& in, const std::string& source, RowRange keep) {
  return parse_vector(in, source, &keep);
}

SpMat read_matrix_market_sparse_rows(const std::string& path, RowRange keep) {
  std::ifstream in = open_for_reading(path);
  return parse_sparse(in, path, &keep);
}

VecX read_matrix_market_vector_rows(const std::string& path, RowRange keep) {
  std::ifstream in = open_for_reading(path);
  return parse_vector(in, path, &keep);
}

}  // namespace cbps
