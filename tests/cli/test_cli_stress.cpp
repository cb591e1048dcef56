// `cbps stress`: redundant rows, their nullity, cfm's effect, and the refused case patterns.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <string>

#include "fixture.hpp"

using cbps::test::run_cli;

TEST_CASE("cbps stress: redundant rows, their nullity, and cfm's effect", "[stress][cli]") {
  const auto r = run_cli("stress --case '^row-twice' --json --quiet");
  REQUIRE(r.code == 0);
  const auto report = nlohmann::json::parse(r.out);
  REQUIRE(report["results"].size() == 4);  // row-twice, row-twice+cfm × pgs, direct
  for (const auto& result : report["results"]) {
    INFO(result.dump());
    CHECK(result["stable"] == true);  // v2 is unique though lambda is not
    if (result["case"] == "row-twice") {
      CHECK(result["condition"]["nullity"] == 1);
    } else {
      CHECK(result["condition"]["nullity"] == 0);
      CHECK(result["regularization"]["cfm"] == 1e-6);
    }
  }
  CHECK(run_cli("stress --case no-such-case").code == 2);
  CHECK(run_cli("stress --case '('").code == 2);
  const auto list = run_cli("stress --list");
  CHECK(list.code == 0);
  CHECK(list.out.find("stable means") != std::string::npos);
}
