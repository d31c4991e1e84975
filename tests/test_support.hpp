#pragma once
// Shared helpers for the doctest suites: tiny inline scenes and a scratch directory.
#include <filesystem>
#include <string>

#include "engine/model.hpp"
#include "engine/scene.hpp"

namespace riffle::test {

/// A small valid scene: a closed shaken tank with a few free-flying grains. `extra` is appended verbatim.
inline std::string small_scene_text(const std::string& extra = "") {
  return R"(
[run]
name = "small"
end_time = 0.05
dt = 1.0e-3
solid_substeps = 4

[materials.grain]
density = 1318.0

[tank]
size = [0.24, 0.16, 0.20]
wall_material = "grain"

[tank.motion]
kind = "sinusoidal"
amplitude = 0.01
frequency = 1.7
ramp_time = 0.2

[solids]
sort_every = 7

[[solids.blocks]]
min = [0.02, 0.02, 0.03]
max = [0.22, 0.14, 0.07]
spacing = 0.02
radius = 0.0025
material = "grain"
velocity = [0.01, -0.02, 0.9]
)" + extra;
}

inline Model small_model() { return parse_scene(small_scene_text(), "small.toml"); }

/// A fresh, empty directory under the system's temporary directory.
inline std::filesystem::path scratch_dir(const std::string& name) {
  const auto path = std::filesystem::temp_directory_path() / ("riffle_test_" + name);
  std::filesystem::remove_all(path);
  std::filesystem::create_directories(path);
  return path;
}

}  // namespace riffle::test
