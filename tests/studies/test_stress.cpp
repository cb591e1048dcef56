// The stress catalogue: every case says what stable means, and the groups the issue asks for.
#include <catch2/catch.hpp>
#include <set>
#include <string>

#include "cbps/studies/stress.hpp"

using namespace cbps;

TEST_CASE("stress catalogue: every case says what stable means", "[stress]") {
  const auto cases = stress_catalogue();
  std::set<std::string> names;
  for (const StressCase& c : cases) {
    INFO(c.name);
    CHECK(names.insert(c.name).second);
    CHECK_FALSE(c.stable_means.empty());
    CHECK_FALSE(c.solvers.empty());
    CHECK(c.steps > 0);
  }
  // The groups the issue asks for.
  std::set<std::string> groups;
  for (const StressCase& c : cases) groups.insert(c.group);
  for (const char* g : {"mass ratio",
                        "size",
                        "time step",
                        "fast impact",
                        "redundant",
                        "near-degenerate",
                        "far from origin",
                        "extreme inertia"})
    CHECK(groups.count(g) == 1);
}
