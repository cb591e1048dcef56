// --out never loses a user's file (issue "Trust", item 1): the same folder with or without a
// trailing slash or as ".", only files listed in cbps-manifest.json replaced, folders holding
// anything else refused with exit 2 and their files untouched, SIGINT/SIGTERM leave no
// temporary folder behind and exit 130/143.
#include <fcntl.h>
#include <signal.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cbps/solvers/peers/peers.hpp"
#include "fixture.hpp"

namespace fs = std::filesystem;
using namespace cbps::test;

namespace {

/// Names in `dir` that start with ".cbps-" (cbps's temporary files and folders).
std::vector<std::string> leftovers(const fs::path& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(".cbps-", 0) == 0) names.push_back(name);
  }
  return names;
}

std::vector<std::string> manifest_files(const fs::path& dir) {
  const auto j = nlohmann::json::parse(slurp(dir / "cbps-manifest.json"));
  REQUIRE(j.at("format") == "cbps-output/1");
  return j.at("files").get<std::vector<std::string>>();
}

/// Starts `cbps ARGS` (split on spaces) as a child process; returns its pid.
pid_t spawn(const std::vector<std::string>& args) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    // As a shell with job control starts it: SIGINT and SIGTERM at their default action and
    // unblocked, whatever this test process inherited (a plain `cmd &` in a script starts it
    // with SIGINT ignored, and cbps keeps an ignored signal ignored).
    ::signal(SIGINT, SIG_DFL);
    ::signal(SIGTERM, SIG_DFL);
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    const int null = ::open("/dev/null", O_WRONLY);  // its messages are not the test's
    ::dup2(null, 1);
    ::dup2(null, 2);
    std::vector<char*> argv;
    std::string exe = CBPS_EXECUTABLE;
    argv.push_back(exe.data());
    std::vector<std::string> copy = args;
    for (std::string& a : copy) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(CBPS_EXECUTABLE, argv.data());
    ::_exit(127);
  }
  return pid;
}

/// Waits until `dir` holds a .cbps-tmp-* folder (the run has started writing), up to 20 s.
bool wait_for_temp(const fs::path& dir) {
  for (int k = 0; k < 2000; ++k) {
    if (!leftovers(dir).empty()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

/// The thread ids of process `pid` (/proc/PID/task), the main thread's (= pid) first.
std::vector<pid_t> threads_of(pid_t pid) {
  std::vector<pid_t> tids{pid};
  std::error_code ec;
  for (const auto& e : fs::directory_iterator("/proc/" + std::to_string(pid) + "/task", ec)) {
    const pid_t tid = static_cast<pid_t>(std::stol(e.path().filename().string()));
    if (tid != pid) tids.push_back(tid);
  }
  return tids;
}

/// waitpid with a limit: the status, or nothing after `seconds` (the child is then killed).
std::optional<int> wait_at_most(pid_t pid, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  int status = 0;
  while (std::chrono::steady_clock::now() < end) {
    if (::waitpid(pid, &status, WNOHANG) == pid) return status;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ::kill(pid, SIGKILL);
  ::waitpid(pid, &status, 0);
  return std::nullopt;
}

/// The processes whose parent is `pid` (/proc/*/stat's fourth field).
std::vector<pid_t> children_of(pid_t pid) {
  std::vector<pid_t> found;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator("/proc", ec)) {
    const std::string name = e.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream in(e.path() / "stat");
    std::string line;
    if (!std::getline(in, line)) continue;
    const std::size_t close = line.rfind(')');  // the command name may hold spaces
    if (close == std::string::npos) continue;
    std::istringstream rest(line.substr(close + 1));
    char state = 0;
    long parent = 0;
    rest >> state >> parent;
    if (parent == pid && state != 'Z') found.push_back(static_cast<pid_t>(std::stol(name)));
  }
  return found;
}

/// True once process `pid` is gone (or a zombie) within `seconds`.
bool gone_within(pid_t pid, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  do {
    std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
    std::string line;
    if (!std::getline(in, line)) return true;
    const std::size_t close = line.rfind(')');
    if (close != std::string::npos && close + 2 < line.size() && line[close + 2] == 'Z')
      return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  } while (std::chrono::steady_clock::now() < end);
  return false;
}

}  // namespace

TEST_CASE("a Siconos peer's child process ends with cbps: SIGINT, SIGTERM and --time-limit",
          "[cli][peers][signal]") {
  // Issue 50, items 4 and 5: Siconos runs in a forked child (peers/siconos.cpp); Ctrl-C ended
  // cbps and left the child running for 30 s more, and nothing bounded its time. siconos:lemke
  // on this base-8 pyramid's 768 rows takes about 30 s (and fails).
  if (!cbps::peer_available(cbps::Method::SiconosLemke)) {
    WARN("this build has no Siconos numerics: not tested");
    return;
  }
  const fs::path dir = scratch_dir("peer_child");
  const fs::path problem = dir / "pyramid";
  const CliResult made =
      run_cli("matrices pyramid --param base=8 --step 30 --quiet --out " + problem.string());
  INFO(made.err);
  REQUIRE(made.code == 0);
  for (const int signal : {SIGINT, SIGTERM}) {
    CAPTURE(signal);
    const pid_t pid = spawn(
        {"lcp", problem.string(), "--solver", "siconos:lemke", "--out", (dir / "out").string()});
    REQUIRE(pid > 0);
    std::vector<pid_t> children;
    for (int k = 0; k < 500 && children.empty(); ++k) {  // the fork comes after the reading
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      children = children_of(pid);
    }
    REQUIRE(children.size() == 1);
    ::kill(pid, signal);
    const std::optional<int> status = wait_at_most(pid, 20.0);
    REQUIRE(status);
    CHECK(WIFEXITED(*status));
    CHECK(WEXITSTATUS(*status) == 128 + signal);
    CHECK(gone_within(children[0], 5.0));  // before the fix: 30 s more
    if (!gone_within(children[0], 0.0)) ::kill(children[0], SIGKILL);
    CHECK_FALSE(fs::exists(dir / "out"));
  }
  // --time-limit 1: the child is killed at the limit, the answer is not solved, exit 1, and
  // the JSON says why.
  const auto start = std::chrono::steady_clock::now();
  const CliResult limited =
      run_cli("lcp " + problem.string() + " --solver siconos:lemke --time-limit 1 --json");
  const double took =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  INFO(limited.out << limited.err);
  CHECK(limited.code == 1);
  CHECK(took < 10.0);
  const auto j = nlohmann::json::parse(limited.out);
  CHECK(j["status"] == "time limit");
  CHECK(j["peer"]["status"].get<std::string>().rfind("time limit", 0) == 0);
  // Issue 50, item 12: a solve that shows nothing until it ends prints a line every 2 s on
  // stderr (the peer's child exposes no iterates), and none under --quiet.
  const CliResult beating =
      run_cli("lcp " + problem.string() + " --solver siconos:lemke --time-limit 2.5 --json");
  INFO(beating.err);
  CHECK(beating.code == 1);
  CHECK(beating.err.find("cbps lcp: siconos:lemke on " + problem.string() +
                         ": running, 2.0 s elapsed (time limit 2.5 s)") != std::string::npos);
  const CliResult silent = run_cli("lcp " + problem.string() +
                                   " --solver siconos:lemke --time-limit 2.5 --json --quiet");
  CHECK(silent.code == 1);
  CHECK(silent.err.find("running") == std::string::npos);
}

TEST_CASE("an output folder given as DIR/, DIR or DIR/. is one folder, rewritten run after run",
          "[cli][out]") {
  const fs::path dir = scratch_dir("out_same");
  for (const std::string out : {"ts/", "ts", "ts/."}) {
    CAPTURE(out);
    const CliResult r = run_cli("run chain --steps 2 --quiet --out " + out, dir);
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK(fs::is_regular_file(dir / "ts" / "summary.json"));
    CHECK(leftovers(dir / "ts").empty());
    CHECK(leftovers(dir).empty());
  }
  CHECK(manifest_files(dir / "ts") ==
        std::vector<std::string>{"bodies.json", "steps.csv", "summary.json", "trajectory.csv"});
  // "." inside the output folder is that folder: rewritten, nothing else touched.
  const CliResult dot = run_cli("run chain --steps 3 --quiet --no-timing --out .", dir / "ts");
  INFO(dot.err);
  REQUIRE(dot.code == 0);
  CHECK(nlohmann::json::parse(slurp(dir / "ts" / "summary.json"))["steps"] == 3);
  CHECK(fs::is_directory(dir / "ts"));
  // Another command's output replaces the files cbps wrote before, and only those.
  const CliResult m = run_cli("matrices chain --param n=2 --out " + (dir / "ts").string());
  REQUIRE(m.code == 0);
  CHECK_FALSE(fs::exists(dir / "ts" / "trajectory.csv"));
  CHECK(fs::exists(dir / "ts" / "A.mtx"));
  CHECK(manifest_files(dir / "ts").size() == 12);
  fs::remove_all(dir);
}

TEST_CASE("an output folder with files cbps did not write is refused, nothing deleted",
          "[cli][out]") {
  const fs::path dir = scratch_dir("out_foreign");
  const fs::path p = dir / "p";
  fs::create_directories(p / "src");
  write_file(p / "src" / "main.cpp", "int main() {}\n");
  write_file(p / "summary.json", "{}");  // looks like an output, is not listed by cbps
  for (const std::string cmd : {"run chain --steps 2 --quiet",
                                "matrices chain --param n=2",
                                "converge chain --param n=2 --step 5 --solvers pgs --no-plot"}) {
    CAPTURE(cmd);
    const CliResult r = run_cli(cmd + " --out " + p.string());
    INFO(r.err);
    CHECK(r.code == 2);
    CHECK(r.err.find("src/main.cpp") != std::string::npos);
    CHECK(r.err.find("summary.json") != std::string::npos);
    CHECK(slurp(p / "src" / "main.cpp") == "int main() {}\n");
    CHECK(slurp(p / "summary.json") == "{}");
    CHECK_FALSE(fs::exists(p / "cbps-manifest.json"));
    CHECK(leftovers(p).empty());
  }
  // One foreign file beside a real cbps output: refused, the output kept as it was.
  const fs::path out = dir / "out";
  REQUIRE(run_cli("run chain --steps 2 --quiet --out " + out.string()).code == 0);
  const std::string before = slurp(out / "summary.json");
  write_file(out / "notes.txt", "mine\n");
  const CliResult r = run_cli("run chain --steps 5 --quiet --out " + out.string());
  CHECK(r.code == 2);
  CHECK(r.err.find("notes.txt") != std::string::npos);
  CHECK(slurp(out / "summary.json") == before);
  CHECK(slurp(out / "notes.txt") == "mine\n");
  // A manifest that is not cbps's is not trusted.
  fs::remove(out / "notes.txt");
  write_file(out / "cbps-manifest.json", R"({"files": ["summary.json"]})");
  CHECK(run_cli("run chain --steps 2 --quiet --out " + out.string()).code == 2);
  CHECK(slurp(out / "summary.json") == before);
  fs::remove_all(dir);
}

TEST_CASE("files a cbps script listed in the manifest are cbps's: replaced on the next run",
          "[cli][out]") {
  const fs::path dir = scratch_dir("out_listed");
  const fs::path out = dir / "run";
  REQUIRE(run_cli("run chain --steps 2 --quiet --out " + out.string()).code == 0);
  // What validation/pendulum_wave_report.py does: writes report.md, adds it to the manifest.
  write_file(out / "report.md", "# report\n");
  auto manifest = nlohmann::json::parse(slurp(out / "cbps-manifest.json"));
  manifest["files"].push_back("report.md");
  write_file(out / "cbps-manifest.json", manifest.dump());
  const CliResult r = run_cli("run chain --steps 3 --quiet --out " + out.string());
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK_FALSE(fs::exists(out / "report.md"));  // it described the run that was replaced
  CHECK(manifest_files(out) ==
        std::vector<std::string>{"bodies.json", "steps.csv", "summary.json", "trajectory.csv"});
  fs::remove_all(dir);
}

TEST_CASE("SIGINT and SIGTERM remove the unfinished output and exit 130 and 143",
          "[cli][out][signal]") {
  const fs::path dir = scratch_dir("out_signal");
  struct Case {
    int signal;
    int code;
    bool existed;  ///< the output folder was there before the run
  };
  for (const Case c : {Case{SIGINT, 130, false}, Case{SIGTERM, 143, true}}) {
    CAPTURE(c.signal);
    const fs::path out = dir / (c.existed ? "kept" : "new");
    if (c.existed) fs::create_directories(out);
    // The pendulum wave's 14,400 steps take about a second: long enough to interrupt.
    const pid_t pid = spawn({"run", "pendulum-wave", "--quiet", "--out", out.string()});
    REQUIRE(pid > 0);
    REQUIRE(wait_for_temp(out));
    ::kill(pid, c.signal);
    int status = 0;
    REQUIRE(::waitpid(pid, &status, 0) == pid);
    REQUIRE(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == c.code);
    if (c.existed) {
      CHECK(fs::is_directory(out));
      CHECK(fs::is_empty(out));
    } else {
      CHECK_FALSE(fs::exists(out));
    }
    CHECK(leftovers(dir).empty());
  }
  fs::remove_all(dir);
}

TEST_CASE("a signal cleans up whichever thread of the process receives it", "[cli][out][signal]") {
  // The kernel gives a process-directed signal to any thread that does not block it; a threaded
  // BLAS (OpenBLAS, which PETSc's packages bring) starts workers before main, which therefore
  // cannot block it for them. tgkill directs the signal at one thread: the main thread, then
  // every other thread of the process in turn (the cleanup's own thread among them; an
  // OpenBLAS worker where one runs). Each run must end with 128 + the signal, its temporary
  // folder removed, within 10 s.
  const fs::path dir = scratch_dir("out_thread_signal");
  std::size_t thread_index = 0;
  for (std::size_t round = 0; round < 4; ++round) {
    const int signal = round % 2 == 0 ? SIGINT : SIGTERM;
    CAPTURE(round, signal);
    const fs::path out = dir / ("run" + std::to_string(round));
    const pid_t pid = spawn({"run", "pendulum-wave", "--quiet", "--out", out.string()});
    REQUIRE(pid > 0);
    REQUIRE(wait_for_temp(out));
    const std::vector<pid_t> tids = threads_of(pid);
    REQUIRE(tids.size() >= 2);  // main and the cleanup thread at least
    const pid_t target = tids[thread_index % tids.size()];
    CAPTURE(tids.size(), target);
    thread_index = round == 0 ? 1 : thread_index + 1;  // main first, then the others in turn
    REQUIRE(::syscall(SYS_tgkill, pid, target, signal) == 0);
    const std::optional<int> status = wait_at_most(pid, 10.0);
    REQUIRE(status.has_value());  // not hung with the signal pending on a thread that blocks it
    REQUIRE(WIFEXITED(*status));  // not killed by the signal's default action
    CHECK(WEXITSTATUS(*status) == 128 + signal);
    CHECK_FALSE(fs::exists(out));
    CHECK(leftovers(dir).empty());
  }
  fs::remove_all(dir);
}

TEST_CASE("a later --out removes the unfinished files of a cbps process that no longer runs",
          "[cli][out][signal]") {
  const fs::path dir = scratch_dir("out_stale");
  const fs::path out = dir / "out";
  // A process id that ran and ended (a child, reaped), and one that runs (this test's).
  const pid_t ended = ::fork();
  if (ended == 0) ::_exit(0);
  REQUIRE(ended > 0);
  int status = 0;
  REQUIRE(::waitpid(ended, &status, 0) == ended);
  const std::string dead = std::to_string(ended);
  const std::string alive = std::to_string(::getpid());
  fs::create_directories(out / (".cbps-tmp-" + dead) / "sub");
  { std::ofstream(out / (".cbps-tmp-" + dead) / "sub" / "trajectory.csv") << "t,x\n0,1\n"; }
  { std::ofstream(out / (".cbps-manifest.tmp-" + dead)) << "{"; }
  fs::create_directories(out / (".cbps-tmp-" + alive));
  { std::ofstream(out / ".cbps-tmp-notapid") << "x"; }
  const CliResult r = run_cli("run chain --steps 2 --quiet --out " + out.string());
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK_FALSE(fs::exists(out / (".cbps-tmp-" + dead)));
  CHECK_FALSE(fs::exists(out / (".cbps-manifest.tmp-" + dead)));
  CHECK(r.err.find(".cbps-tmp-" + dead) != std::string::npos);  // said what it removed
  CHECK(fs::is_directory(out / (".cbps-tmp-" + alive)));        // its process may still be writing
  CHECK(fs::exists(out / ".cbps-tmp-notapid"));                 // not a name cbps gives
  CHECK(fs::is_regular_file(out / "summary.json"));
  fs::remove_all(dir);
}
