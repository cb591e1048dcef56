// --out never loses a user's file (issue "Trust", item 1): the same folder with or without a
// trailing slash or as ".", only files listed in cbps-manifest.json replaced, folders holding
// anything else refused with exit 2 and their files untouched, SIGINT/SIGTERM leave no
// temporary folder behind and exit 130/143.
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

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

}  // namespace

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
