// The settings of a scene's world and solver, declared once (World and its SchemeSettings,
// SolverSettings, scene.hpp): each is one entry of world_settings() or solver_settings(),
// which the scene file's reader and writer (/world/KEY, /solver/KEY, scene_json.cpp), the
// options of every command that runs a scene (--KEY, underscores as dashes, where the entry
// says so), Python's Scene.KEY and the tables of docs/scene-format.md (a test holds the page to
// world_settings_markdown() and solver_settings_markdown()) all read. Adding a setting is its
// field, one entry in settings.cpp and its use. Gravity, a vector, and the method's own
// parameters are read and written beside them.
#pragma once

#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cbps/scene/scene.hpp"

namespace cbps {

/// What a setting holds: a real number in its range, a whole number in its range, one of its
/// words (held as the word's index, the order of its enum), or a flag (0 false, 1 true; a
/// scene file's boolean).
enum class SettingType { Real, Whole, Word, Flag };

/// One setting of a T (World, SolverSettings): its key, type, unit, range, rule and how it is
/// read from and written to a T. Every reader and writer of T's settings reads these entries.
template <typename T>
struct Setting {
  std::string_view key{};  ///< /world/KEY or /solver/KEY; the option --KEY with '-' for '_'
  SettingType type = SettingType::Real;
  std::string_view unit{};  ///< SI unit; "" for none
  /// Real and Whole: the range, min ≤ value ≤ max (min < value with above_min).
  double min = 0.0;
  double max = std::numeric_limits<double>::infinity();
  bool above_min = false;
  bool fraction = false;  ///< Real: a scene file may also give it as a fraction "p/q" (dt)
  /// Word: its words in enum order, and what they name in messages ("push mode").
  const std::vector<std::string>& (*words)() = nullptr;
  std::string_view noun{};
  /// Where the setting has a meaning (a scheme's own settings under that scheme, the cone's law
  /// under friction cone): given elsewhere it is refused and never written. Null: everywhere.
  bool (*applies)(const T&) = nullptr;
  std::string_view applies_text{};  ///< e.g. "scheme soft-step", for messages
  bool option = false;              ///< --KEY in the commands that run a scene
  std::string_view default_text{};  ///< the docs' default where the value alone would not say it
  std::string_view rule{};          ///< what it is: --help and the docs' rule
  double (*get)(const T&) = nullptr;
  void (*set)(T&, double) = nullptr;
  /// A rule that reads the other settings (substeps under the paper's scheme, relaxation's
  /// range by method): why `value` cannot be set, or "". Null: none.
  std::string (*check)(const T&, double value) = nullptr;
  /// Written only where this holds (a setting that defaults to another until given). Null:
  /// always, where it applies.
  bool (*given)(const T&) = nullptr;
};

using WorldSetting = Setting<World>;
using SolverSetting = Setting<SolverSettings>;

/// Every world setting, in the order a scene file's /world is read (a scheme before its own
/// settings, friction before its cone).
std::span<const WorldSetting> world_settings();
/// Every solver setting of a scene (SolverSettings, scene.hpp; SolveSettings, solver.hpp), in
/// the order a scene file's /solver is read (the method before what depends on it). The
/// method's own parameters (/solver/parameters) and the older /solver/warm_start are read
/// beside them.
std::span<const SolverSetting> solver_settings();
/// The option of a setting: "--" and its key with '-' for '_' ("--contact-hertz").
template <typename T>
std::string option_name(const Setting<T>& s);
/// Its values as a rule: "> 0", ">= 0", "in [0, 1]", ">= 1", "one of original, improved",
/// "true or false".
template <typename T>
std::string range_text(const Setting<T>& s);
/// The setting of that key, or null.
const WorldSetting* find_world_setting(std::string_view key);
const SolverSetting* find_solver_setting(std::string_view key);

/// The world a scene file starts from before its /world is read: World's defaults with the
/// scene files' contact margin and persistence (kSceneContactMargin, kSceneContactPersistence).
World scene_file_world();

/// The value of `text` for `s` (a number, "1/240" as p/q; a whole number; one of its words;
/// true or false), or nullopt with `why` set ("expected a number", "unknown push mode \"x\"
/// (valid: ...)").
template <typename T>
std::optional<double> setting_value(const Setting<T>& s, std::string_view text, std::string& why);

/// Sets `s` of `target` to `value`, checked: its range ("must be >= 0", "must be in [0, 1]"), a
/// whole number, where it applies (a scheme's own setting under another scheme) and its own
/// rule (more than one substep under the paper's scheme; relaxation's range by method).
/// Returns why it cannot, or "" once set. Naming another scheme sets substeps to that scheme's
/// default (1 for paper, kSchemeSubsteps otherwise).
template <typename T>
std::string set_setting(T& target, const Setting<T>& s, double value);
/// The same from text (setting_value, then set_setting): why `text` cannot be set, or "".
template <typename T>
std::string set_setting_text(T& target, const Setting<T>& s, std::string_view text);
inline std::string set_world_setting(World& world, const WorldSetting& s, double value) {
  return set_setting(world, s, value);
}

/// The setting's value as text: a number as the shortest text that reads back the same, a
/// word as itself, a flag as true or false.
template <typename T>
std::string setting_text(const Setting<T>& s, const T& target);

/// The rows of docs/scene-format.md's tables: the world settings (gravity's row aside) and the
/// solver settings (the method's parameters and warm_start aside).
std::string world_settings_markdown();
std::string solver_settings_markdown();

}  // namespace cbps
