// A CSV output file with fixed-precision numbers (trajectory.csv, steps.csv; docs/outputs.md).
#pragma once

#include <cstdio>
#include <string>

namespace cbps {

/// A buffered CSV file: the header on construction, then rows of numbers written with %.12g
/// (reals) or %ld (counts), and text fields. close() reports a failed write; a file not closed is
/// closed by the destructor without a check (the output folder it is in is then not committed).
class CsvFile {
 public:
  CsvFile(const std::string& path, const std::string& header);
  ~CsvFile();
  CsvFile(const CsvFile&) = delete;
  CsvFile& operator=(const CsvFile&) = delete;

  void num(double x);
  void integer(long x);
  /// A text field: as it is, or in double quotes (inner quotes doubled, RFC 4180) when it holds
  /// a comma, a quote or a line break.
  void text(const std::string& x);
  void end_row();
  /// Closes the file; std::runtime_error "<path>: write failed" if any write failed.
  void close();

 private:
  std::string path_;
  std::FILE* f_;
  bool first_ = true;
};

}  // namespace cbps
