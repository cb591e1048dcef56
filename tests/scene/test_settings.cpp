// The tables of world and solver settings (scene/settings.hpp): every setting read, written and
// checked from its one entry; the docs' tables, the fuzz dictionary and --help made from them.
#include <catch2/catch.hpp>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "cbps/base/error.hpp"
#include "cbps/scene/scene_json.hpp"
#include "cbps/scene/settings.hpp"

using namespace cbps;

namespace {

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

/// A world where `s` applies (its scheme or law chosen), so that it may be set.
World world_where_it_applies(const WorldSetting& s) {
  World world = scene_file_world();
  for (const std::string scheme : {"soft-step", "xpbd"})
    if (s.applies_text.substr(0, 7) == "scheme " && s.applies_text.substr(7) == scheme) {
      std::string why;
      set_world_setting(world,
                        *find_world_setting("scheme"),
                        *setting_value(*find_world_setting("scheme"), scheme, why));
    }
  if (s.key == "speculative_distance" || s.key == "substeps") world.scheme.kind = Scheme::Tgs;
  if (s.key == "cone") world.friction = FrictionLaw::CoulombCone;
  return world;
}

/// The scene's file with KEY's value replaced by -1 is refused, naming /PART/KEY.
void refused_in_file(const Scene& scene, const std::string& part, std::string_view key) {
  std::string file = scene_to_json(scene);
  std::string quoted = "\"";  // appended, not added: GCC 12's -Wrestrict misreads the sum
  quoted.append(key).append("\": ");
  const auto at = file.find(quoted);
  REQUIRE(at != std::string::npos);
  const auto end = file.find_first_of(",\n}", at + quoted.size());
  file.replace(at + quoted.size(), end - at - quoted.size(), "-1");
  CHECK_THROWS_WITH(parse_scene(file, "settings.json"),
                    Catch::Contains("settings.json: " + part + std::string(key) + ": "));
}

/// A value of `s` that is not its default and lies in its range: the last word, the other flag,
/// or the minimum plus 2 (whole) or 0.375 (an exact binary fraction), within the maximum.
template <typename T>
double other_value(const Setting<T>& s, const T& target) {
  return s.type == SettingType::Word    ? static_cast<double>(s.words().size() - 1)
         : s.type == SettingType::Flag  ? 1.0 - s.get(target)
         : s.type == SettingType::Whole ? s.min + 2.0
                                        : std::min(s.min + 0.375, s.max);
}

}  // namespace

TEST_CASE("docs/scene-format.md holds the world and solver settings' rows as the tables make them",
          "[settings]") {
  const std::string page = read_text(std::string(CBPS_SOURCE_DIR) + "/docs/scene-format.md");
  for (const std::string& rows : {world_settings_markdown(), solver_settings_markdown()}) {
    INFO(
        "rows docs/scene-format.md should hold (after /world/gravity, before /solver/warm_start):\n"
        << rows);
    CHECK(page.find(rows) != std::string::npos);
  }
}

TEST_CASE("every world and solver setting is in the fuzz dictionary of scene files", "[settings]") {
  const std::string dict = read_text(std::string(CBPS_SOURCE_DIR) + "/fuzz/scene_json.dict");
  std::vector<std::string_view> keys;
  for (const WorldSetting& s : world_settings()) keys.push_back(s.key);
  for (const SolverSetting& s : solver_settings()) keys.push_back(s.key);
  for (const std::string_view key : keys) {
    CAPTURE(key);
    std::string entry = R"("\")";
    entry.append(key).append(R"(\"")");
    CHECK(dict.find(entry) != std::string::npos);
  }
}

TEST_CASE("every world setting reads back from a scene file as written, and its range is held",
          "[settings]") {
  for (const WorldSetting& s : world_settings()) {
    CAPTURE(s.key);
    World world = world_where_it_applies(s);
    const double value = other_value(s, world);
    REQUIRE(set_world_setting(world, s, value).empty());
    Scene scene;
    scene.world = world;
    const Scene back = parse_scene(scene_to_json(scene), "settings.json");
    CHECK(s.get(back.world) == value);
    // Below the range (or a word past the last) is refused with the key named.
    if (s.type == SettingType::Word) {
      CHECK_FALSE(set_world_setting(world, s, static_cast<double>(s.words().size())).empty());
    } else {
      CHECK_FALSE(set_world_setting(world, s, s.min - 1.0).empty());
      refused_in_file(scene, "/world/", s.key);
    }
  }
}

TEST_CASE("a setting of one scheme or law is refused under another, and not written",
          "[settings]") {
  const std::string file = R"({"world": {"scheme": "tgs", "contact_hertz": 20}, "bodies": []})";
  CHECK_THROWS_WITH(parse_scene(file, "s.json"),
                    "s.json: /world/contact_hertz: a setting of scheme soft-step; the world has "
                    "scheme tgs (got 20)");
  CHECK_THROWS_WITH(
      parse_scene(R"({"world": {"friction": "coulomb", "cone": "ccp"}, "bodies": []})", "s.json"),
      Catch::Contains("/world/cone: a setting of friction cone; the world has friction coulomb"));
  Scene scene;  // the paper's scheme: the soft step's stiffness means nothing and is left out
  scene.world.scheme.contact_hertz = 20.0;
  CHECK(scene_to_json(scene).find("contact_hertz") == std::string::npos);
}

TEST_CASE("naming another scheme gives it its substeps, and more than one under paper is refused",
          "[settings]") {
  World world;
  const WorldSetting& scheme = *find_world_setting("scheme");
  const WorldSetting& substeps = *find_world_setting("substeps");
  std::string why;
  CHECK(set_world_setting(world, substeps, 3.0) ==
        "needs a scheme that substeps (tgs, soft-step, xpbd), not paper");
  REQUIRE(set_world_setting(world, scheme, *setting_value(scheme, "tgs", why)).empty());
  CHECK(world.scheme.substeps == kSchemeSubsteps);
  REQUIRE(set_world_setting(world, substeps, 3.0).empty());
  REQUIRE(set_world_setting(world, scheme, *setting_value(scheme, "tgs", why)).empty());
  CHECK(world.scheme.substeps == 3);  // the same scheme named again keeps them
  REQUIRE(set_world_setting(world, scheme, *setting_value(scheme, "paper", why)).empty());
  CHECK(world.scheme.substeps == 1);
  CHECK_FALSE(setting_value(scheme, "verlet", why));
  CHECK(why == "unknown scheme \"verlet\" (valid: paper, tgs, soft-step, xpbd)");
  CHECK(set_world_setting(world, *find_world_setting("substeps"), 1.5) == "expected an integer");
}

TEST_CASE("an option's name is its key with dashes", "[settings]") {
  CHECK(option_name(*find_world_setting("contact_damping_ratio")) == "--contact-damping-ratio");
  CHECK(find_world_setting("no_such_setting") == nullptr);
}

TEST_CASE("every solver setting reads back from a scene file as written, and its range is held",
          "[settings]") {
  for (const SolverSetting& s : solver_settings()) {
    CAPTURE(s.key);
    SolverSettings solver;
    const double value = other_value(s, solver);
    REQUIRE(value != s.get(solver));
    REQUIRE(set_setting(solver, s, value).empty());
    Scene scene;
    scene.solver = solver;
    const Scene back = parse_scene(scene_to_json(scene), "settings.json");
    CHECK(s.get(back.solver) == value);
    if (s.type == SettingType::Word) {
      CHECK_FALSE(set_setting(solver, s, static_cast<double>(s.words().size())).empty());
    } else if (s.type == SettingType::Flag) {
      CHECK(set_setting(solver, s, 0.5) == "expected true or false");
    } else {
      CHECK_FALSE(set_setting(solver, s, s.min - 1.0).empty());
      refused_in_file(scene, "/solver/", s.key);
    }
  }
}

TEST_CASE("the solver settings that depend on the method are checked against it", "[settings]") {
  SolverSettings solver;
  std::string why;
  const SolverSetting& method = *find_solver_setting("method");
  const SolverSetting& relaxation = *find_solver_setting("relaxation");
  const SolverSetting& contacts_first = *find_solver_setting("contacts_first");
  REQUIRE(set_setting(solver, relaxation, 1.5).empty());  // SOR under pgs: (0, 2)
  // Jacobi damps: (0, 1]. Naming it with omega 1.5 is refused, and so is 1.5 under it.
  CHECK(set_setting(solver, method, *setting_value(method, "jacobi", why)) ==
        "takes a relaxation in (0, 1], not 1.5");
  REQUIRE(set_setting(solver, relaxation, 1.0).empty());
  REQUIRE(set_setting(solver, method, *setting_value(method, "jacobi", why)).empty());
  CHECK(set_setting(solver, relaxation, 1.5) == "must be in (0, 1]");
  CHECK(set_setting(solver, contacts_first, 1.0) ==
        "applies to the methods pgs and matrix-free (method is \"jacobi\")");
  CHECK_THROWS_WITH(
      parse_scene(R"({"solver": {"method": "direct", "contacts_first": true}, "bodies": []})",
                  "s.json"),
      "s.json: /solver/contacts_first: applies to the methods pgs and matrix-free (method is "
      "\"direct\")");
  CHECK_THROWS_WITH(
      parse_scene(R"({"solver": {"order": "sideways"}, "bodies": []})", "s.json"),
      "s.json: /solver/order: unknown row order \"sideways\" (valid: natural, reverse, random)");
  // A flag is a boolean in a scene file, true or false on the command line.
  CHECK_THROWS_WITH(parse_scene(R"({"solver": {"split_islands": 1}, "bodies": []})", "s.json"),
                    Catch::Contains("s.json: /solver/split_islands: expected true or false"));
  CHECK(setting_value(contacts_first, "true", why) == 1.0);
  CHECK_FALSE(setting_value(contacts_first, "yes", why));
  // warm_friction follows warm until given, and is written only once given.
  SolverSettings warm;
  warm.warm = 0.5;
  CHECK(find_solver_setting("warm_friction")->get(warm) == 0.5);
  Scene scene;
  CHECK(scene_to_json(scene).find("warm_friction") == std::string::npos);
  scene.solver.warm_friction = 0.0;
  CHECK(parse_scene(scene_to_json(scene), "s.json").solver.warm_friction == 0.0);
  // A seed up to 2^53 (every whole number a double holds exactly) reads back as given.
  CHECK(parse_scene(R"({"solver": {"seed": 9007199254740992}, "bodies": []})", "s.json")
            .solver.seed == 9007199254740992u);
  CHECK_THROWS_WITH(
      parse_scene(R"({"solver": {"seed": 9007199254740994}, "bodies": []})", "s.json"),
      Catch::Contains("/solver/seed: too large"));
}
