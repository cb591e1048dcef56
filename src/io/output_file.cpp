// One output file written whole or not at all (output_file.hpp).
#include "cbps/io/output_file.hpp"

#include <unistd.h>

#include <filesystem>

#include "cbps/base/error.hpp"

namespace cbps {

namespace fs = std::filesystem;

void check_output_file(const std::string& path,
                       const std::string& what,
                       bool may_replace,
                       const std::string& how_to_replace) {
  std::error_code ec;
  if (path.empty() || fs::path(path).filename().empty() || fs::is_directory(path, ec))
    throw InputError(what + ": is a folder, not a file");
  const fs::path parent = fs::absolute(path).parent_path();
  if (!fs::is_directory(parent, ec))
    throw InputError(what + ": the folder " + parent.string() + " does not exist");
  if (!may_replace && fs::exists(path, ec))
    throw InputError(what + ": exists; refusing to overwrite it (" + how_to_replace + ")");
}

std::string temporary_name(const std::string& path) {
  const fs::path file = fs::absolute(path);
  std::string name = ".";  // appended piece by piece: GCC 12 warns (-Wrestrict) on "." + string
  name += file.filename().string();
  name += ".cbps-tmp-";
  name += std::to_string(::getpid());
  return (file.parent_path() / name).string();
}

void write_file_atomically(const std::string& path,
                           const std::string& what,
                           const std::function<void(const std::string& temporary)>& write) {
  const std::string temp = temporary_name(path);
  const std::string folder = fs::path(temp).parent_path().string();
  std::error_code ec;
  try {
    write(temp);
  } catch (const std::exception& e) {
    fs::remove(temp, ec);
    throw InputError(what + ": cannot write in " + folder + ": " + e.what());
  }
  fs::rename(temp, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(temp, ignored);
    throw InputError(what + ": cannot rename the written file to it: " + ec.message());
  }
}

}  // namespace cbps
