#pragma once
// Shared helpers for the doctest suites: tiny inline scenes and a scratch directory.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <unistd.h>
#include <string>
#include <vector>

#include "components/model.hpp"
#include "engine/scene/scene.hpp"

namespace riffle::test {

/// The problems parse_scene reports for `text`, read as the file `file`; a failed check if it accepts the scene.
inline std::vector<std::string> problems_of(const std::string& text, const std::string& file = "bad.toml") {
  try {
    parse_scene(text, file);
  } catch (const SceneError& error) {
    return error.problems();
  }
  FAIL_CHECK("the scene was accepted:\n", text);
  return {};
}

/// (1/(pi R^2)) times the integral of max(0, s - v) over the disc u^2 + v^2 <= R^2, v the height above its centre:
/// the mean hydrostatic pressure per rho g over a vertical disc whose centre lies s below the water line (exact;
/// the reference of the pressure transducer tests).
inline double half_submerged_mean(double s, double radius) {
  constexpr double kPi = 3.14159265358979323846;
  const double r2 = radius * radius;
  if (s >= radius) return s;
  if (s <= -radius) return 0.0;
  const double root = std::sqrt(r2 - s * s);
  return (s * (s * root + r2 * std::asin(s / radius) + r2 * kPi / 2.0) + 2.0 / 3.0 * root * root * root) /
         (kPi * r2);
}

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

/// A small valid fluid scene without grains: a tank of 8 x 4 x 6 lattice cells (l0 = 5 mm, open top, origin off
/// zero so the lattice anchoring shows), two fluid boxes (4 x 4 x 3 moving, 4 x 4 x 1 at rest) and two overlapping
/// wall boxes (4 and 8 points, 4 shared). `extra` is appended verbatim.
inline std::string fluid_scene_text(const std::string& extra = "") {
  return R"(
[run]
name = "fluid"
end_time = 0.01
dt = 1.0e-3

[materials.glass]
density = 2500.0

[tank]
size = [0.04, 0.02, 0.03]
origin = [0.1, -0.01, 0.0]
open_faces = ["z_max"]
wall_material = "glass"

[tank.motion]
kind = "sinusoidal"
amplitude = 0.01
frequency = 1.7

[fluid]
spacing = 0.005

[[fluid.boxes]]
low = [0.1, -0.01, 0.0]
high = [0.12, 0.01, 0.015]
velocity = [0.1, 0.0, -0.2]

[[fluid.boxes]]
low = [0.12, -0.01, 0.0]
high = [0.14, 0.01, 0.005]

[[fluid.wall_boxes]]
low = [0.12, -0.01, 0.005]
high = [0.125, 0.01, 0.01]

[[fluid.wall_boxes]]
low = [0.12, -0.01, 0.005]
high = [0.13, 0.01, 0.01]
)" + extra;
}

inline Model fluid_model() { return parse_scene(fluid_scene_text(), "fluid.toml"); }

/// A small coupled scene for the [coupling] keys' tests: one 5 mm grain in a 10 cm closed tank of water (l0 = 1 cm) up
/// to 8 cm, no [coupling] table (a test appends one). The text's first line is [run], so the appended [coupling] is
/// line 19.
inline std::string coupled_scene_text() {
  return R"([run]
end_time = 0.1
dt = 1.0e-3
[materials.grain]
density = 2650.0
[tank]
size = [0.1, 0.1, 0.1]
wall_material = "grain"
[solids]
[[solids.spheres]]
position = [0.05, 0.05, 0.05]
radius = 0.005
material = "grain"
[fluid]
spacing = 0.01
[[fluid.boxes]]
low = [0.0, 0.0, 0.0]
high = [0.1, 0.1, 0.08]
)";
}

/// A fresh, empty directory under the system's temporary directory.
inline std::filesystem::path scratch_dir(const std::string& name) {
  // Per process: ctest runs every test case as its own process, two at a time, and test cases share names.
  const auto path =
      std::filesystem::temp_directory_path() / ("riffle_test_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(path);
  std::filesystem::create_directories(path);
  return path;
}

}  // namespace riffle::test
