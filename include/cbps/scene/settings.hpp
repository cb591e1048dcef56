// The settings of a scene's world, declared once (World and its SchemeSettings, scene.hpp): each
// is one entry of world_settings(), which the scene file's reader and writer (/world/KEY,
// scene_json.cpp), the options of every command that runs a scene (--KEY, underscores as dashes,
// where the entry says so), Python's Scene.KEY and the table of docs/scene-format.md (a test
// holds the page to world_settings_markdown()) all read. Adding a setting is its field in World,
// one entry here and its use. Gravity, a vector, is read and written beside them.
#pragma once

#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cbps/scene/scene.hpp"

namespace cbps {

/// What a setting holds: a real number in its range, a whole number in its range, or one of its
/// words (held as the word's index, the order of its enum).
enum class SettingType { Real, Whole, Word };

struct WorldSetting {
  std::string_view key{};  ///< /world/KEY; the option --KEY with '-' for '_'
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
  bool (*applies)(const World&) = nullptr;
  std::string_view applies_text{};  ///< e.g. "scheme soft-step", for messages
  bool option = false;              ///< --KEY in the commands that run a scene
  std::string_view default_text{};  ///< the docs' default where the value alone would not say it
  std::string_view rule{};          ///< what it is: --help and the docs' rule
  double (*get)(const World&) = nullptr;
  void (*set)(World&, double) = nullptr;
};

/// Every world setting, in the order a scene file's /world is read (a scheme before its own
/// settings, friction before its cone).
std::span<const WorldSetting> world_settings();
/// The option of a setting: "--" and its key with '-' for '_' ("--contact-hertz").
std::string option_name(const WorldSetting& s);
/// Its values as a rule: "> 0", ">= 0", "in [0, 1]", ">= 1", "one of original, improved".
std::string range_text(const WorldSetting& s);
/// The setting of that key, or null.
const WorldSetting* find_world_setting(std::string_view key);

/// The world a scene file starts from before its /world is read: World's defaults with the
/// scene files' contact margin and persistence (kSceneContactMargin, kSceneContactPersistence).
World scene_file_world();

/// The value of `text` for `s` (a number, "1/240" as p/q; a whole number; one of its words), or
/// nullopt with `why` set ("expected a number", "unknown push mode \"x\" (valid: ...)").
std::optional<double> setting_value(const WorldSetting& s, std::string_view text, std::string& why);

/// Sets `s` of `world` to `value`, checked: its range ("must be >= 0", "must be in [0, 1]"), a
/// whole number, a scheme's own setting under another scheme, more than one substep under the
/// paper's scheme. Returns why it cannot, or "" once set. Naming another scheme sets substeps
/// to that scheme's default (1 for paper, kSchemeSubsteps otherwise).
std::string set_world_setting(World& world, const WorldSetting& s, double value);

/// The setting's value as text: a number as the shortest text that reads back the same, a
/// word as itself.
std::string setting_text(const WorldSetting& s, const World& world);

/// The rows of docs/scene-format.md's table for the world settings (gravity's row aside).
std::string world_settings_markdown();

}  // namespace cbps
