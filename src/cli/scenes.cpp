// cbps scenes [--json]: the built-in scenes, their parameters, defaults and units.
#include "cbps/scenes.hpp"

#include <iostream>

#include "common.hpp"

namespace cbps::cli {

void register_scenes(CLI::App& app, Action& run) {
  auto* cmd = app.add_subcommand("scenes", "list the built-in scenes and their parameters");
  auto json = std::make_shared<bool>(false);
  cmd->add_flag("--json", *json, "print as JSON");
  cmd->callback([&run, json] {
    run = [json] {
      if (*json) {
        nlohmann::json out = nlohmann::json::array();
        for (const BuiltinScene& s : builtin_scenes()) {
          nlohmann::json params = nlohmann::json::array();
          for (const SceneParameter& p : s.parameters) {
            params.push_back({{"name", p.name},
                              {"default", p.default_value},
                              {"unit", p.unit},
                              {"description", p.description}});
          }
          out.push_back({{"name", s.name}, {"description", s.description}, {"parameters", params}});
        }
        std::cout << out.dump(2) << "\n";
        return 0;
      }
      for (const BuiltinScene& s : builtin_scenes()) {
        std::cout << s.name << ": " << s.description << "\n";
        for (const SceneParameter& p : s.parameters) {
          std::string unit = p.unit == "-" ? "" : p.unit;
          std::cout << "  " << p.name << " = " << p.default_value << (unit.empty() ? "" : " ")
                    << unit << "  (" << p.description << ")\n";
        }
        std::cout << "\n";
      }
      std::cout << "Set parameters with --param NAME=VALUE; a JSON scene file may be given "
                   "instead of a name.\n";
      return 0;
    };
  });
}

}  // namespace cbps::cli
