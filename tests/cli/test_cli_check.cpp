// `cbps run --check`: every step of every contact scene solved again by the direct path (6.2).
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string>

#include "fixture.hpp"

using namespace cbps;
using test::kG;

namespace {

/// The number after `"key": ` in a JSON text (the first occurrence); NaN if there is none.
double json_number(const std::string& json, const std::string& key) {
  const std::string pattern = "\"" + key + "\": ";
  const std::size_t at = json.find(pattern);
  if (at == std::string::npos) return std::nan("");
  return std::strtod(json.c_str() + at + pattern.size(), nullptr);
}

struct CheckedRun {
  std::string args;
  double weight;             ///< the scene's total weight m g, N: the force scale of its lambdas
  bool coulomb_box = false;  ///< friction=coulomb: bounds ±mu lambda_n (5.4)
};

void check_cross_check(const CheckedRun& c, long steps) {
  CAPTURE(c.args);
  const test::CliResult r =
      test::run_cli("run " + c.args + " --check --json --quiet --steps " + std::to_string(steps));
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(json_number(r.out, "steps_checked") == double(steps));
  // Every step's direct answer judged as `cbps lcp` judges a solution: the unit-free residual
  // (system/unit_free.hpp) ≤ 1e-9, with Coulomb's bounds ±mu lambda_n taken at the answer itself.
  // Under the paper's box every step passes. Under Coulomb's box the direct path iterates the
  // bounds to a fixed point and on the card house and the sliding box it does not always reach
  // one in its 100 rounds (card house: 43 of 60 steps, bounds still moving by up to 1.1 N):
  // there every unverified step must be one it reported as stopped short, never one it called
  // solved. (`direct_stopped_short` also counts steps short of its own stricter rule.)
  const double unverified = json_number(r.out, "direct_unverified");
  if (c.coulomb_box)
    CHECK(unverified <= json_number(r.out, "direct_stopped_short"));
  else
    CHECK(unverified == 0.0);
  const double residual = json_number(r.out, "max_direct_residual");
  CAPTURE(residual);
  CHECK(residual <= 1e-9 * c.weight);
  CHECK(r.out.find("\"collision (4)\"") != std::string::npos);
  // Each checked step's direct solve took one route; the check's own time lies inside the run's.
  const nlohmann::json summary = nlohmann::json::parse(r.out);
  const nlohmann::json& cross = summary.at("cross_check");
  long routed = 0;
  for (const auto& [route, count] : cross.at("direct_routes").items()) {
    CAPTURE(route);
    CHECK(count.get<long>() > 0);
    routed += count.get<long>();
  }
  CHECK(routed == steps);
  CHECK(cross.at("direct_time_s").get<double>() > 0.0);
  CHECK(cross.at("direct_time_s").get<double>() <= summary.at("wall_time_s").get<double>());
  CHECK(cross.at("direct_pivots").get<long>() >= 0);
}

}  // namespace

TEST_CASE("contact scenes pass the --check cross-check against the direct path (6.2, 4)",
          "[contact][cli][eq6.2][eq4]") {
  // Every contact scene, run by PGS, block PGS or the direct path itself, each step solved
  // again by the direct path started from the run's lambda (from lambda = 0 if that stalls).
  const CheckedRun run = GENERATE(values<CheckedRun>({
      {"v-corner", 1.0 * kG},
      {"v-corner --param mu=0.5", 1.0 * kG},
      {"v-corner --param mu=0.5 --param friction=coulomb", 1.0 * kG, true},
      {"v-corner --param mu=0.5 --param friction=coulomb --solver direct", 1.0 * kG, true},
      {"newtons-cradle", 5 * 0.2 * kG},
      {"slide", 1.0 * kG},
      {"slide --param friction=coulomb", 1.0 * kG, true},
      {"slide --solver direct", 1.0 * kG},
      {"slide --param friction=coulomb --solver direct", 1.0 * kG, true},
      {"bounce", 1.0 * kG},  // 240 steps (1 s): the ball lands at about 0.45 s
      {"overlap --push original", 3.0 * kG},
      {"overlap --push improved", 3.0 * kG},
      {"overlap --push improved --solver direct", 3.0 * kG},
      {"overlap --push original --solver direct", 3.0 * kG},
      {"stack", 10.0 * kG},
      {"stack --solver block-pgs", 10.0 * kG},
      {"stack --solver direct", 10.0 * kG},
      {"pyramid --param base=4", 10.0 * kG},
      {"pyramid --param base=4 --solver block-pgs", 10.0 * kG},
      {"pyramid --param base=4 --solver direct", 10.0 * kG},
      {"card-house", 15 * 0.1 * kG, true},  // friction=coulomb by default
  }));
  check_cross_check(run, run.args == "bounce" ? 240 : 60);
}

TEST_CASE("a --check run under --no-timing leaves the check's time out, as every wall time",
          "[cli][check]") {
  // scripts/compare_runs.sh compares summary.json byte for byte under --no-timing: a time left in
  // it made two runs of the same physics differ.
  const test::CliResult r = test::run_cli("run chain --check --no-timing --json --quiet --steps 5");
  REQUIRE(r.code == 0);
  const nlohmann::json summary = nlohmann::json::parse(r.out);
  CHECK_FALSE(summary.contains("wall_time_s"));
  const nlohmann::json& cross = summary.at("cross_check");
  CHECK(cross.at("steps_checked").get<long>() == 5);
  CHECK_FALSE(cross.contains("direct_time_s"));
}
