// Opening a text reader's input (input_file.hpp).
#include "cbps/io/input_file.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "cbps/base/error.hpp"

namespace cbps {

namespace fs = std::filesystem;

std::ifstream open_text_file(const std::string& path, const std::string& expected) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) throw InputError(path + ": no such file or folder");
  if (fs::is_directory(status)) throw InputError(path + ": is a folder, not " + expected);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open: " + std::strerror(errno));
  // The first 4 KiB tell text from binary: HDF5's signature, or a NUL byte, which no text
  // reader here accepts.
  char head[4096];
  in.read(head, sizeof head);
  const std::streamsize n = in.gcount();
  static constexpr char kHdf5[] = "\x89HDF\r\n\x1a\n";
  if (n >= 8 && std::equal(head, head + 8, kHdf5))
    throw InputError(path + ": an HDF5 file, not " + expected +
                     " (an FCLIB problem file is a problem of its own: `cbps lcp FILE` reads it "
                     "whole, docs/cones.md)");
  const char* nul = std::find(head, head + n, '\0');
  if (nul != head + n)
    throw InputError(path + ": a binary file (a NUL byte at offset " + std::to_string(nul - head) +
                     "), not " + expected);
  in.clear();
  in.seekg(0);
  return in;
}

}  // namespace cbps
