#pragma once
// Scene loading and validation: TOML text -> Model. All problems are collected and raised together as a
// SceneError, each naming file, line, column and key. See docs/SCENES.md for the format.
#include <cstdint>
#include <string>
#include <vector>

#include "engine/setup/budget.hpp"
#include "components/model.hpp"
#include "engine/toml/scene_reader.hpp"

namespace riffle {

/// A scene file may not be larger than this (16 MiB: the largest scene in scenes/ is a few KiB; a list of a million
/// explicit spheres is about 100 MiB and belongs in a checkpoint given as [solids] initial_state).
inline constexpr std::uint64_t kMaxSceneFileBytes = 16u << 20;

/// The text of a scene file: regular files only (a FIFO, /dev/zero, a device or a directory is refused before it
/// is read), at most kMaxSceneFileBytes. Throws SceneError.
std::string read_scene_text(const std::string& path);

/// Reads and validates a scene file, with `overrides` (--set KEY=VALUE, engine/scene/scene_overrides.hpp) applied
/// first. Throws SceneError (also for an unreadable file).
Model load_scene_file(const std::string& path, const SceneLimits& limits = {},
                      const std::vector<std::string>& overrides = {}, SceneKeyCatalogue* catalogue = nullptr);

/// Reads the material name at `key` and returns its index in model.materials (materials must be read already);
/// a missing, non-string or unknown name is reported through the reader and gives 0.
std::int32_t read_material(const Model& model, TableReader& reader, const std::string& key);

/// [s] output.checkpoint_interval when the scene does not set it: end_time / 10 for a run of at least 1000 steps of
/// run.dt, else 0 (a checkpoint only at the end and on a signal).
double default_checkpoint_interval(double end_time, double dt);

/// Validates scene text; `file_name` is used in messages only.
/// Refuses (SceneError) a scene whose estimated budget (engine/setup/budget.hpp) exceeds the memory limit, before any
/// particle is generated or laid out.
/// With `overrides`, model.scene_text is the changed scene written back as TOML (scene_text_with_overrides).
/// With `catalogue`, every key the reading asks for is recorded there (engine/toml/scene_reader.hpp, SceneKey).
Model parse_scene(const std::string& text, const std::string& file_name, const SceneLimits& limits = {},
                  const std::vector<std::string>& overrides = {}, SceneKeyCatalogue* catalogue = nullptr);

}  // namespace riffle
