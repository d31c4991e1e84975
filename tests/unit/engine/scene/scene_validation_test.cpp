// Scene validation: every bad scene must be rejected with a SceneError whose lines name the file, the line and
// column of the offending key or value, the full key and what was wrong; every good scene must load. The fuzz test
// at the end feeds thousands of mutated scenes through the parser: it may only return a sane Model or throw a
// SceneError.
#include <doctest/doctest.h>

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "engine/scene/scene.hpp"
#include "engine/setup/bed_generation.hpp"
#include "tests/support/test_support.hpp"

namespace {

using test::joined;

// Small but uses every key the reader knows, so that mutations (and the fuzz test) reach every code path.
// Blocks: x and y from 0.02 to 0.08 step 0.01 -> 7 each, z from 0.02 to 0.04 -> 3: 147 grains, plus 1 sphere.
constexpr std::string_view kBaseScene = R"(# Base scene for the validation tests.
[run]
name = "base"
end_time = 0.1
dt = 1.0e-3
solid_substeps = 4
gravity = [0.0, 0.0, -9.81]

[materials.sand]
density = 2650.0

[materials.glass]
density = 2500.0

[tank]
size = [0.2, 0.1, 0.1]
origin = [0.0, 0.0, 0.0]
open_faces = ["z_max"]
wall_material = "glass"
domain_margin = 0.05

[tank.motion]
kind = "sinusoidal"
direction = [1.0, 0.0, 0.0]
amplitude = 0.01
frequency = 2.0
ramp_time = 0.5

[solids]
sort_every = 10

[[solids.spheres]]
position = [0.1, 0.05, 0.05]
velocity = [0.0, 0.0, 1.0]
angular_velocity = [0.0, 5.0, 0.0]
radius = 0.005
material = "sand"
size_class = 1

[[solids.blocks]]
min = [0.02, 0.02, 0.02]
max = [0.08, 0.08, 0.04]
spacing = 0.01
radius = 0.004
material = "sand"
velocity = [0.0, 0.0, 0.5]

[output]
vtk_interval = 0.01
checkpoint_interval = 0.05
checkpoint_keep = 2
diagnostics_every = 5
)";

constexpr std::size_t kBaseGrains = 7 * 7 * 3 + 1;

using riffle::test::count_of, riffle::test::replace_once, riffle::test::position_of, riffle::test::problems_of,
    riffle::test::TextPosition;


/// One problem line "file:line:column: key: message", split up; nullopt if it does not have that shape.
struct ProblemLine {
  std::string file;
  int line = 0;
  int column = 0;
  std::string key;
  std::string message;
};

std::optional<ProblemLine> split_problem(const std::string& text, const std::string& file_name) {
  if (text.rfind(file_name + ":", 0) != 0) return std::nullopt;
  std::istringstream rest(text.substr(file_name.size() + 1));
  ProblemLine problem;
  problem.file = file_name;
  char colon1 = 0, colon2 = 0;
  if (!(rest >> problem.line >> colon1 >> problem.column >> colon2) || colon1 != ':' || colon2 != ':')
    return std::nullopt;
  std::string tail;
  std::getline(rest, tail);
  const std::size_t split = tail.find(": ");
  if (tail.empty() || tail[0] != ' ' || split == std::string::npos || split < 2) return std::nullopt;
  problem.key = tail.substr(1, split - 1);
  problem.message = tail.substr(split + 2);
  if (problem.message.empty()) return std::nullopt;
  return problem;
}

}  // namespace

TEST_CASE("the base scene of these tests is valid") {
  const riffle::Model model = riffle::parse_scene(std::string(kBaseScene), "base.toml");
  CHECK(riffle::scene_spheres(model).size() == kBaseGrains);
  CHECK(riffle::scene_sphere_count(model.solids) == static_cast<std::int64_t>(kBaseGrains));
  CHECK(model.dt == 1.0e-3);
  CHECK(model.solid_substeps == 4);
  CHECK(model.tank.motion.kind == riffle::TankMotionModel::Kind::kSinusoidal);
}

TEST_CASE("bad scenes are rejected with file, line, column, key and a useful message") {
  struct BadScene {
    const char* find;      // text of the base scene to change (must occur once)
    const char* replace;   // what it becomes
    const char* at;        // where the problem must be reported: unique text of the mutated scene, '^' = column
    const char* key;       // full key in the message
    const char* message;   // fragment of the message
    std::size_t problems;  // how many problems the scene has in all (1 = no follow-up noise)
  };
  const std::vector<BadScene> cases = {
      // Wrong type, non-positive or non-finite numbers.
      {"dt = 1.0e-3", "dt = \"fast\"", "dt = ^\"fast\"", "run.dt", "expected a number > 0 [s], got a string", 1},
      {"dt = 1.0e-3", "dt = -1", "dt = ^-1", "run.dt", "expected a number > 0 [s], got -1", 1},
      {"dt = 1.0e-3", "dt = 0.0", "dt = ^0.0", "run.dt", "got 0", 1},
      {"dt = 1.0e-3", "dt = nan", "dt = ^nan", "run.dt", "got nan", 1},
      {"dt = 1.0e-3", "dt = -inf", "dt = ^-inf", "run.dt", "got -inf", 1},
      {"dt = 1.0e-3", "dt = 1.0e-30", "dt = ^1.0e-30", "run.dt", "dt is too small for end_time", 1},
      // An integer beyond 2^53 is still a number: report its value, not "got 0".
      {"dt = 1.0e-3", "dt = -9007199254740993", "dt = ^-9007199254740993", "run.dt", "got -9.0072e+15", 1},
      {"size = [0.2, 0.1, 0.1]", "size = [0.2, 0.0, 0.1]", "size = [0.2, ^0.0", "tank.size[1]",
       "expected a number > 0 [m], got 0", 1},
      {"size = [0.2, 0.1, 0.1]", "size = [-0.2, 0.1, 0.1]", "size = [^-0.2", "tank.size[0]", "got -0.2", 1},
      {"size = [0.2, 0.1, 0.1]", "size = [-9007199254740993, 0.1, 0.1]", "size = [^-9007", "tank.size[0]",
       "got -9.0072e+15", 1},
      {"size = [0.2, 0.1, 0.1]", "size = [0.2, \"wide\", 0.1]", "size = [0.2, ^\"wide\"", "tank.size[1]",
       "got a string", 1},
      {"density = 2650.0", "density = 0", "density = ^0", "materials.sand.density", "expected a number > 0", 1},
      {"amplitude = 0.01", "amplitude = -0.01", "amplitude = ^-0.01", "tank.motion.amplitude",
       "expected a number >= 0 [m], got -0.01", 1},
      {"gravity = [0.0, 0.0, -9.81]", "gravity = [0.0, 0.0, inf]", "gravity = [0.0, 0.0, ^inf]", "run.gravity[2]",
       "expected a finite number [m/s^2], got inf", 1},
      // Integers out of range or of the wrong type.
      {"solid_substeps = 4", "solid_substeps = 0", "solid_substeps = ^0", "run.solid_substeps",
       "expected an integer in [1, 1000000], got 0", 1},
      {"solid_substeps = 4", "solid_substeps = 2.5", "solid_substeps = ^2.5", "run.solid_substeps",
       "got a number", 1},
      {"checkpoint_keep = 2", "checkpoint_keep = -1", "checkpoint_keep = ^-1", "output.checkpoint_keep",
       "expected an integer in [1, 1000000], got -1", 1},
      // [solids] hold_until: a time in [0, 1 day], not with fixed_to_tank.
      {"sort_every = 10", "sort_every = 10\nhold_until = -1.0", "hold_until = ^-1.0", "solids.hold_until",
       "expected a number in [0, 86400] [s], got -1", 1},
      {"sort_every = 10", "sort_every = 10\nfixed_to_tank = true\nhold_until = 2.0", "hold_until = ^2.0",
       "solids.hold_until", "fixed_to_tank already holds the grains for the whole run", 1},
      // [solids] fixed_below and a sphere's fixed: not with fixed_to_tank.
      {"sort_every = 10", "sort_every = 10\nfixed_to_tank = true\nfixed_below = 0.01", "fixed_below = ^0.01",
       "solids.fixed_below", "fixed_to_tank already holds every grain", 1},
      {"sort_every = 10", "sort_every = 10\nfixed_below = \"low\"", "fixed_below = ^\"low\"", "solids.fixed_below",
       "got a string", 1},
      {"size_class = 1", "size_class = 1\nfixed = 1", "fixed = ^1", "solids.spheres[0].fixed", "expected true or false, got an integer",
       1},
      {"size_class = 1", "size_class = 1001", "size_class = ^1001", "solids.spheres[0].size_class", "got 1001", 1},
      // Unknown keys: top level, misspelt table, nested, in an array of tables.
      {"[run]", "colour = \"red\"\n[run]", "^colour", "colour",
       "unknown key (known keys here: contact, coupling, fluid, materials, mean_flow, output, run, solids, tank)", 1},
      {"[output]", "[outptu]", "[^outptu]", "outptu", "unknown key", 1},
      {"end_time = 0.1", "end_tme = 0.1", "^end_tme", "run.end_tme", "unknown key (known keys here: dt, end_time", 2},
      {"end_time = 0.1", "end_tme = 0.1", "^[run]", "run.end_time", "missing required key; expected a number > 0", 2},
      {"amplitude = 0.01", "amplitud = 0.01", "^amplitud", "tank.motion.amplitud", "unknown key", 2},
      {"amplitude = 0.01", "amplitud = 0.01", "^[tank.motion]", "tank.motion.amplitude", "missing required key", 2},
      {"size_class = 1", "size_clas = 1", "^size_clas", "solids.spheres[0].size_clas", "unknown key", 1},
      // Missing required keys and tables (reported at the table that lacks them; the root table is line 1).
      {"dt = 1.0e-3\n", "", "^[run]", "run.dt", "missing required key; expected a number > 0 [s]", 1},
      {"size = [0.2, 0.1, 0.1]\n", "", "^[tank]", "tank.size", "missing required key; expected an array of 3", 1},
      {"density = 2650.0\n", "", "^[materials.sand]", "materials.sand.density", "missing required key", 1},
      {"position = [0.1, 0.05, 0.05]\n", "", "^[[solids.spheres]]", "solids.spheres[0].position",
       "missing required key", 1},
      {"[run]\nname = \"base\"\nend_time = 0.1\ndt = 1.0e-3\nsolid_substeps = 4\ngravity = [0.0, 0.0, -9.81]\n", "",
       "^# Base scene", "run", "missing required table [run]", 1},
      // Unknown material names.
      {"radius = 0.005\nmaterial = \"sand\"", "radius = 0.005\nmaterial = \"gravel\"", "material = ^\"gravel\"",
       "solids.spheres[0].material", "unknown material \"gravel\" (materials defined: glass, sand)", 1},
      {"radius = 0.005\nmaterial = \"sand\"", "radius = 0.005\nmaterial = \"\"", "material = ^\"\"",
       "solids.spheres[0].material", "unknown material \"\"", 1},
      {"wall_material = \"glass\"", "wall_material = \"steel\"", "wall_material = ^\"steel\"", "tank.wall_material",
       "unknown material \"steel\"", 1},
      // Wrong array lengths and shapes.
      {"size = [0.2, 0.1, 0.1]", "size = [0.2, 0.1]", "size = ^[0.2, 0.1]", "tank.size",
       "expected an array of 3 numbers [m], each a number > 0, got an array of 2 items", 1},
      {"gravity = [0.0, 0.0, -9.81]", "gravity = [0.0, 0.0, -9.81, 1.0]", "gravity = ^[", "run.gravity",
       "got an array of 4 items", 1},
      {"velocity = [0.0, 0.0, 1.0]", "velocity = 1.0", "velocity = ^1.0", "solids.spheres[0].velocity",
       "expected an array of 3 numbers [m/s], each a finite number, got a number", 1},
      // Invalid choices. An invalid kind must not make amplitude and frequency "unknown keys".
      {"kind = \"sinusoidal\"", "kind = \"circular\"", "kind = ^\"circular\"", "tank.motion.kind",
       "expected one of \"none\", \"sinusoidal\", \"table\", got \"circular\"", 1},
      {"kind = \"sinusoidal\"", "kind = 5", "kind = ^5", "tank.motion.kind", "expected a string, got an integer", 1},
      {"open_faces = [\"z_max\"]", "open_faces = [\"top\"]", "open_faces = [^\"top\"]", "tank.open_faces",
       "got \"top\"", 1},
      {"open_faces = [\"z_max\"]", "open_faces = [\"z_max\", \"z_max\"]", "\"z_max\", ^\"z_max\"", "tank.open_faces",
       "\"z_max\" is listed twice", 1},
      {"vtk_interval = 0.01", "vtk_interval = 0.01\nvtk_encoding = \"ascii\"", "vtk_encoding = ^\"ascii\"",
       "output.vtk_encoding", "expected one of \"appended\", \"inline\", got \"ascii\"", 1},
      {"vtk_interval = 0.01", "vtk_interval = 0.01\nvtk_precision = \"half\"", "vtk_precision = ^\"half\"",
       "output.vtk_precision", "expected one of \"single\", \"double\", got \"half\"", 1},
      {"direction = [1.0, 0.0, 0.0]", "direction = [0.0, 0.0, 0.0]", "direction = ^[", "tank.motion.direction",
       "expected a non-zero direction vector", 1},
      // Geometry. A bad tank size must not also make every grain "outside the tank".
      {"position = [0.1, 0.05, 0.05]", "position = [0.3, 0.05, 0.05]", "position = ^[0.3", "solids.spheres[0].position",
       "the sphere does not fit inside the tank", 1},
      {"position = [0.1, 0.05, 0.05]", "position = [0.196, 0.05, 0.05]", "position = ^[0.196",
       "solids.spheres[0].position", "does not fit inside the tank", 1},
      {"spacing = 0.01", "spacing = 0.005", "spacing = ^0.005", "solids.blocks[0].spacing",
       "spacing must be at least the sphere diameter (0.008 m)", 1},
      {"spacing = 0.01\nradius = 0.004", "spacing = 1e-7\nradius = 2e-7", "spacing = ^1e-7", "solids.blocks[0].spacing",
       "at least the sphere diameter (4e-07 m)", 1},
      {"spacing = 0.01\nradius = 0.004", "spacing = 1e-5\nradius = 4e-6", "spacing = ^1e-5", "solids.blocks[0].spacing",
       "more than 5e7 spheres", 1},
      {"max = [0.08, 0.08, 0.04]", "max = [0.01, 0.08, 0.04]", "max = ^[0.01", "solids.blocks[0].max",
       "every component of max must be >= the one of min", 1},
      {"min = [0.02, 0.02, 0.02]\nmax = [0.08, 0.08, 0.04]", "min = [0.5, 0.5, 0.5]\nmax = [0.6, 0.6, 0.6]",
       "min = ^[0.5", "solids.blocks[0].min", "the block places no sphere inside the tank", 1},
      {"size = [0.2, 0.1, 0.1]", "size = [0.2, 0.1, -0.1]", "size = [0.2, 0.1, ^-0.1]", "tank.size[2]", "got -0.1", 1},
      // TOML syntax errors, reported with their line; toml++ has no key for them ("(syntax)") and chooses the
      // column itself (often the end of the bad token), so only the line is checked for these.
      {"frequency = 2.0", "frequency = 2.0.0", "frequency = 2.0^.0", "(syntax)", "Error while parsing", 1},
      {"dt = 1.0e-3", "dt = 1e400", "dt = ^1e400", "(syntax)", "'1e400' could not be interpreted", 1},
      {"dt = 1.0e-3", "dt = 1.0e-3\ndt = 2.0e-3", "^dt = 2.0e-3", "(syntax)", "dt", 1},
      {"[tank.motion]", "[tank.motion", "[tank.motion^", "(syntax)", "Error while parsing", 1},
  };

  for (const BadScene& bad : cases) {
    const std::string text = replace_once(kBaseScene, bad.find, bad.replace);
    const TextPosition where = position_of(text, bad.at);
    const bool syntax = std::string_view(bad.key) == "(syntax)";
    const std::string prefix = "bad.toml:" + std::to_string(where.line) + ":" +
                               (syntax ? std::string() : std::to_string(where.column) + ": " + bad.key + ": ");
    const std::string after_prefix = syntax ? ": (syntax): " : "";  // after the column toml++ chose
    CAPTURE(text);
    const std::vector<std::string> problems = problems_of(text);
    const bool found = std::any_of(problems.begin(), problems.end(), [&](const std::string& line) {
      if (line.rfind(prefix, 0) != 0) return false;
      std::size_t message_from = prefix.size();
      if (syntax) {
        const std::size_t column_end = line.find_first_not_of("0123456789", prefix.size());
        if (column_end == prefix.size() || line.compare(column_end, after_prefix.size(), after_prefix) != 0)
          return false;
        message_from = column_end + after_prefix.size();
      }
      return line.find(bad.message, message_from) != std::string::npos;
    });
    CHECK_MESSAGE(found, "no problem starts with \"", prefix, after_prefix, "\" and mentions \"",
                  std::string(bad.message), "\"; got:\n", joined(problems));
    CHECK_MESSAGE(problems.size() == bad.problems, "expected ", bad.problems, " problem(s), got:\n", joined(problems));
  }
}

TEST_CASE("several problems in one scene are all reported, each at its own line") {
  std::string text(kBaseScene);
  text = replace_once(text, "dt = 1.0e-3", "dt = \"fast\"");
  text = replace_once(text, "open_faces = [\"z_max\"]", "open_faces = [\"top\"]");
  text = replace_once(text, "amplitude = 0.01", "amplitud = 0.01");
  text = replace_once(text, "radius = 0.005\nmaterial = \"sand\"", "radius = 0.005\nmaterial = \"gravel\"");
  text = replace_once(text, "checkpoint_keep = 2", "checkpoint_keep = 0");
  const std::vector<std::string> problems = problems_of(text);
  CAPTURE(joined(problems));

  const std::vector<std::pair<std::string, std::string>> expected = {
      {"dt = ^\"fast\"", "run.dt"},
      {"open_faces = [^\"top\"]", "tank.open_faces"},
      {"^amplitud", "tank.motion.amplitud"},
      {"^[tank.motion]", "tank.motion.amplitude"},
      {"material = ^\"gravel\"", "solids.spheres[0].material"},
      {"checkpoint_keep = ^0", "output.checkpoint_keep"},
  };
  CHECK(problems.size() == expected.size());
  for (const auto& [at, key] : expected) {
    const TextPosition where = position_of(text, at);
    const std::string prefix =
        "bad.toml:" + std::to_string(where.line) + ":" + std::to_string(where.column) + ": " + key + ": ";
    CHECK_MESSAGE(std::any_of(problems.begin(), problems.end(),
                              [&](const std::string& line) { return line.rfind(prefix, 0) == 0; }),
                  "missing ", prefix);
  }

  // what() is the list itself, one problem per line, so the command line can print it as it is.
  try {
    riffle::parse_scene(text, "bad.toml");
    FAIL("accepted");
  } catch (const riffle::SceneError& error) {
    std::string lines;
    for (std::size_t k = 0; k < error.problems().size(); ++k) lines += (k ? "\n" : "") + error.problems()[k];
    CHECK(std::string(error.what()) == lines);
  }
}

TEST_CASE("[output] vtk_encoding, vtk_precision, vtk_dummy_particles: unset, raw appended single precision without dummies") {
  const riffle::Model plain = riffle::parse_scene(std::string(kBaseScene), "base.toml");
  CHECK(plain.output.vtk_encoding == riffle::OutputModel::VtkEncoding::kAppended);
  CHECK(plain.output.vtk_precision == riffle::OutputModel::VtkPrecision::kSingle);
  const riffle::Model exact = riffle::parse_scene(
      replace_once(kBaseScene, "vtk_interval = 0.01",
                   "vtk_interval = 0.01\nvtk_encoding = \"inline\"\nvtk_precision = \"double\""),
      "exact.toml");
  CHECK(exact.output.vtk_encoding == riffle::OutputModel::VtkEncoding::kInline);
  CHECK(exact.output.vtk_precision == riffle::OutputModel::VtkPrecision::kDouble);
  CHECK_FALSE(plain.output.vtk_dummy_particles);
  CHECK(riffle::parse_scene(replace_once(kBaseScene, "vtk_interval = 0.01", "vtk_interval = 0.01\nvtk_dummy_particles = true"),
                            "dummies.toml")
            .output.vtk_dummy_particles);
}

TEST_CASE("valid edge values are accepted") {
  SUBCASE("an empty list of spheres") {
    const std::string text = replace_once(
        kBaseScene,
        "[[solids.spheres]]\nposition = [0.1, 0.05, 0.05]\nvelocity = [0.0, 0.0, 1.0]\n"
        "angular_velocity = [0.0, 5.0, 0.0]\nradius = 0.005\nmaterial = \"sand\"\nsize_class = 1\n",
        "spheres = []\n");
    CHECK(riffle::scene_spheres(riffle::parse_scene(text, "edge.toml")).size() == kBaseGrains - 1);
  }
  SUBCASE("integers where numbers are expected, also beyond 2^53") {
    std::string text = replace_once(kBaseScene, "size = [0.2, 0.1, 0.1]", "size = [1, 9007199254740993, 1]");
    text = replace_once(text, "density = 2650.0", "density = 2650");
    const riffle::Model model = riffle::parse_scene(text, "edge.toml");
    CHECK(model.tank.size.x() == 1.0);
    CHECK(model.tank.size.y() == 9007199254740992.0);
    CHECK(model.materials.size() == 2);
  }
  SUBCASE("a direction with huge or tiny components is normalised, not zeroed") {
    for (const char* direction : {"[1e300, 1e300, 0.0]", "[1e-200, 0.0, 0.0]", "[0.0, -3.0, 4.0]"}) {
      CAPTURE(direction);
      const std::string text =
          replace_once(kBaseScene, "direction = [1.0, 0.0, 0.0]", std::string("direction = ") + direction);
      const riffle::Vec3 unit = riffle::parse_scene(text, "edge.toml").tank.motion.direction;
      CHECK(std::isfinite(unit.norm()));
      CHECK(unit.norm() == doctest::Approx(1.0).epsilon(1e-12));
    }
  }
  SUBCASE("a block row whose spheres touch a wall is kept, one that overlaps it is skipped") {
    // 0.0025 + 7 x 0.005 lands one ulp past 0.04 - 0.0025: touching within rounding still fits.
    const std::string block = "min = [0.02, 0.02, 0.02]\nmax = [0.08, 0.08, 0.04]\nspacing = 0.01\nradius = 0.004\n";
    std::string touching = replace_once(kBaseScene, "size = [0.2, 0.1, 0.1]", "size = [0.2, 0.04, 0.1]");
    touching = replace_once(touching, "position = [0.1, 0.05, 0.05]", "position = [0.1, 0.02, 0.05]");
    touching = replace_once(touching, block,
                            "min = [0.0825, 0.0025, 0.0025]\nmax = [0.1575, 0.0375, 0.0375]\nspacing = 0.005\n"
                            "radius = 0.0025\n");
    const riffle::Model touching_model = riffle::parse_scene(touching, "edge.toml");
    CHECK(riffle::scene_spheres(touching_model).size() == 16 * 8 * 8 + 1);
    CHECK(riffle::scene_sphere_count(touching_model.solids) == 16 * 8 * 8 + 1);  // counted as generated
    // Shifted by 10 nm across y, the last row overlaps the wall by far more than rounding.
    std::string overlapping = replace_once(touching, "min = [0.0825, 0.0025,", "min = [0.0825, 0.00250001,");
    overlapping = replace_once(overlapping, "max = [0.1575, 0.0375,", "max = [0.1575, 0.03750001,");
    const riffle::Model overlapping_model = riffle::parse_scene(overlapping, "edge.toml");
    CHECK(riffle::scene_spheres(overlapping_model).size() == 16 * 7 * 8 + 1);
    CHECK(riffle::scene_sphere_count(overlapping_model.solids) == 16 * 7 * 8 + 1);
  }
  SUBCASE("kind = \"none\" needs no amplitude or frequency") {
    const std::string text = replace_once(kBaseScene,
                                          "kind = \"sinusoidal\"\ndirection = [1.0, 0.0, 0.0]\namplitude = 0.01\n"
                                          "frequency = 2.0\nramp_time = 0.5\n",
                                          "kind = \"none\"\n");
    CHECK(riffle::parse_scene(text, "edge.toml").tank.motion.kind == riffle::TankMotionModel::Kind::kNone);
  }
}

TEST_CASE("an unreadable scene file gives a SceneError naming the path") {
  const std::filesystem::path directory =
      std::filesystem::temp_directory_path() / ("riffle_scene_validation_" + std::to_string(::getpid()));
  std::filesystem::create_directories(directory);
  // Removes the directory also when a REQUIRE ends a subcase early.
  struct RemoveOnExit {
    std::filesystem::path path;
    ~RemoveOnExit() {
      std::error_code ignored;
      std::filesystem::remove_all(path, ignored);
    }
  } remove_on_exit{directory};

  auto problems_of_file = [](const std::string& path) -> std::vector<std::string> {
    try {
      riffle::load_scene_file(path);
    } catch (const riffle::SceneError& error) {
      return error.problems();
    } catch (const std::exception& error) {
      FAIL("load_scene_file threw something other than SceneError: ", error.what());
    }
    FAIL("load_scene_file accepted ", path);
    return {};
  };

  SUBCASE("a file that does not exist") {
    const std::string path = (directory / "no_such_scene.toml").string();
    const std::vector<std::string> problems = problems_of_file(path);
    REQUIRE(problems.size() == 1);
    CHECK(problems[0].rfind(path + ": ", 0) == 0);
    CHECK(problems[0].find("cannot open") != std::string::npos);
  }
  SUBCASE("a directory (opens, but reads as nothing: must not be reported as a scene without tables)") {
    const std::vector<std::string> problems = problems_of_file(directory.string());
    REQUIRE(problems.size() == 1);
    CHECK(problems[0].rfind(directory.string() + ": ", 0) == 0);
    CHECK(problems[0].find("directory") != std::string::npos);
  }
  SUBCASE("a readable file names itself in every problem") {
    const std::string path = (directory / "bad.toml").string();
    std::ofstream(path) << replace_once(kBaseScene, "dt = 1.0e-3", "dt = -1");
    const std::vector<std::string> problems = problems_of_file(path);
    REQUIRE(problems.size() == 1);
    const TextPosition where = position_of(replace_once(kBaseScene, "dt = 1.0e-3", "dt = -1"), "dt = ^-1");
    CHECK(problems[0].rfind(path + ":" + std::to_string(where.line) + ":" + std::to_string(where.column) +
                                ": run.dt: ",
                            0) == 0);
  }
}

TEST_CASE("the shipped scenes load") {
  std::vector<std::filesystem::path> scenes;
  for (const auto& entry : std::filesystem::directory_iterator(RIFFLE_SOURCE_DIR "/scenes/"))
    if (entry.path().extension() == ".toml") scenes.push_back(entry.path());
  REQUIRE(!scenes.empty());
  for (const std::filesystem::path& scene : scenes) {
    CAPTURE(scene.string());
    try {
      const riffle::Model model = riffle::load_scene_file(scene.string());
      CHECK(model.dt > 0.0);
    } catch (const riffle::SceneError& error) {
      // A scene that starts from another run's end state (scenes/dry_shaken_tank.toml) is valid only once that run
      // has been made; on a fresh clone the one acceptable problem is the missing checkpoint, named at its key.
      const auto& problems = error.problems();
      const bool only_missing_start = problems.size() == 1 &&
                                      problems[0].find(": solids.initial_state: ") != std::string::npos &&
                                      problems[0].find("cannot open the checkpoint") != std::string::npos;
      if (!only_missing_start) FAIL_CHECK(error.what());
    }
  }
}

TEST_CASE("free_fall_box.toml is read as written") {
  const std::string path = RIFFLE_SOURCE_DIR "/scenes/free_fall_box.toml";
  const riffle::Model model = riffle::load_scene_file(path);
  std::ifstream file(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  CHECK(model.scene_text == text);
  CHECK(model.scene_file == path);

  CHECK(model.name == "free_fall_box");
  CHECK(model.end_time == 0.25);
  CHECK(model.dt == 1.0e-3);
  CHECK(model.solid_substeps == 10);
  CHECK(model.solid_dt() == doctest::Approx(1.0e-4));
  CHECK(model.gravity == riffle::Vec3(0.0, 0.0, -9.81));

  REQUIRE(model.materials.size() == 2);
  auto material_index = [&](const std::string& name) {
    for (std::size_t k = 0; k < model.materials.size(); ++k)
      if (model.materials[k].name == name) return static_cast<std::int32_t>(k);
    FAIL("no material ", name);
    return std::int32_t{-1};
  };
  const std::int32_t grain = material_index("grain");
  CHECK(model.materials[static_cast<std::size_t>(grain)].density == 1318.0);
  CHECK(model.materials[static_cast<std::size_t>(material_index("glass"))].density == 2500.0);

  CHECK(model.tank.size == riffle::Vec3(0.24, 0.16, 0.20));
  CHECK(model.tank.origin == riffle::Vec3::Zero());
  CHECK(model.tank.open_faces == std::vector<std::string>{"z_max"});
  CHECK(model.tank.wall_material == material_index("glass"));
  CHECK(model.tank.motion.kind == riffle::TankMotionModel::Kind::kSinusoidal);
  CHECK(model.tank.motion.direction == riffle::Vec3::UnitX());
  CHECK(model.tank.motion.amplitude == 0.01);
  CHECK(model.tank.motion.frequency == 1.7);
  CHECK(model.tank.motion.ramp_time == 0.5882);
  CHECK(model.solids.enabled);
  CHECK(model.solids.sort_every == 50);
  CHECK(model.output.vtk_interval == 0.01);
  CHECK(model.output.checkpoint_interval == 0.05);

  // The block spans [0.02, 0.22] x [0.02, 0.14] x [0.02, 0.06] with spacing 0.01: 21 x 13 x 5 grains, all inside
  // the 0.24 x 0.16 x 0.20 tank with room for their 2.5 mm radius; plus the one explicit sphere.
  constexpr std::size_t kBlockGrains = 21 * 13 * 5;
  const std::vector<riffle::SphereSpec> spheres = riffle::scene_spheres(model);
  REQUIRE(spheres.size() == kBlockGrains + 1);
  std::size_t block_grains = 0;
  std::size_t explicit_spheres = 0;
  riffle::Vec3 low = riffle::Vec3::Constant(1e9);
  riffle::Vec3 high = riffle::Vec3::Constant(-1e9);
  for (const riffle::SphereSpec& sphere : spheres) {
    CHECK(sphere.material == grain);
    if (sphere.radius == 0.0025) {
      ++block_grains;
      CHECK(sphere.velocity == riffle::Vec3(0.0, 0.0, 1.2));
      CHECK(sphere.size_class == 0);
      low = low.cwiseMin(sphere.position);
      high = high.cwiseMax(sphere.position);
    } else {
      ++explicit_spheres;
      CHECK(sphere.radius == 0.0075);
      CHECK(sphere.position == riffle::Vec3(0.12, 0.08, 0.10));
      CHECK(sphere.velocity == riffle::Vec3(0.05, 0.0, 0.9));
      CHECK(sphere.angular_velocity == riffle::Vec3(0.0, 10.0, 0.0));
      CHECK(sphere.size_class == 2);
    }
  }
  CHECK(block_grains == kBlockGrains);
  CHECK(explicit_spheres == 1);
  CHECK(low.isApprox(riffle::Vec3(0.02, 0.02, 0.02), 1e-12));
  CHECK(high.isApprox(riffle::Vec3(0.22, 0.14, 0.06), 1e-12));
}

namespace {

/// Why `model` is not sane, or "" if it is: what any accepted scene must guarantee to the engine.
std::string insane(const riffle::Model& model) {
  auto finite = [](const riffle::Vec3& v) { return v.allFinite(); };
  if (!(model.dt > 0.0) || !std::isfinite(model.dt)) return "dt";
  if (!(model.end_time > 0.0) || !std::isfinite(model.end_time)) return "end_time";
  if (model.solid_substeps < 1) return "solid_substeps";
  if (!finite(model.gravity)) return "gravity";
  if (model.materials.empty()) return "no materials";
  for (const riffle::Material& material : model.materials)
    if (!(material.density > 0.0) || !std::isfinite(material.density)) return "density";
  const auto material_count = static_cast<std::int32_t>(model.materials.size());
  const riffle::TankModel& tank = model.tank;
  if (!finite(tank.size) || !(tank.size.array() > 0.0).all()) return "tank.size";
  if (!finite(tank.origin)) return "tank.origin";
  if (tank.wall_material < 0 || tank.wall_material >= material_count) return "tank.wall_material";
  if (!(tank.domain_margin >= 0.0) || !std::isfinite(tank.domain_margin)) return "tank.domain_margin";
  if (tank.motion.kind == riffle::TankMotionModel::Kind::kSinusoidal) {
    if (!finite(tank.motion.direction) || std::abs(tank.motion.direction.norm() - 1.0) > 1e-12)
      return "tank.motion.direction";
    if (!(tank.motion.amplitude >= 0.0) || !std::isfinite(tank.motion.amplitude)) return "tank.motion.amplitude";
    if (!(tank.motion.frequency > 0.0) || !std::isfinite(tank.motion.frequency)) return "tank.motion.frequency";
    if (!(tank.motion.ramp_time >= 0.0) || !std::isfinite(tank.motion.ramp_time)) return "tank.motion.ramp_time";
    if (!(std::abs(tank.motion.phase) <= 2.0 * 3.14159265358979323846 + 1e-12)) return "tank.motion.phase";
    if (!(tank.motion.start_time >= 0.0) || !std::isfinite(tank.motion.start_time)) return "tank.motion.start_time";
  }
  for (const riffle::SphereSpec& sphere : riffle::scene_spheres(model)) {
    if (!(sphere.radius > 0.0) || !std::isfinite(sphere.radius)) return "sphere radius";
    if (!finite(sphere.position) || !finite(sphere.velocity) || !finite(sphere.angular_velocity))
      return "sphere state";
    if (sphere.material < 0 || sphere.material >= material_count) return "sphere material";
    if (sphere.size_class < 0) return "sphere size_class";
    // The reader promises every initial sphere fits in the tank at rest.
    if (((sphere.position.array() - sphere.radius) < tank.origin.array()).any() ||
        ((sphere.position.array() + sphere.radius) > (tank.origin + tank.size).array()).any())
      return "sphere outside the tank";
  }
  const riffle::OutputModel& output = model.output;
  if (!(output.vtk_interval >= 0.0) || !std::isfinite(output.vtk_interval)) return "output.vtk_interval";
  if (!(output.checkpoint_interval >= 0.0) || !std::isfinite(output.checkpoint_interval))
    return "output.checkpoint_interval";
  if (output.checkpoint_keep < 1 || output.diagnostics_every < 1) return "output counts";
  return "";
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::string line;
  std::istringstream stream(text);
  while (std::getline(stream, line)) lines.push_back(line);
  return lines;
}

std::string unlines(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += line + "\n";
  return text;
}

/// One random edit of the kinds a user (or a bad merge) makes; deterministic given `random`.
std::string mutate(std::string text, std::mt19937& random) {
  auto pick = [&](std::size_t count) { return std::uniform_int_distribution<std::size_t>(0, count - 1)(random); };
  static const std::string kSpecial = "[]=\"#.,\n";
  static const std::vector<std::string> kNumbers = {"nan",  "-nan",   "inf",  "-inf", "+inf", "1e400", "-1e400",
                                                    "-0",   "0",      "-0.0", "-1",   "1e300", "-1e300", "1e-300",
                                                    "1e-320", "9223372036854775807", "9007199254740993", "0x10",
                                                    "1_000", "\"1\"", "true", "[]"};
  switch (pick(5)) {
    case 0:  // delete a character
      if (!text.empty()) text.erase(pick(text.size()), 1);
      break;
    case 1: {  // insert a printable or structurally meaningful character
      const char c = pick(2) ? static_cast<char>(' ' + pick(95)) : kSpecial[pick(kSpecial.size())];
      text.insert(pick(text.size() + 1), 1, c);
      break;
    }
    case 2: {  // duplicate a line
      std::vector<std::string> lines = lines_of(text);
      if (lines.empty()) break;
      const std::size_t k = pick(lines.size());
      lines.insert(lines.begin() + static_cast<std::ptrdiff_t>(k), lines[k]);
      text = unlines(lines);
      break;
    }
    case 3: {  // swap two lines
      std::vector<std::string> lines = lines_of(text);
      if (lines.size() < 2) break;
      std::swap(lines[pick(lines.size())], lines[pick(lines.size())]);
      text = unlines(lines);
      break;
    }
    default: {  // replace a number with an extreme or invalid token
      auto digit = [&](std::size_t k) { return k < text.size() && std::isdigit(static_cast<unsigned char>(text[k])); };
      std::vector<std::pair<std::size_t, std::size_t>> numbers;  // start, length
      for (std::size_t k = 0; k < text.size();) {
        const bool starts = digit(k) || (text[k] == '-' && digit(k + 1));
        // A digit right after a letter or an underscore belongs to a name, not to a number.
        if (!starts || (k > 0 && (std::isalnum(static_cast<unsigned char>(text[k - 1])) || text[k - 1] == '_'))) {
          ++k;
          continue;
        }
        std::size_t end = k + 1;
        while (end < text.size() && (digit(end) || std::string_view(".eE+-").find(text[end]) != std::string_view::npos))
          ++end;
        numbers.emplace_back(k, end - k);
        k = end;
      }
      if (numbers.empty()) break;
      const auto [start, length] = numbers[pick(numbers.size())];
      text.replace(start, length, kNumbers[pick(kNumbers.size())]);
      break;
    }
  }
  return text;
}

}  // namespace

TEST_CASE("fuzz: mutated scenes give a sane Model or a SceneError, nothing else") {
  std::ifstream file(RIFFLE_SOURCE_DIR "/scenes/free_fall_box.toml", std::ios::binary);
  const std::string shipped((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  REQUIRE(!shipped.empty());
  const std::vector<std::string> seeds = {std::string(kBaseScene), shipped};

  std::mt19937 random(20240611);
  constexpr int kTrials = 4000;
  int accepted = 0;
  int rejected = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    std::string text = seeds[static_cast<std::size_t>(trial) % seeds.size()];
    const int edits = 1 + static_cast<int>(random() % 3);
    for (int k = 0; k < edits; ++k) text = mutate(std::move(text), random);
    const int line_count = static_cast<int>(std::count(text.begin(), text.end(), '\n')) + 1;
    try {
      const riffle::Model model = riffle::parse_scene(text, "fuzz.toml");
      ++accepted;
      const std::string why = insane(model);
      if (!why.empty()) FAIL_CHECK("trial ", trial, ": accepted a scene with a bad ", why, ":\n", text);
      if (model.scene_text != text) FAIL_CHECK("trial ", trial, ": scene_text is not the text parsed");
    } catch (const riffle::SceneError& error) {
      ++rejected;
      if (error.problems().empty()) FAIL_CHECK("trial ", trial, ": SceneError without problems:\n", text);
      for (const std::string& line : error.problems()) {
        const std::optional<ProblemLine> problem = split_problem(line, "fuzz.toml");
        if (!problem || problem->line < 1 || problem->line > line_count || problem->column < 1)
          FAIL_CHECK("trial ", trial, ": malformed problem line \"", line, "\" for:\n", text);
      }
    } catch (const std::exception& error) {
      FAIL_CHECK("trial ", trial, ": parse_scene threw ", error.what(), " for:\n", text);
    } catch (...) {
      FAIL_CHECK("trial ", trial, ": parse_scene threw a non-exception for:\n", text);
    }
  }
  MESSAGE("fuzz: ", accepted, " accepted, ", rejected, " rejected");
  // Both outcomes must be common, or the mutations are not exercising the validator.
  CHECK(accepted > kTrials / 20);
  CHECK(rejected > kTrials / 4);
}

TEST_CASE("a long run checkpoints by default: output.checkpoint_interval unset gives end_time / 10") {
  using riffle::default_checkpoint_interval;
  // At least 1000 steps of run.dt is a long run; shorter ones write a checkpoint only at the end (and on a signal).
  CHECK(default_checkpoint_interval(1.0, 1.0e-3) == 0.1);
  CHECK(default_checkpoint_interval(58.8235, 1.0e-3) == 58.8235 / 10.0);
  CHECK(default_checkpoint_interval(0.999, 1.0e-3) == 0.0);
  CHECK(default_checkpoint_interval(0.6, 1.0e-3) == 0.0);  // scenes/dam_break.toml: 600 steps
  const auto scene = [](const std::string& end_time, const std::string& output) {
    const std::string text = replace_once(replace_once(kBaseScene, "end_time = 0.1\n", "end_time = " + end_time + "\n"),
                                          "checkpoint_interval = 0.05\n", output);
    return riffle::parse_scene(text, "long.toml");
  };
  CHECK(scene("2.0", "").output.checkpoint_interval == 0.2);
  CHECK(scene("0.5", "").output.checkpoint_interval == 0.0);
  // A scene that sets the key keeps it, 0 included.
  CHECK(scene("2.0", "checkpoint_interval = 0\n").output.checkpoint_interval == 0.0);
  CHECK(scene("2.0", "checkpoint_interval = 0.3\n").output.checkpoint_interval == 0.3);
}
