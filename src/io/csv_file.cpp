#include "cbps/io/csv_file.hpp"

#include <cmath>
#include <stdexcept>

namespace cbps {

CsvFile::CsvFile(const std::string& path, const std::string& header)
    : path_(path), f_(std::fopen(path.c_str(), "w")) {
  if (f_ == nullptr) throw std::runtime_error(path + ": cannot open for writing");
  std::fputs(header.c_str(), f_);
  std::fputc('\n', f_);
}

CsvFile::~CsvFile() {
  if (f_ != nullptr) std::fclose(f_);
}

void CsvFile::num(double x) {
  if (std::isnan(x)) {  // "nan", never printf's "-nan" (docs/cli-contract.md)
    std::fputs(first_ ? "nan" : ",nan", f_);
    first_ = false;
    return;
  }
  std::fprintf(f_, first_ ? "%.12g" : ",%.12g", x);
  first_ = false;
}

void CsvFile::integer(long x) {
  std::fprintf(f_, first_ ? "%ld" : ",%ld", x);
  first_ = false;
}

void CsvFile::text(const std::string& x) {
  if (!first_) std::fputc(',', f_);
  first_ = false;
  if (x.find_first_of(",\"\r\n") == std::string::npos) {
    std::fputs(x.c_str(), f_);
    return;
  }
  std::fputc('"', f_);
  for (const char c : x) {
    if (c == '"') std::fputc('"', f_);
    std::fputc(c, f_);
  }
  std::fputc('"', f_);
}

void CsvFile::end_row() {
  std::fputc('\n', f_);
  first_ = true;
}

void CsvFile::close() {
  const bool bad = std::ferror(f_) != 0;
  const bool closed = std::fclose(f_) == 0;
  f_ = nullptr;
  if (bad || !closed) throw std::runtime_error(path_ + ": write failed");
}

}  // namespace cbps
