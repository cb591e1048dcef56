// cbps scenes NAME --export FILE: a built-in scene as an editable JSON scene file.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "fixture.hpp"

namespace fs = std::filesystem;

using namespace cbps::test;

namespace {

/// Every number in two JSON documents agrees to round-off, and every other value exactly;
/// `path` names the place for the failure message.
void check_same_numbers(const nlohmann::json& a, const nlohmann::json& b, const std::string& path) {
  CAPTURE(path);
  if (a.is_number() && b.is_number()) {
    const double x = a.get<double>(), y = b.get<double>();
    CHECK(std::abs(x - y) <= 1e-12 * std::max({1.0, std::abs(x), std::abs(y)}));
    return;
  }
  REQUIRE(a.type() == b.type());
  if (a.is_object()) {
    REQUIRE(a.size() == b.size());
    for (auto it = a.begin(); it != a.end(); ++it) {
      REQUIRE(b.contains(it.key()));
      check_same_numbers(it.value(), b[it.key()], path + "." + it.key());
    }
  } else if (a.is_array()) {
    REQUIRE(a.size() == b.size());
    for (std::size_t k = 0; k < a.size(); ++k)
      check_same_numbers(a[k], b[k], path + "[" + std::to_string(k) + "]");
  } else {
    CHECK(a == b);
  }
}

}  // namespace

TEST_CASE("cbps scenes --export writes a scene file that runs as the built-in scene does",
          "[cli][scenes]") {
  const fs::path dir = scratch_dir("scenes_export");
  const fs::path file = dir / "stack3.json";
  const CliResult made = run_cli("scenes stack --param n=3 --export " + file.string());
  INFO(made.out << made.err);
  REQUIRE(made.code == 0);
  REQUIRE(fs::is_regular_file(file));
  // Nothing left beside it: the temporary file was renamed.
  std::size_t entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++entries;
  CHECK(entries == 1);
  // An editable scene file: plain JSON with the scene's bodies (ground and three boxes).
  const auto scene = nlohmann::json::parse(slurp(file));
  CHECK(scene["bodies"].size() == 4);

  const CliResult from_file = run_cli("run " + file.string() + " --steps 50 --no-timing --json");
  const CliResult builtin = run_cli("run stack --param n=3 --steps 50 --no-timing --json");
  INFO(from_file.err << builtin.err);
  REQUIRE(from_file.code == 0);
  REQUIRE(builtin.code == 0);
  const auto a = nlohmann::json::parse(from_file.out);
  const auto b = nlohmann::json::parse(builtin.out);
  CHECK(a["steps"] == 50);
  CHECK(a["energy_final"].is_number());
  // The whole summary: energy, constraint error, penetration, iterations, residual, stages.
  check_same_numbers(a, b, "summary");

  // The trajectories agree too (every body, every recorded step).
  const fs::path ta = dir / "ta", tb = dir / "tb";
  REQUIRE(run_cli("run " + file.string() + " --steps 50 --no-timing --quiet --out " + ta.string())
              .code == 0);
  REQUIRE(
      run_cli("run stack --param n=3 --steps 50 --no-timing --quiet --out " + tb.string()).code ==
      0);
  CHECK(slurp(ta / "trajectory.csv") == slurp(tb / "trajectory.csv"));
  fs::remove_all(dir);
}

TEST_CASE("cbps scenes --export refuses to overwrite a file unless --force", "[cli][scenes]") {
  const fs::path dir = scratch_dir("scenes_force");
  const fs::path file = dir / "mine.json";
  write_file(file, "my own notes\n");
  const CliResult refused = run_cli("scenes chain --export " + file.string());
  CHECK(refused.code == 2);
  CHECK(refused.err.find("cbps: --export " + file.string() + ": exists") != std::string::npos);
  CHECK(slurp(file) == "my own notes\n");  // untouched

  const CliResult forced =
      run_cli("scenes chain --param n=4 --export " + file.string() + " --force");
  INFO(forced.err);
  CHECK(forced.code == 0);
  const auto scene = nlohmann::json::parse(slurp(file));
  CHECK(scene["bodies"].size() == 4);
  CHECK(scene["constraints"].size() == 4);  // one joint to the world, three between links

  // Bad input: exit 2, nothing written.
  const fs::path other = dir / "other.json";
  const CliResult bad_param = run_cli("scenes chain --param nn=4 --export " + other.string());
  CHECK(bad_param.code == 2);
  CHECK(bad_param.err.find("nn") != std::string::npos);
  const CliResult bad_name = run_cli("scenes no-such-scene --export " + other.string());
  CHECK(bad_name.code == 2);
  CHECK(run_cli("scenes --export " + other.string()).code == 2);
  CHECK_FALSE(fs::exists(other));
  const CliResult folder = run_cli("scenes chain --export " + dir.string() + " --force");
  CHECK(folder.code == 2);
  CHECK(folder.err.find("is a folder") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("cbps scenes --help documents --export and --force", "[cli][scenes]") {
  const CliResult r = run_cli("scenes --help");
  CHECK(r.code == 0);
  CHECK(r.out.find("--export") != std::string::npos);
  CHECK(r.out.find("--force") != std::string::npos);
}
