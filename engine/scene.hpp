#pragma once
// Scene loading and validation: TOML text -> Model. All problems are collected and raised together as a
// SceneError, each naming file, line, column and key. See docs/SCENES.md for the format.
#include <string>

#include "engine/model.hpp"
#include "engine/scene_reader.hpp"

namespace riffle {

/// Reads and validates a scene file. Throws SceneError (also for an unreadable file).
Model load_scene_file(const std::string& path);

/// Reads the material name at `key` and returns its index in model.materials (materials must be read already);
/// a missing, non-string or unknown name is reported through the reader and gives 0.
std::int32_t read_material(const Model& model, TableReader& reader, const std::string& key);

/// Validates scene text; `file_name` is used in messages only.
Model parse_scene(const std::string& text, const std::string& file_name);

}  // namespace riffle
