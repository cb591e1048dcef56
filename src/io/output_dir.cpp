#include "cbps/io/output_dir.hpp"

#include <fcntl.h>
#include <pthread.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "cbps/base/error.hpp"
#include "cbps/io/output_file.hpp"

namespace cbps {

namespace fs = std::filesystem;

namespace {

/// The temporary folders of the live OutputDirs and, for each, the output folder to remove
/// with it when this process made it; guarded by registry_mutex (the signal thread reads it).
std::mutex registry_mutex;
std::map<std::string, std::string>& temp_registry() {
  static std::map<std::string, std::string> registry;
  return registry;
}
std::string command_line = "cbps";

/// cbps's own unfinished files: .cbps-tmp-PID folders and .cbps-manifest.tmp-PID files.
bool is_temp_name(const std::string& name) { return name.rfind(".cbps-", 0) == 0; }

/// Absolute and lexically normal, without a trailing separator: "ts/", "ts/." and "ts" alike.
fs::path normal_folder(const std::string& path) {
  fs::path p = fs::absolute(fs::path(path)).lexically_normal();
  while (!p.has_filename() && p.has_parent_path() && p != p.root_path()) p = p.parent_path();
  return p;
}

/// Every regular file (or link) below `root`, as relative generic paths, sorted; folders only
/// through what they hold. cbps's temporary files and folders (.cbps-*) at the top are skipped.
std::vector<std::string> files_below(const fs::path& root) {
  std::vector<std::string> files;
  std::error_code ec;
  fs::recursive_directory_iterator it(root, ec), end;
  if (ec) throw InputError(root.string() + ": cannot list: " + ec.message());
  for (; it != end; it.increment(ec)) {
    if (ec) throw InputError(root.string() + ": cannot list: " + ec.message());
    const fs::path rel = it->path().lexically_relative(root);
    if (it.depth() == 0 && is_temp_name(rel.string())) {
      it.disable_recursion_pending();
      continue;
    }
    if (it->is_directory(ec) && !it->is_symlink(ec)) continue;
    files.push_back(rel.generic_string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

void write_manifest(const fs::path& folder, const std::vector<std::string>& files) {
  const nlohmann::json manifest = {
      {"format", kManifestFormat},
      {"about",
       "the files cbps wrote in this folder; a later --out here replaces only these and refuses "
       "if the folder holds any other file"},
      {"command", command_line},
      {"files", files}};
  const fs::path temp = folder / (".cbps-manifest.tmp-" + std::to_string(::getpid()));
  write_text(temp.string(), manifest.dump(2) + "\n");
  std::error_code ec;
  fs::rename(temp, folder / kManifestName, ec);
  if (ec) throw std::runtime_error((folder / kManifestName).string() + ": " + ec.message());
}

/// Removes `dir` and its parents up to (not including) `top` while they are empty.
void remove_empty_parents(fs::path dir, const fs::path& top) {
  std::error_code ec;
  while (dir != top && dir.string().size() > top.string().size() && fs::is_empty(dir, ec) && !ec) {
    fs::remove(dir, ec);
    dir = dir.parent_path();
  }
}

/// The process id in a name cbps gives its unfinished files (".cbps-tmp-PID",
/// ".cbps-manifest.tmp-PID"), or 0 for any other name.
pid_t temporary_owner(const std::string& name) {
  for (const char* prefix : {".cbps-tmp-", ".cbps-manifest.tmp-"}) {
    const std::string p = prefix;
    if (name.size() <= p.size() || name.compare(0, p.size(), p) != 0) continue;
    const std::string digits = name.substr(p.size());
    if (digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) return 0;
    return static_cast<pid_t>(std::stol(digits));
  }
  return 0;
}

/// Removes the unfinished files that cbps processes which no longer run left in `folder` (a
/// process killed by SIGKILL, or by a signal before its cleanup existed), saying so on stderr.
/// A name whose process still runs is left alone: it may be another cbps writing there now.
void remove_stale_temporaries(const fs::path& folder) {
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    const std::string name = entry.path().filename().string();
    const pid_t owner = temporary_owner(name);
    if (owner <= 0 || owner == ::getpid()) continue;
    if (::kill(owner, 0) == 0 || errno != ESRCH) continue;  // running, or not ours to ask
    std::error_code removed;
    fs::remove_all(entry.path(), removed);
    if (!removed)
      std::fprintf(stderr,
                   "cbps: removed %s, left unfinished by process %ld, which no longer runs\n",
                   entry.path().c_str(),
                   static_cast<long>(owner));
  }
}

}  // namespace

void set_command_line(int argc, char** argv) {
  command_line.clear();
  for (int k = 0; k < argc; ++k) {
    if (k > 0) command_line += ' ';
    command_line += k == 0 ? fs::path(argv[0]).filename().string() : std::string(argv[k]);
  }
}

void check_out_is_not_input(const std::string& out,
                            const std::string& input,
                            const std::string& option) {
  std::error_code ec;
  if (!out.empty() && !input.empty() && fs::exists(out, ec) && fs::equivalent(out, input, ec))
    throw InputError(option + " " + out + ": is the problem itself; choose another folder");
}

std::vector<std::string> read_manifest(const std::string& folder) {
  const fs::path path = fs::path(folder) / kManifestName;
  std::error_code ec;
  if (!fs::exists(path, ec)) return {};
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  const auto not_ours = [&](const std::string& why) {
    return InputError(path.string() + ": not a cbps manifest (" + why +
                      "); cbps replaces files only in folders it wrote");
  };
  const nlohmann::json j = nlohmann::json::parse(text.str(), nullptr, false);
  if (j.is_discarded() || !j.is_object()) throw not_ours("not a JSON object");
  if (!j.contains("format") || j["format"] != kManifestFormat)
    throw not_ours(std::string("no \"format\": \"") + kManifestFormat + "\"");
  if (!j.contains("files") || !j["files"].is_array()) throw not_ours("no \"files\" list");
  std::vector<std::string> files;
  for (const auto& f : j["files"]) {
    if (!f.is_string()) throw not_ours("a file name that is not a string");
    const fs::path rel = fs::path(f.get<std::string>()).lexically_normal();
    if (rel.empty() || rel.is_absolute() || *rel.begin() == "..")
      throw not_ours("a file outside the folder: " + f.get<std::string>());
    files.push_back(rel.generic_string());
  }
  return files;
}

OutputDir::OutputDir(const std::string& final_path) : option_(final_path) {
  if (final_path.empty()) throw InputError("--out: empty folder name");
  const fs::path final_dir = normal_folder(final_path);
  final_ = final_dir.string();
  std::error_code ec;
  if (fs::exists(final_dir, ec)) {
    if (!fs::is_directory(final_dir, ec))
      throw InputError("--out " + option_ + ": exists and is not a folder");
    std::vector<std::string> ours = read_manifest(final_);
    std::sort(ours.begin(), ours.end());
    std::vector<std::string> foreign;
    for (const std::string& f : files_below(final_dir)) {
      if (f != kManifestName && !std::binary_search(ours.begin(), ours.end(), f))
        foreign.push_back(f);
    }
    if (!foreign.empty()) {
      std::string list;
      for (std::size_t k = 0; k < foreign.size() && k < 5; ++k)
        list += (k ? ", " : "") + foreign[k];
      if (foreign.size() > 5) list += " and " + std::to_string(foreign.size() - 5) + " more";
      throw InputError("--out " + option_ + ": the folder holds " + std::to_string(foreign.size()) +
                       " file(s) cbps did not write (" + list +
                       "); cbps only replaces files listed in its " + kManifestName +
                       ", so choose another folder or move them");
    }
  } else {
    fs::create_directories(final_dir, ec);
    if (ec) throw InputError("--out " + option_ + ": cannot create: " + ec.message());
    created_final_ = true;
  }
  remove_stale_temporaries(final_dir);
  temp_ = (final_dir / (".cbps-tmp-" + std::to_string(::getpid()))).string();
  const std::lock_guard<std::mutex> lock(registry_mutex);
  fs::remove_all(temp_, ec);  // a leftover of an earlier process with this id
  if (!fs::create_directory(temp_, ec)) {
    if (created_final_) fs::remove(final_dir, ec);
    throw InputError("--out " + option_ + ": cannot create a folder in it: " + ec.message());
  }
  temp_registry()[temp_] = created_final_ ? final_ : std::string();
}

OutputDir::~OutputDir() {
  const std::lock_guard<std::mutex> lock(registry_mutex);
  temp_registry().erase(temp_);
  std::error_code ec;
  fs::remove_all(temp_, ec);  // only our own temporary folder; after commit() it is empty
  if (!committed_ && created_final_ && fs::is_empty(final_, ec)) fs::remove(final_, ec);
}

std::string OutputDir::file(const std::string& name) const {
  return (fs::path(temp_) / name).string();
}

void OutputDir::commit() {
  const std::lock_guard<std::mutex> lock(registry_mutex);  // not interrupted half-way
  const fs::path final_dir(final_);
  const fs::path temp_dir(temp_);
  const std::vector<std::string> old_files = read_manifest(final_);
  const std::vector<std::string> new_files = files_below(temp_dir);
  // A file that appeared since the check, under a name this output uses, is not replaced.
  std::error_code ec;
  for (const std::string& f : new_files) {
    if (f != kManifestName && fs::exists(final_dir / f, ec) &&
        std::find(old_files.begin(), old_files.end(), f) == old_files.end())
      throw InputError("--out " + option_ + ": " + f +
                       " appeared there while cbps ran and was not written by cbps; nothing "
                       "replaced");
  }
  // The manifest first lists old and new files, so that an interruption half-way leaves every
  // cbps file listed; then the files move in, old ones not written again go, and the manifest
  // is rewritten with the new files only.
  std::vector<std::string> both = old_files;
  both.insert(both.end(), new_files.begin(), new_files.end());
  std::sort(both.begin(), both.end());
  both.erase(std::unique(both.begin(), both.end()), both.end());
  write_manifest(final_dir, both);
  for (const std::string& f : new_files) {
    const fs::path target = final_dir / f;
    fs::create_directories(target.parent_path(), ec);
    fs::rename(temp_dir / f, target, ec);
    if (ec)
      throw std::runtime_error("--out " + option_ + ": cannot move " + f +
                               " into place: " + ec.message());
  }
  for (const std::string& f : old_files) {
    if (std::find(new_files.begin(), new_files.end(), f) != new_files.end()) continue;
    const fs::path stale = final_dir / f;
    if (fs::is_regular_file(stale, ec) || fs::is_symlink(stale, ec)) fs::remove(stale, ec);
    remove_empty_parents(stale.parent_path(), final_dir);
  }
  write_manifest(final_dir, new_files);
  temp_registry().erase(temp_);
  fs::remove_all(temp_dir, ec);  // empty folders only: every file moved out
  committed_ = true;
}

namespace {

/// The write end of the pipe the signal handler writes the signal's number to, and the read
/// end the cleanup thread waits on (install_interrupt_cleanup); -1 before.
int interrupt_pipe[2] = {-1, -1};
/// Set by the cleanup thread once it runs (its start, which allocates, is over).
std::atomic<bool> cleanup_thread_started{false};
/// The signal that interrupted the command, 0 while none did (set by the handler).
volatile std::sig_atomic_t interrupt_signal = 0;

/// The process-wide handler of SIGINT and SIGTERM. The kernel may run it on any thread that
/// does not block the signal, including threads a library started before main (OpenBLAS's
/// workers), so it does only what a handler may: it records the signal and writes its number to
/// the pipe; the cleanup thread does the rest.
extern "C" void on_interrupt(int signal) {
  const int saved_errno = errno;
  interrupt_signal = signal;
  const unsigned char number = static_cast<unsigned char>(signal);
  [[maybe_unused]] const ssize_t written = ::write(interrupt_pipe[1], &number, 1);
  errno = saved_errno;
}

/// Removes `path` and all below it, again while another thread of this process may still be
/// writing a file into it (the command goes on until the cleanup thread ends the process).
void remove_while_written(const fs::path& path) {
  std::error_code ec;
  for (int attempt = 0; attempt < 100 && fs::exists(path, ec); ++attempt) {
    fs::remove_all(path, ec);
    if (ec) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

/// The cleanup after SIGINT or SIGTERM, on a thread of its own: waits for the handler's byte,
/// removes every unfinished output (never a committed one: commit() holds the lock), says so,
/// and ends the process with 128 + the signal.
void cleanup_on_interrupt() {
  cleanup_thread_started.store(true, std::memory_order_release);
  unsigned char number = 0;
  while (::read(interrupt_pipe[0], &number, 1) != 1) {
    if (errno != EINTR) return;  // the pipe is gone: nothing to wait for
  }
  const int signal = number;
  const std::lock_guard<std::mutex> lock(registry_mutex);
  for (const auto& [temp, made] : temp_registry()) {
    remove_while_written(temp);
    std::error_code ec;
    if (!made.empty() && fs::is_empty(made, ec)) fs::remove(made, ec);
    std::fprintf(stderr, "cbps: interrupted; removed the unfinished output %s\n", temp.c_str());
  }
  std::fprintf(stderr, "cbps: stopped by %s\n", signal == SIGINT ? "SIGINT" : "SIGTERM");
  std::fflush(stderr);
  std::_Exit(128 + signal);
}

}  // namespace

void install_interrupt_cleanup() {
  if (::pipe2(interrupt_pipe, O_CLOEXEC) != 0)
    throw std::runtime_error(std::string("cannot make the interrupt pipe: ") +
                             std::strerror(errno));
  std::thread(cleanup_on_interrupt).detach();
  // A thread's start allocates (its stack, the sanitizers' bookkeeping): a peer's fork() during
  // it would leave the child's allocator locked. Go on once the thread waits in read().
  while (!cleanup_thread_started.load(std::memory_order_acquire)) std::this_thread::yield();
  struct sigaction action {};
  action.sa_handler = on_interrupt;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  for (const int signal : {SIGINT, SIGTERM}) {
    struct sigaction previous {};
    sigaction(signal, nullptr, &previous);
    // A signal the parent set to be ignored stays ignored (as `nohup` and a shell's
    // background jobs expect); every other disposition becomes the cleanup.
    if (previous.sa_handler != SIG_IGN) sigaction(signal, &action, nullptr);
  }
  // Threads started before main (a threaded BLAS's workers) receive the signal as well as
  // this one: the handler above serves every thread. No thread blocks them.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_UNBLOCK, &signals, nullptr);
}

int wait_if_interrupted(int code) {
  // The command failed or ended because the cleanup thread removed its output: that thread
  // ends the process with the signal's code; until it does, this thread waits.
  while (interrupt_signal != 0) std::this_thread::sleep_for(std::chrono::seconds(1));
  return code;
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  out.flush();
  if (!out) throw std::runtime_error(path + ": write failed");
}

void write_output_file(const std::string& path, const std::string& what, const std::string& text) {
  const std::string temp = temporary_name(path);
  {
    const std::lock_guard<std::mutex> lock(registry_mutex);
    temp_registry()[temp] = "";  // Ctrl-C removes it (install_interrupt_cleanup)
  }
  const auto forget = [&temp] {
    const std::lock_guard<std::mutex> lock(registry_mutex);
    temp_registry().erase(temp);
  };
  try {
    write_file_atomically(path, what, [&](const std::string& t) { write_text(t, text); });
  } catch (...) {
    forget();
    throw;
  }
  forget();
}

}  // namespace cbps
