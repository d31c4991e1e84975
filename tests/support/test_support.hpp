#pragma once
// Shared helpers for the doctest suites: tiny inline scenes and a scratch directory.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include "components/model.hpp"
#include "components/world.hpp"
#include "engine/setup/fluid_layout.hpp"
#include "engine/scene/scene.hpp"
#include "systems/physics/mps/mps_common.hpp"
#include "tests/support/scene_builder.hpp"

namespace riffle::test {

/// The problems parse_scene reports for `text`, read as the file `file`; a failed check (which lets a table of cases
/// go on) if it accepts the scene or throws anything but SceneError.
inline std::vector<std::string> problems_of(const std::string& text, const std::string& file = "bad.toml") {
  try {
    parse_scene(text, file);
  } catch (const SceneError& error) {
    return error.problems();
  } catch (const std::exception& error) {
    FAIL_CHECK("parse_scene threw something other than SceneError: ", error.what(), "\n", text);
    return {};
  }
  FAIL_CHECK("the scene was accepted:\n", text);
  return {};
}

inline constexpr double kG = 9.81;         // [m/s^2] gravity in the test scenes
inline constexpr double kRho = 1000.0;     // [kg/m^3] water in the test scenes

/// The slot of grain `id` (neighbour-list rebuilds may reorder the slots).
inline std::size_t slot_of(const Solids& solids, EntityId id) {
  return static_cast<std::size_t>(std::find(solids.id.begin(), solids.id.end(), id) - solids.id.begin());
}

/// `lines`, each indented by two spaces on a line of its own: a list of problems shown in a failed check.
inline std::string joined(const std::vector<std::string>& lines) {
  std::string out;
  for (const std::string& line : lines) out += "  " + line + "\n";
  return out;
}

/// The lines of the file at `path` (none if it cannot be read).
inline std::vector<std::string> file_lines(const std::filesystem::path& path) {
  std::ifstream file(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(file, line);) lines.push_back(line);
  return lines;
}

/// The bytes of the file at `path` ("" if it cannot be read).
inline std::string file_text(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

/// How many times `needle` occurs in `text` (overlapping occurrences count).
inline std::size_t count_of(std::string_view text, std::string_view needle) {
  std::size_t count = 0;
  for (std::size_t at = text.find(needle); at != std::string_view::npos; at = text.find(needle, at + 1)) ++count;
  return count;
}

/// `text` with `old` replaced by `with`; `old` must occur exactly once, so that a table row cannot silently edit the
/// wrong line.
inline std::string replace_once(std::string_view text, std::string_view old, std::string_view with) {
  REQUIRE_MESSAGE(count_of(text, old) == 1, "\"", std::string(old), "\" must occur exactly once in the scene");
  std::string out(text);
  out.replace(out.find(old), old.size(), with);
  return out;
}

/// A place in a text: 1-based line and column, as toml++ reports them.
struct TextPosition {
  int line = 0;
  int column = 0;
};

/// Where `needle` is in `text`; a '^' in it marks the character meant (default: its first), so "dt = ^-1" points at
/// the value, not the key. With `once` the needle must occur exactly once, else its first occurrence counts.
inline TextPosition position_of(std::string_view text, std::string needle, bool once = true) {
  std::size_t mark = needle.find('^');
  if (mark == std::string::npos)
    mark = 0;
  else
    needle.erase(mark, 1);
  if (once)
    REQUIRE_MESSAGE(count_of(text, needle) == 1, "\"", needle, "\" must occur exactly once in the scene");
  else
    REQUIRE_MESSAGE(text.find(needle) != std::string_view::npos, "\"", needle, "\" is not in the scene");
  const std::size_t at = text.find(needle) + mark;
  const std::size_t newline = at == 0 ? std::string_view::npos : text.rfind('\n', at - 1);
  TextPosition position;
  position.line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
  position.column = static_cast<int>(newline == std::string_view::npos ? at + 1 : at - newline);
  return position;
}

/// "file:line:column: ", the start of a problem reported at `needle` in `text` (as position_of finds it).
inline std::string location(const std::string& file, std::string_view text, const std::string& needle,
                            bool once = true) {
  const TextPosition where = position_of(text, needle, once);
  return file + ":" + std::to_string(where.line) + ":" + std::to_string(where.column) + ": ";
}

/// "file:line:column: " of the first occurrence of `needle` in `text` (a '^' in the needle marks the character meant).
inline std::string first_location(const std::string& file, std::string_view text, const std::string& needle) {
  return location(file, text, needle, false);
}

/// (1/(pi R^2)) times the integral of max(0, s - v) over the disc u^2 + v^2 <= R^2, v the height above its centre:
/// the mean hydrostatic pressure per rho g over a vertical disc whose centre lies s below the water line (exact;
/// the reference of the pressure transducer tests).
inline double half_submerged_mean(double s, double radius) {
  const double r2 = radius * radius;
  if (s >= radius) return s;
  if (s <= -radius) return 0.0;
  const double root = std::sqrt(r2 - s * s);
  return (s * (s * root + r2 * std::asin(s / radius) + r2 * std::numbers::pi / 2.0) + 2.0 / 3.0 * root * root * root) /
         (std::numbers::pi * r2);
}

/// A small valid scene: a closed shaken tank with a few free-flying grains. `extra` is appended verbatim.
inline std::string small_scene_text(const std::string& extra = "") {
  return SceneBuilder(SceneBuilder::kSpaced)
      .run({.name = "small", .end_time = 0.05, .dt = 1.0e-3, .solid_substeps = 4})
      .material("grain", {.density = 1318.0}).tank({.size = {0.24, 0.16, 0.20}, .wall_material = "grain"})
      .tank_motion({.amplitude = 0.01, .frequency = 1.7, .ramp_time = 0.2}).solids().set("sort_every", 7)
      .block({.min = {0.02, 0.02, 0.03}, .max = {0.22, 0.14, 0.07}, .spacing = 0.02, .radius = 0.0025,
              .material = "grain", .velocity = {0.01, -0.02, 0.9}})
      .toml() + extra;
}

inline Model small_model() { return parse_scene(small_scene_text(), "small.toml"); }

/// small_model() with water of spacing `spacing` and the coupling on: the model of the coupling systems' tests on a
/// World built by hand.
inline Model small_coupled_model(double spacing) {
  Model model = small_model();
  model.fluid.enabled = true;
  model.fluid.spacing = spacing;
  fill_mps_constants(model.fluid);
  model.coupling.enabled = true;
  return model;
}

/// A point or vector as the scene builder takes it.
inline Triple triple(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

/// Gives `world` water particles filling the box from the origin to `high` on the lattice of `spacing`.
inline void fill_with_water(World& world, const Vec3& high, double spacing) {
  world.fluid.emplace();
  append_layout(*world.fluid, fluid_box_layout(Vec3::Zero(), Vec3::Zero(), high, spacing));
}

/// A small valid fluid scene without grains: a tank of 8 x 4 x 6 lattice cells (l0 = 5 mm, open top, origin off
/// zero so the lattice anchoring shows), two fluid boxes (4 x 4 x 3 moving, 4 x 4 x 1 at rest) and two overlapping
/// wall boxes (4 and 8 points, 4 shared). `extra` is appended verbatim.
inline std::string fluid_scene_text(const std::string& extra = "") {
  return SceneBuilder(SceneBuilder::kSpaced).run({.name = "fluid", .end_time = 0.01, .dt = 1.0e-3})
      .material("glass", {.density = 2500.0})
      .tank({.size = {0.04, 0.02, 0.03}, .origin = {0.1, -0.01, 0.0}, .open_faces = {"z_max"},
             .wall_material = "glass"})
      .tank_motion({.amplitude = 0.01, .frequency = 1.7}).fluid({.spacing = 0.005})
      .fluid_box({0.1, -0.01, 0.0}, {0.12, 0.01, 0.015}, {0.1, 0.0, -0.2})
      .fluid_box({0.12, -0.01, 0.0}, {0.14, 0.01, 0.005})
      .wall_box({.low = {0.12, -0.01, 0.005}, .high = {0.125, 0.01, 0.01}})
      .wall_box({.low = {0.12, -0.01, 0.005}, .high = {0.13, 0.01, 0.01}}).toml() + extra;
}

inline Model fluid_model() { return parse_scene(fluid_scene_text(), "fluid.toml"); }

/// A small coupled scene for the [coupling] keys' tests: one 5 mm grain in a 10 cm closed tank of water (l0 = 1 cm) up
/// to 8 cm, no [coupling] table (a test appends one). The text's first line is [run], so the appended [coupling] is
/// line 19.
inline std::string coupled_scene_text() {
  return SceneBuilder().run({.end_time = 0.1, .dt = 1.0e-3}).material("grain", {.density = 2650.0})
      .tank({.size = {0.1, 0.1, 0.1}, .wall_material = "grain"})
      .sphere({.position = {0.05, 0.05, 0.05}, .radius = 0.005, .material = "grain"}).fluid({.spacing = 0.01})
      .fluid_box({0.0, 0.0, 0.0}, {0.1, 0.1, 0.08}).toml();
}

/// The scratch directories this test process made, removed when it ends (also after a failed check), so that runs of
/// the suite do not fill the temporary directory (each leaves ~15 MB of checkpoints and frames). RIFFLE_KEEP_SCRATCH=1
/// keeps them for a look after a failure.
class ScratchDirectories {
 public:
  ScratchDirectories(const ScratchDirectories&) = delete;
  ScratchDirectories& operator=(const ScratchDirectories&) = delete;
  static ScratchDirectories& instance() {
    static ScratchDirectories directories;
    return directories;
  }
  void add(const std::filesystem::path& path) { paths_.push_back(path); }
  ~ScratchDirectories() {
    if (const char* keep = std::getenv("RIFFLE_KEEP_SCRATCH"); keep != nullptr && std::string_view(keep) == "1") return;
    for (const auto& path : paths_) {
      std::error_code ignored;
      std::filesystem::remove_all(path, ignored);
    }
  }

 private:
  ScratchDirectories() = default;
  std::vector<std::filesystem::path> paths_;
};

/// A fresh, empty directory under the system's temporary directory, removed when the test process ends.
inline std::filesystem::path scratch_dir(const std::string& name) {
  // Per process: ctest runs every test case as its own process, two at a time, and test cases share names.
  const auto path =
      std::filesystem::temp_directory_path() / ("riffle_test_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(path);
  std::filesystem::create_directories(path);
  ScratchDirectories::instance().add(path);
  return path;
}

}  // namespace riffle::test
