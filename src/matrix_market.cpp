// Matrix Market writer.
#include "cbps/matrix_market.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>

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

}  // namespace cbps
