// cbps verify [--json]: the derivation checks, one line per paper equation.
#include "cbps/studies/verify.hpp"

#include <cstdio>
#include <iostream>
#include <memory>

#include "common.hpp"

namespace cbps::cli {

void register_verify(CLI::App& app, Action& run) {
  auto* cmd = app.add_subcommand("verify", "numerical checks of the paper's derivations");
  auto json = std::make_shared<bool>(false);
  add_json_flag(cmd, *json, "the checks");
  cmd->callback([&run, json] {
    run = [json] {
      const std::vector<Check> checks = run_derivation_checks();
      bool all = true;
      nlohmann::json out = nlohmann::json::array();
      if (!*json)
        std::printf("%-14s %-10s %-10s %-5s %s\n", "equation", "error", "tolerance", "", "check");
      for (const Check& c : checks) {
        all = all && c.pass();
        if (*json) {
          out.push_back({{"equation", c.equation},
                         {"what", c.what},
                         {"error", c.error},
                         {"tolerance", c.tolerance},
                         {"pass", c.pass()}});
        } else {
          std::printf("%-14s %-10.3g %-10.3g %-5s %s\n",
                      c.equation.c_str(),
                      c.error,
                      c.tolerance,
                      c.pass() ? "pass" : "FAIL",
                      c.what.c_str());
        }
      }
      if (*json) std::cout << out.dump(2) << "\n";
      return all ? 0 : 1;
    };
  });
}

}  // namespace cbps::cli
