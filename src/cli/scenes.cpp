// cbps scenes [NAME [--param K=V ...] [--export FILE [--force]]] [--json]: the built-in scenes,
// their parameters, defaults and units; with --export one of them as an editable JSON scene file.

#include <iostream>
#include <map>

#include "cbps/base/error.hpp"
#include "cbps/scene/builtin.hpp"
#include "cbps/scene/scene_json.hpp"
#include "common.hpp"

namespace cbps::cli {

namespace {

struct ScenesOptions {
  std::string name;
  std::vector<std::string> params;
  std::string export_file;
  bool force = false;
  bool json = false;
};

nlohmann::json scene_listing_json(const BuiltinScene& s) {
  nlohmann::json params = nlohmann::json::array();
  for (const SceneParameter& p : s.parameters) {
    params.push_back({{"name", p.name},
                      {"default", p.default_value},
                      {"unit", p.unit},
                      {"description", p.description}});
  }
  return {{"name", s.name}, {"description", s.description}, {"parameters", params}};
}

void print_listing(const BuiltinScene& s) {
  std::cout << s.name << ": " << s.description << "\n";
  for (const SceneParameter& p : s.parameters) {
    std::string unit = p.unit == "-" ? "" : p.unit;
    std::cout << "  " << p.name << " = " << p.default_value << (unit.empty() ? "" : " ") << unit
              << "  (" << p.description << ")\n";
  }
  std::cout << "\n";
}

/// Writes the scene's JSON whole or not at all (cbps/io/output_file.hpp). An existing FILE is
/// replaced only with --force.
void export_scene(const ScenesOptions& o) {
  const std::string what = "--export " + o.export_file;
  check_output_file(o.export_file, what, o.force, "--force replaces it");
  const Scene scene =
      make_builtin_scene(o.name, parameter_values(o.params));  // InputError for a bad name or value
  write_output_file(o.export_file, what, scene_to_json(scene));
}

int scenes_command(const ScenesOptions& o) {
  if (o.name.empty()) {
    if (!o.params.empty()) throw InputError("--param: give the scene NAME it applies to");
    if (!o.export_file.empty()) throw InputError("--export: give the scene NAME to export");
    if (o.json) {
      nlohmann::json out = nlohmann::json::array();
      for (const BuiltinScene& s : builtin_scenes()) out.push_back(scene_listing_json(s));
      std::cout << out.dump(2) << "\n";
      return 0;
    }
    for (const BuiltinScene& s : builtin_scenes()) print_listing(s);
    std::cout << "Set parameters with --param NAME=VALUE; a JSON scene file may be given "
                 "instead of a name. `cbps scenes NAME --export FILE` writes a scene as an "
                 "editable JSON file.\n";
    return 0;
  }
  const BuiltinScene* s = find_builtin_scene(o.name);
  if (s == nullptr) make_builtin_scene(o.name, {});  // throws, listing the built-in scenes
  if (!o.export_file.empty()) {
    export_scene(o);
    if (o.json) {
      std::cout << nlohmann::json({{"scene", o.name}, {"export", o.export_file}}).dump(2) << "\n";
    } else {
      std::cout << "wrote " << o.export_file << "\n";
    }
    return 0;
  }
  if (!o.params.empty())
    throw InputError("--param: only with --export (the listing shows the defaults)");
  if (o.json) {
    std::cout << scene_listing_json(*s).dump(2) << "\n";
  } else {
    print_listing(*s);
  }
  return 0;
}

}  // namespace

void register_scenes(CLI::App& app, Action& run) {
  auto* cmd = app.add_subcommand(
      "scenes",
      "list the built-in scenes and their parameters; with NAME --export FILE write one as an "
      "editable JSON scene file");
  auto o = std::make_shared<ScenesOptions>();
  cmd->add_option("NAME", o->name, "a built-in scene: list only it, or export it with --export");
  cmd->add_option("--param",
                  o->params,
                  "NAME=VALUE: a parameter of the exported scene (repeatable; with --export)")
      ->type_name("NAME=VALUE");
  auto* exp = cmd->add_option("--export",
                              o->export_file,
                              "write scene NAME, with its --param values, as a JSON scene file "
                              "FILE that `cbps run FILE` reads (written to a temporary file "
                              "beside FILE, then renamed)")
                  ->type_name("FILE");
  cmd->add_flag("--force", o->force, "with --export: replace an existing FILE")->needs(exp);
  add_json_flag(cmd, o->json, "the scenes");
  cmd->callback([&run, o] { run = [o] { return scenes_command(*o); }; });
}

}  // namespace cbps::cli
