#pragma once
// Reading scene files (TOML, schema_version 1: one body; 2: bodies and joints,
// filling Scene::multibody; format in docs/scene_format.md).
#include <string>

#include "rigidae/model/scene.hpp"

namespace rigidae::io {

// Parses and validates a scene. Throws rigidae::InputError whose message
// starts with "FILE:LINE:COL: error: " and says what would be valid.
// Orientation inputs are converted to R0_WB; the angular velocity to body
// components.
Scene load_scene(const std::string& path);
// Same, from text already in memory; `source_name` stands in for the path in messages.
Scene parse_scene(const std::string& text, const std::string& source_name);

}  // namespace rigidae::io
