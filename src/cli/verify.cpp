// cbps verify [--json]: the derivation checks, one line per paper equation.
#include "cbps/studies/verify.hpp"

#include <cstdio>
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
      std::printf(
          "%s", *json ? (checks_json(checks).dump(2) + "\n").c_str() : checks_text(checks).c_str());
      return all_pass(checks) ? 0 : 1;
    };
  });
}

}  // namespace cbps::cli
