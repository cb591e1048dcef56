// Matrix Market writer and reader.
#include "cbps/matrix_market.hpp"

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

#include "cbps/error.hpp"

namespace cbps {

namespace {

/// Shortest text that reads back to the same double; inf and -inf spelled out.
std::string number_text(double x) {
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
      out << it.row() + 1 << " " << it.col() + 1 << " " << number_text(it.value()) << "\n";
    }
  }
  finish(out, path);
}

void write_matrix_market(const std::string& path, const VecX& v, const std::string& comment) {
  std::ofstream out = open_for_writing(path);
  out << "%%MatrixMarket matrix array real general\n";
  write_comment(out, comment);
  out << v.size() << " 1\n";
  for (Eigen::Index k = 0; k < v.size(); ++k) out << number_text(v(k)) << "\n";
  finish(out, path);
}

namespace {

/// Reads a Matrix Market file line by line; every error names the file and the line.
class LineReader {
 public:
  explicit LineReader(const std::string& path) : path_(path), in_(path) {
    if (!in_) throw InputError(path + ": line 0: cannot open the file");
  }

  [[noreturn]] void fail(const std::string& why) const {
    throw InputError(path_ + ": line " + std::to_string(line_) + ": " + why);
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
    errno = 0;
    char* end = nullptr;
    const double value = std::strtod(token.c_str(), &end);
    if (end == token.c_str() || *end != '\0')
      fail("expected a number " + what + ", found '" + token + "'");
    if (std::isnan(value)) fail("NaN " + what);
    return value;
  }

  /// The size line's integers (nonnegative; a size of 0 is allowed).
  std::vector<long> sizes(std::size_t count) {
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
      v.push_back(value);
    }
    return v;
  }

 private:
  std::string path_;
  std::ifstream in_;
  int line_ = 0;
};

void check_field(const LineReader& r, const std::string& field) {
  if (field != "real" && field != "integer")
    r.fail("field '" + field + "' is not read (only real or integer)");
}

}  // namespace

SpMat read_matrix_market_sparse(const std::string& path) {
  LineReader r(path);
  const std::vector<std::string> h = r.header();
  if (h[0] != "coordinate") r.fail("expected a coordinate (sparse) matrix, found '" + h[0] + "'");
  check_field(r, h[1]);
  const bool symmetric = h[2] == "symmetric";
  if (!symmetric && h[2] != "general")
    r.fail("symmetry '" + h[2] + "' is not read (only general or symmetric)");
  const std::vector<long> s = r.sizes(3);
  const long rows = s[0], cols = s[1], nnz = s[2];
  if (symmetric && rows != cols) r.fail("a symmetric matrix must be square");
  std::vector<Triplet> entries;
  entries.reserve(static_cast<std::size_t>(symmetric ? 2 * nnz : nnz));
  for (long k = 0; k < nnz; ++k) {
    const std::string what = "entry " + std::to_string(k + 1) + " of " + std::to_string(nnz);
    const std::vector<std::string> t = r.next_line(what);
    if (t.size() != 3)
      r.fail(what + " needs 'row column value', found " + std::to_string(t.size()) + " tokens");
    const long i = r.integer(t[0], "row index", rows) - 1;
    const long j = r.integer(t[1], "column index", cols) - 1;
    const double value = r.number(t[2], "in " + what);
    if (symmetric && j > i) r.fail("a symmetric file holds the lower triangle only (row < column)");
    entries.emplace_back(i, j, value);
    if (symmetric && i != j) entries.emplace_back(j, i, value);
  }
  r.expect_end(nnz);
  SpMat M(rows, cols);
  M.setFromTriplets(entries.begin(), entries.end());
  return M;
}

VecX read_matrix_market_vector(const std::string& path) {
  LineReader r(path);
  const std::vector<std::string> h = r.header();
  if (h[0] != "array") r.fail("expected an array (dense) vector, found '" + h[0] + "'");
  check_field(r, h[1]);
  if (h[2] != "general") r.fail("symmetry '" + h[2] + "' is not read for a vector (only general)");
  const std::vector<long> s = r.sizes(2);
  if (s[1] != 1) r.fail("expected an n x 1 vector, found " + std::to_string(s[1]) + " columns");
  VecX v(s[0]);
  for (long k = 0; k < s[0]; ++k) {
    const std::string what = "entry " + std::to_string(k + 1) + " of " + std::to_string(s[0]);
    const std::vector<std::string> t = r.next_line(what);
    if (t.size() != 1)
      r.fail(what + " needs one number, found " + std::to_string(t.size()) + " tokens");
    v(k) = r.number(t[0], "in " + what);
  }
  r.expect_end(s[0]);
  return v;
}

}  // namespace cbps
