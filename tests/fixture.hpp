// What several test files share: running the cbps executable (exit code and captured output),
// scratch folders.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace cbps::test {

struct CliResult {
  int code = -1;    ///< exit code, -1 if the process did not exit normally
  std::string out;  ///< stdout
  std::string err;  ///< stderr
};

/// An empty folder under the temporary directory, unique to this process.
inline std::filesystem::path scratch_dir(const std::string& name) {
  const std::filesystem::path p = std::filesystem::temp_directory_path() /
                                  ("cbps_test_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(p);
  std::filesystem::create_directories(p);
  return p;
}

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void write_file(const std::filesystem::path& p, const std::string& text) {
  std::ofstream(p) << text;
}

/// Runs `cbps ARGS` (the executable under test, CBPS_EXECUTABLE) with stdout and stderr captured,
/// from the folder `cwd` when one is given.
inline CliResult run_cli(const std::string& args, const std::filesystem::path& cwd = {}) {
  static const std::filesystem::path dir = scratch_dir("io");
  const std::filesystem::path out = dir / "stdout";
  const std::filesystem::path err = dir / "stderr";
  const std::string cd = cwd.empty() ? std::string() : "cd '" + cwd.string() + "' && ";
  const std::string cmd =
      cd + std::string(CBPS_EXECUTABLE) + " " + args + " >" + out.string() + " 2>" + err.string();
  const int status = std::system(cmd.c_str());
  CliResult r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

}  // namespace cbps::test
