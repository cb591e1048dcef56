// Opening an input file for one of the text readers (Matrix Market, Siconos .dat): a file that
// is missing, a folder, unreadable or not text at all (an HDF5 file such as FCLIB's, any binary
// file) is refused with InputError naming the file and which of these it is, before a reader
// would report "line 1" of bytes it cannot show.
#pragma once

#include <fstream>
#include <string>

namespace cbps {

/// `path` opened for reading from its start, or InputError "<path>: <why>": "no such file or
/// folder", "is a folder, not <expected>", "cannot open: <reason>", "an HDF5 file, not
/// <expected> ...", "a binary file (a NUL byte at offset N), not <expected>". `expected` is
/// what the reader takes, e.g. "a Matrix Market text file".
std::ifstream open_text_file(const std::string& path, const std::string& expected);

}  // namespace cbps
