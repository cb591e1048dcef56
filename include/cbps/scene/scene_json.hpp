// JSON scene files: reading with validation (errors name the file and the JSON path) and writing.
#pragma once

#include <string>

#include "cbps/scene/scene.hpp"

namespace cbps {

/// Reads a scene from a JSON file. Throws InputError("<file>: <json path>: <why>").
Scene read_scene_file(const std::string& path);

/// Parses a scene from JSON text; `source` names it in errors.
Scene parse_scene(const std::string& text, const std::string& source);

/// Writes a scene as JSON text that parse_scene reads back to the same scene.
std::string scene_to_json(const Scene& scene);

}  // namespace cbps
