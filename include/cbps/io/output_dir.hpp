// Output that never loses a user's data (docs/cli-contract.md): an output folder written whole
// or not at all with a manifest of the files cbps wrote, single files renamed into place, and
// the cleanup of unfinished output on SIGINT and SIGTERM, whichever thread receives them.
#pragma once

#include <string>
#include <vector>

namespace cbps {

/// The file in every output folder that lists the files cbps wrote there (kManifestFormat).
inline constexpr const char* kManifestName = "cbps-manifest.json";
inline constexpr const char* kManifestFormat = "cbps-output/1";

/// An output folder (--out) that never loses a user's file. The files are written into a hidden
/// temporary folder inside it (.cbps-tmp-PID) and moved into place by commit(), so nothing
/// changes unless the command succeeds; without commit() the temporary folder is removed, and
/// so is the output folder if this made it and it is still empty. cbps-manifest.json lists the
/// files cbps wrote: commit() replaces and removes only files listed there (and its own new
/// ones). A folder holding anything else is refused up front (InputError naming those files),
/// so nothing is ever deleted that cbps did not write. "DIR", "DIR/" and "DIR/." are the same.
/// SIGINT and SIGTERM remove every temporary folder (install_interrupt_cleanup); a later OutputDir
/// in the same folder removes those a process left that no longer runs (killed by SIGKILL).
class OutputDir {
 public:
  explicit OutputDir(const std::string& final_path);
  ~OutputDir();
  OutputDir(const OutputDir&) = delete;
  OutputDir& operator=(const OutputDir&) = delete;
  /// Where to write the output file `name` (inside the temporary folder until commit()).
  std::string file(const std::string& name) const;
  void commit();

 private:
  std::string option_;  ///< as given, for messages
  std::string final_;   ///< absolute, normalised, no trailing separator
  std::string temp_;
  bool created_final_ = false;
  bool committed_ = false;
};

/// The files a cbps output folder's manifest lists (relative paths), or InputError if it is not
/// a cbps manifest; empty when the folder has none.
std::vector<std::string> read_manifest(const std::string& folder);

/// InputError when `out` (given as `option`) exists and is `input` itself (an output folder must
/// not be the problem it was read from); nothing when either is empty.
void check_out_is_not_input(const std::string& out,
                            const std::string& input,
                            const std::string& option);

/// Records the command line for the manifests (main calls this first).
void set_command_line(int argc, char** argv);

/// Handles SIGINT and SIGTERM in the whole process, whichever thread the kernel gives them to
/// (a threaded BLAS starts threads before main): the handler only writes the signal to a pipe,
/// and a thread of its own removes every OutputDir's temporary folder (and output folders made
/// for them), says so on stderr and exits with 128 + the signal (130, 143). A signal the parent
/// ignores stays ignored. main calls this before anything else.
void install_interrupt_cleanup();

/// `code`, or never returns once a signal arrived: the cleanup thread then ends the process
/// with the signal's exit code (main returns through this, so that a command failing because
/// its output was removed under it does not exit 1 first).
int wait_if_interrupted(int code);

/// Writes text to a file, throwing on failure.
void write_text(const std::string& path, const std::string& text);

/// Writes one output file whole or not at all (cbps/io/output_file.hpp: a temporary file
/// beside it, renamed into place), its temporary file removed on Ctrl-C as --out's folders are.
/// Check it first with check_output_file.
void write_output_file(const std::string& path, const std::string& what, const std::string& text);

}  // namespace cbps
