// One output file written whole or not at all (the single-file counterpart of `--out DIR`,
// docs/cli-contract.md): the content goes to a hidden temporary file beside FILE,
// ".NAME.cbps-tmp-PID", which is renamed over FILE once it is complete, so FILE is either its old
// self or the new content, never half of it. Used by `cbps scenes --export`, `cbps explain
// --html` and the Python module's writers.
#pragma once

#include <functional>
#include <string>

namespace cbps {

/// Checks, before any work, that FILE can be written: it is not a folder, its folder exists,
/// and it does not exist unless `may_replace`. InputError "<what>: <why>" otherwise; `what`
/// names the file as the user gave it (e.g. "--export scene.json"), and `how_to_replace` ends
/// the message for an existing FILE (e.g. "--force replaces it").
void check_output_file(const std::string& path,
                       const std::string& what,
                       bool may_replace,
                       const std::string& how_to_replace);

/// The temporary name FILE is written under before the rename: ".NAME.cbps-tmp-PID" in FILE's
/// folder (the same file system, so the rename is atomic).
std::string temporary_name(const std::string& path);

/// Calls write(temporary) and renames the temporary file to FILE. On any failure the temporary
/// file is removed, FILE keeps its old content and InputError names `what` and the reason.
void write_file_atomically(const std::string& path,
                           const std::string& what,
                           const std::function<void(const std::string& temporary)>& write);

}  // namespace cbps
