// The [fluid] scene table and the initial MPS particles: defaults, a fully specified example, every validation
// problem at its file:line:column and key, and the initial lattice against the closed forms of fluid_layout.hpp.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "engine/setup/fluid_layout.hpp"
#include "engine/setup/initial_state.hpp"
#include "engine/scene/scene.hpp"
#include "systems/physics/geometry/tank_kinematics.hpp"
#include "systems/physics/mps/mps_common.hpp"
#include "tests/support/test_support.hpp"
#include "systems/physics/mps/hypre_pressure_solver.hpp"
#include "tests/support/scene_builder.hpp"

using namespace riffle;
using riffle::test::SceneBuilder;

namespace {

using test::joined;

/// "file:line:column: " of the character marked '^' in `needle` (default its first), which occurs once in `text`.
std::string marked_location(const std::string& text, const std::string& needle, const std::string& file) {
  return test::location(file, text, needle);
}

using test::problems_of;
using test::replace_once;


std::size_t count_kind(const FluidParticles& particles, FluidKind kind) {
  return static_cast<std::size_t>(
      std::count(particles.kind.begin(), particles.kind.end(), static_cast<std::int32_t>(kind)));
}

/// Wall and dummy particles of a box tank by the closed form of tank_wall_layout: count(L) = prod_a (n_a + L_a^- +
/// L_a^+) - prod_a n_a, with `layers` beyond each closed face.
std::size_t shell_count(const std::array<double, 3>& cells, const std::array<bool, 6>& closed, double layers) {
  double outer = 1.0, inner = 1.0;
  for (std::size_t a = 0; a < 3; ++a) {
    outer *= cells[a] + (closed[2 * a] ? layers : 0.0) + (closed[2 * a + 1] ? layers : 0.0);
    inner *= cells[a];
  }
  return static_cast<std::size_t>(outer - inner);
}

}  // namespace

TEST_CASE("a minimal fluid table gets the documented defaults") {
  const Model model = test::fluid_model();  // [fluid] sets only spacing and the boxes
  const FluidModel& fluid = model.fluid;
  CHECK(fluid.enabled);
  CHECK_FALSE(model.solids.enabled);
  CHECK(fluid.spacing == 0.005);
  CHECK(fluid.effective_radius_ratio == 2.4);
  CHECK(fluid.density == 1000.0);
  CHECK(fluid.kinematic_viscosity == 1.0e-6);
  CHECK(fluid.tank_walls);
  CHECK(fluid.clamp_negative_pressure);
  CHECK(fluid.surface_threshold == 0.93);
  CHECK(fluid.density_relaxation_rate == 48.0);
  CHECK(fluid.compressibility == 1.0e-9);
  CHECK(fluid.sound_speed == 0.0);  // incompressible: the quasi-compressible rows are off
  CHECK(fluid.courant == 0.2);
  CHECK(fluid.diffusion_number == 0.2);
  CHECK(fluid.min_dt == 1.0e-6);
  CHECK(fluid.solver_tolerance == 1.0e-8);
  CHECK(fluid.solver_max_iterations == 2000);
  CHECK(fluid.neighbour_skin_ratio == 0.3);
  CHECK(fluid.narrow_neighbour_skin_ratio == 0.1);
  CHECK(fluid.escape == FluidModel::EscapePolicy::kRemove);
  CHECK(fluid.escape_distance == std::numeric_limits<double>::infinity());
  CHECK(fluid.escape_fraction_limit == 0.01);
  CHECK(fluid.schemes.higher_order_source);
  CHECK(fluid.schemes.error_compensating_source);
  CHECK(fluid.schemes.higher_order_laplacian);
  CHECK(fluid.schemes.gradient_correction);
  CHECK(fluid.schemes.dynamic_stabilisation);
  REQUIRE(fluid.boxes.size() == 2);
  CHECK(fluid.boxes[0].velocity == Vec3(0.1, 0.0, -0.2));
  CHECK(fluid.boxes[1].velocity == Vec3::Zero());
  CHECK(fluid.wall_boxes.size() == 2);
  CHECK_FALSE(parse_scene(test::small_scene_text(), "small.toml").fluid.enabled);
}

TEST_CASE("every fluid key is read into the model") {
  const std::string text = replace_once(test::fluid_scene_text(), "[fluid]\nspacing = 0.005\n", SceneBuilder()
      .fluid({.spacing = 0.005, .kinematic_viscosity = 1.004e-6, .clamp_negative_pressure = false})
      .set("effective_radius", 3.1).set("density", 998.2).set("tank_walls", false).set("surface_threshold", 0.97)
      .set("density_relaxation_rate", 10.0).set("compressibility", 0.0).set("sound_speed", 20.0).set("courant", 0.1)
      .set("diffusion_number", 0.125).set("min_dt", 1e-7).set("solver_tolerance", 1e-10)
      .set("solver_max_iterations", 500).set("neighbour_skin", 0.0).set("escape_distance", 0.05)
      .set("escape_fraction_limit", 0.2)
      .table("fluid.schemes").set("hs", false).set("ecs", true).set("hl", false).set("gc", true).set("ds", false)
      .toml());
  const FluidModel fluid = parse_scene(text, "full.toml").fluid;
  CHECK(fluid.effective_radius_ratio == 3.1);
  CHECK(fluid.effective_radius() == doctest::Approx(0.0155).epsilon(1e-14));
  // The MPS constants are derived once, from these l0 and r_e / l0, as the lattice sums give them.
  const LatticeConstants lattice = lattice_constants(3, 0.005, fluid.effective_radius());
  CHECK(mps_constants(fluid).effective_radius == fluid.effective_radius());
  CHECK(mps_constants(fluid).reference_density == lattice.number_density);
  CHECK(mps_constants(fluid).laplacian_lambda == lattice.laplacian_lambda);
  CHECK(mps_constants(fluid).particle_volume == 0.005 * 0.005 * 0.005);
  // A model changed after is refused rather than run with the constants of its old spacing.
  FluidModel changed = fluid;
  changed.spacing = 0.004;
  CHECK_THROWS_AS(mps_constants(changed), std::logic_error);
  fill_mps_constants(changed);
  CHECK(mps_constants(changed).particle_volume == 0.004 * 0.004 * 0.004);
  changed.effective_radius_ratio = 2.4;
  CHECK_THROWS_AS(mps_constants(changed), std::logic_error);
  CHECK(fluid.density == 998.2);
  CHECK(fluid.kinematic_viscosity == 1.004e-6);
  CHECK_FALSE(fluid.tank_walls);
  CHECK_FALSE(fluid.clamp_negative_pressure);
  CHECK(fluid.surface_threshold == 0.97);
  CHECK(fluid.density_relaxation_rate == 10.0);
  CHECK(fluid.compressibility == 0.0);
  CHECK(fluid.sound_speed == 20.0);
  CHECK(fluid.courant == 0.1);
  CHECK(fluid.diffusion_number == 0.125);
  CHECK(fluid.min_dt == 1e-7);
  CHECK(fluid.solver_tolerance == 1e-10);
  CHECK(fluid.solver_max_iterations == 500);
  CHECK(fluid.neighbour_skin_ratio == 0.0);
  CHECK(fluid.narrow_neighbour_skin_ratio == 0.0);  // the narrow skin's default never exceeds the skin
  CHECK(fluid.escape == FluidModel::EscapePolicy::kRemove);
  CHECK(fluid.escape_distance == 0.05);
  CHECK(fluid.escape_fraction_limit == 0.2);
  CHECK(parse_scene(replace_once(test::fluid_scene_text(), "spacing = 0.005\n", "spacing = 0.005\nescape = \"stop\"\n"),
                    "stop.toml")
            .fluid.escape == FluidModel::EscapePolicy::kStop);
  CHECK_FALSE(fluid.schemes.higher_order_source);
  CHECK(fluid.schemes.error_compensating_source);
  CHECK_FALSE(fluid.schemes.higher_order_laplacian);
  CHECK(fluid.schemes.gradient_correction);
  CHECK_FALSE(fluid.schemes.dynamic_stabilisation);
  CHECK_FALSE(fluid.schemes.conservative_gradient);
  // The conservative gradient turns GC off unless gc is given (and refused true: the bad-table case below).
  // The sealed fluid scene (no open face) with these [fluid.schemes] keys.
  const auto sealed_schemes = [](const std::string& keys) {
    return parse_scene(replace_once(replace_once(test::fluid_scene_text(), "open_faces = [\"z_max\"]\n", ""),
                                "spacing = 0.005\n", "spacing = 0.005\n[fluid.schemes]\n" + keys),
                       "sealed.toml")
        .fluid.schemes;
  };
  const FluidSchemes conservative = sealed_schemes("conservative_gradient = true\n");
  CHECK(conservative.conservative_gradient);
  CHECK_FALSE(conservative.gradient_correction);
  CHECK(conservative.grain_gradient == FluidSchemes::GrainGradient::kApplied);  // the grains sample the applied gradient unless told
  const FluidSchemes corrected = sealed_schemes("conservative_gradient = true\ngrain_gradient = \"corrected\"\n");
  CHECK(corrected.grain_gradient == FluidSchemes::GrainGradient::kCorrected);
}

TEST_CASE("bad fluid tables are rejected at file, line, column and key") {
  struct BadFluid {
    const char* find;     // text of the fluid scene to change (must occur once)
    const char* replace;  // what it becomes
    const char* at;       // unique text of the changed scene where the problem is reported; '^' marks the column
    const char* key;
    const char* message;  // fragment of the message
  };
  const std::string first_box = "low = [0.1, -0.01, 0.0]\nhigh = [0.12, 0.01, 0.015]";
  const std::vector<BadFluid> cases = {
      {"spacing = 0.005\n", "", "^[fluid]", "fluid.spacing", "missing required key; expected a number > 0 [m]"},
      {"spacing = 0.005", "spacing = -0.005", "spacing = ^-0.005", "fluid.spacing", "got -0.005"},
      {"spacing = 0.005", "spacing = 0.005\neffective_radius = 1.9", "effective_radius = ^1.9",
       "fluid.effective_radius", "expected a number in [2, 4] [1], got 1.9"},
      {"spacing = 0.005", "spacing = 0.005\neffective_radius = 4.5", "effective_radius = ^4.5",
       "fluid.effective_radius", "got 4.5"},
      {"spacing = 0.005", "spacing = 0.005\nsurface_threshold = 1.0", "surface_threshold = ^1.0",
       "fluid.surface_threshold", "expected a number in (0.5, 1) [1], got 1"},
      {"spacing = 0.005", "spacing = 0.005\ncourant = 0.6", "courant = ^0.6", "fluid.courant",
       "expected a number in (0, 0.5] [1]"},
      {"spacing = 0.005", "spacing = 0.005\nkinematic_viscosity = -1e-6", "kinematic_viscosity = ^-1e-6",
       "fluid.kinematic_viscosity", "expected a number >= 0 [m^2/s]"},
      {"spacing = 0.005", "spacing = 0.005\ndensity_relaxation_rate = -1", "density_relaxation_rate = ^-1",
       "fluid.density_relaxation_rate", "expected a number >= 0 [1/s]"},
      {"spacing = 0.005", "spacing = 0.005\nsound_speed = -5", "sound_speed = ^-5", "fluid.sound_speed",
       "expected a number >= 0 [m/s]"},
      {"spacing = 0.005", "spacing = 0.005\nsound_speed = \"fast\"", "sound_speed = ^\"fast\"", "fluid.sound_speed",
       "expected a number >= 0 [m/s], got a string"},
      {"spacing = 0.005", "spacing = 0.005\nsolver_tolerance = 0", "solver_tolerance = ^0", "fluid.solver_tolerance",
       "expected a number in (0, 1) [1]"},
      {"spacing = 0.005", "spacing = 0.005\nsolver_max_iterations = 0", "solver_max_iterations = ^0",
       "fluid.solver_max_iterations", "expected an integer in [1, 100000000]"},
      {"spacing = 0.005", "spacing = 0.005\nneighbour_skin = 2.5", "neighbour_skin = ^2.5", "fluid.neighbour_skin",
       "expected a number in [0, 2] [1]"},
      {"spacing = 0.005", "spacing = 0.005\nneighbour_skin = 0.2\nneighbour_skin_narrow = 0.25",
       "neighbour_skin_narrow = ^0.25", "fluid.neighbour_skin_narrow", "must not exceed neighbour_skin (0.2)"},
      {"spacing = 0.005", "spacing = 0.005\ntank_walls = 1", "tank_walls = ^1", "fluid.tank_walls",
       "expected true or false, got an integer"},
      {"spacing = 0.005", "spacing = 0.005\nspcing = 0.005", "^spcing", "fluid.spcing", "unknown key"},
      {"spacing = 0.005", "spacing = 0.005\nescape = \"drop\"", "escape = ^\"drop\"", "fluid.escape",
       "expected one of \"remove\", \"stop\""},
      {"spacing = 0.005", "spacing = 0.005\nescape_distance = -0.1", "escape_distance = ^-0.1",
       "fluid.escape_distance", "expected a number >= 0 [m], got -0.1"},
      {"spacing = 0.005", "spacing = 0.005\nescape = \"stop\"\nescape_distance = 0.1", "escape_distance = ^0.1",
       "fluid.escape_distance", "needs escape = \"remove\""},
      {"spacing = 0.005", "spacing = 0.005\nescape_fraction_limit = 0", "escape_fraction_limit = ^0",
       "fluid.escape_fraction_limit", "expected a number in (0, 1] [1], got 0"},
      {"spacing = 0.005", "spacing = 0.005\nescape_fraction_limit = 1.5", "escape_fraction_limit = ^1.5",
       "fluid.escape_fraction_limit", "got 1.5"},
      {"spacing = 0.005", "spacing = 0.005\n[fluid.schemes]\nhs = \"yes\"", "hs = ^\"yes\"", "fluid.schemes.hs",
       "expected true or false, got a string"},
      {"spacing = 0.005", "spacing = 0.005\n[fluid.schemes]\nxs = true", "^xs", "fluid.schemes.xs",
       "unknown key (known keys here: conservative_gradient, ds, ecs, gc, grain_gradient, hl, hs)"},
      {"spacing = 0.005", "spacing = 0.005\n[fluid.schemes]\ngrain_gradient = \"corrected\"", "grain_gradient = ^\"corrected\"",
       "fluid.schemes.grain_gradient", "\"corrected\" is for conservative_gradient = true"},
      {"spacing = 0.005", "spacing = 0.005\n[fluid.schemes]\nconservative_gradient = true\ngc = true", "gc = ^true",
       "fluid.schemes.gc", "the conservative gradient replaces the gradient correction"},
      {"spacing = 0.005", "spacing = 0.005\n[fluid.schemes]\nconservative_gradient = true", "conservative_gradient = ^true",
       "fluid.schemes.conservative_gradient", "is for water without a free surface (a sealed box full of water"},
      // [fluid.initial_velocity] (the tank spans z in [0, 0.03] m).
      {"spacing = 0.005", "spacing = 0.005\n[fluid.initial_velocity]\n"
       "kind = \"log\"\nbottom = 0.0\ntop = 0.01\nvelocity = 0.1",
       "kind = ^\"log\"", "fluid.initial_velocity.kind", "expected one of \"linear\", \"power\""},
      {"spacing = 0.005", "spacing = 0.005\n[fluid.initial_velocity]\n"
       "kind = \"linear\"\nbottom = 0.02\ntop = 0.01\nvelocity = 0.1",
       "top = ^0.01", "fluid.initial_velocity.top", "must be above bottom (0.02 m)"},
      {"spacing = 0.005", "spacing = 0.005\n[fluid.initial_velocity]\n"
       "kind = \"linear\"\nbottom = 0.0\ntop = 0.05\nvelocity = 0.1",
       "top = ^0.05", "fluid.initial_velocity.top", "expected a number in [0, 0.03] [m], got 0.05"},
      {"spacing = 0.005", "spacing = 0.005\n[fluid.initial_velocity]\n"
       "kind = \"linear\"\nbottom = 0.0\ntop = 0.01\nvelocity = 0.1\nexponent = 0.5",
       "exponent = ^0.5", "fluid.initial_velocity.exponent", "needs kind = \"power\""},
      {"spacing = 0.005", "spacing = 0.005\n[fluid.initial_velocity]\n"
       "kind = \"power\"\nbottom = 0.0\ntop = 0.01\nvelocity = 0.1\nexponent = 0",
       "exponent = ^0", "fluid.initial_velocity.exponent", "expected a number in (0, 10] [1], got 0"},
      {"spacing = 0.005", "spacing = 0.005\n[fluid.initial_velocity]\nkind = \"power\"\nbottom = 0.0\ntop = 0.01",
       "^[fluid.initial_velocity]", "fluid.initial_velocity.velocity", "missing required key"},
      {"spacing = 0.005", "spacing = 0.005\n[fluid.initial_velocity]\n"
       "kind = \"power\"\nbottom = 0.0\ntop = 0.01\nvelocity = 0.1\nspeed = 1",
       "^speed", "fluid.initial_velocity.speed", "unknown key"},
      // Boxes.
      {"velocity = [0.1, 0.0, -0.2]", "velocity = [0.1, 0.0]", "velocity = ^[0.1, 0.0]", "fluid.boxes[0].velocity",
       "got an array of 2 items"},
      {"low = [0.12, -0.01, 0.005]\nhigh = [0.125, 0.01, 0.01]",
       "low = [0.12, -0.01, 0.005]\nhigh = [0.125, 0.01, 0.01]\nvelocity = [1.0, 0.0, 0.0]", "^velocity = [1.0",
       "fluid.wall_boxes[0].velocity", "unknown key (known keys here: high, low, placement)"},
      {"high = [0.12, 0.01, 0.015]", "high = [0.12, 0.01, 0.0]", "high = ^[0.12, 0.01, 0.0]", "fluid.boxes[0].high",
       "every component of high must be > the one of low (along z: 0 <= 0)"},
      {"high = [0.12, 0.01, 0.015]", "high = [0.12, 0.02, 0.015]", "high = ^[0.12, 0.02", "fluid.boxes[0].high",
       "the box must lie inside the tank's inner box (0.1, -0.01, 0) - (0.14, 0.01, 0.03) m"},
      {"low = [0.1, -0.01, 0.0]\nhigh = [0.12", "low = [0.09, -0.01, 0.0]\nhigh = [0.12", "low = ^[0.09",
       "fluid.boxes[0].low", "inside the tank's inner box"},
      {first_box.c_str(), "low = [0.113, -0.01, 0.0]\nhigh = [0.117, 0.01, 0.015]", "low = ^[0.113",
       "fluid.boxes[0].low",
       "the box contains no lattice point: along x no particle centre tank.origin + (i + 1/2) spacing lies in "
       "[low, high]"},
      {"low = [0.12, -0.01, 0.0]\nhigh = [0.14, 0.01, 0.005]", "low = [0.115, -0.01, 0.0]\nhigh = [0.14, 0.01, 0.005]",
       "low = ^[0.115", "fluid.boxes[1].low", "the box overlaps fluid.boxes[0] (they share lattice points)"},
      {"low = [0.12, -0.01, 0.005]\nhigh = [0.125", "low = [0.12, -0.01, 0.0]\nhigh = [0.125", "low = ^[0.12, -0.01, 0.0]\nhigh = [0.125",
       "fluid.wall_boxes[0].low", "the wall box overlaps fluid.boxes[1] (they share lattice points)"},
      {"spacing = 0.005", "spacing = 1e-6", "high = ^[0.12, 0.01, 0.015]", "fluid.boxes[0].high",
       "more than 5e7 particles"},
      // The tank walls need whole lattice cells along every axis.
      {"size = [0.04, 0.02, 0.03]", "size = [0.04, 0.023, 0.03]", "spacing = ^0.005", "fluid.spacing",
       "with tank_walls = true the tank size along y (0.023 m) must be an integer multiple of spacing (0.005 m); "
       "nearest valid size 0.025 m"},
  };
  for (const BadFluid& bad : cases) {
    const std::string text = replace_once(test::fluid_scene_text(), bad.find, bad.replace);
    const std::string prefix = marked_location(text, bad.at, "bad.toml") + bad.key + ": ";
    CAPTURE(text);
    const std::vector<std::string> problems = problems_of(text);
    const bool found = std::any_of(problems.begin(), problems.end(), [&](const std::string& line) {
      return line.rfind(prefix, 0) == 0 && line.find(bad.message, prefix.size()) != std::string::npos;
    });
    CHECK_MESSAGE(found, "no problem starts with \"", prefix, "\" and mentions \"", std::string(bad.message),
                  "\"; got:\n", joined(problems));
    // Each case is one mistake: no follow-up noise, except a 1e-6 spacing, which also floods the tank walls.
    if (std::string_view(bad.replace) != "spacing = 1e-6")
      CHECK_MESSAGE(problems.size() == 1, "expected 1 problem, got:\n", joined(problems));
  }
}

TEST_CASE("a fluid without boxes is refused, and tank_walls = false lifts the whole-cell rule") {
  std::string text = test::fluid_scene_text();
  text = text.substr(0, text.find("[[fluid.boxes]]"));
  std::vector<std::string> problems = problems_of(text);
  REQUIRE(problems.size() == 1);
  CHECK(problems[0].rfind(marked_location(text, "^[fluid]", "bad.toml") +
                              "fluid.boxes: expected at least one [[fluid.boxes]] table",
                          0) == 0);
  text = replace_once(test::fluid_scene_text(), "size = [0.04, 0.02, 0.03]", "size = [0.04, 0.023, 0.03]");
  text = replace_once(text, "spacing = 0.005", "spacing = 0.005\ntank_walls = false");
  const Model model = parse_scene(text, "no_walls.toml");
  const World world = initial_world(model);
  CHECK(count_kind(*world.fluid, FluidKind::kDummy) == 0);
  CHECK(count_kind(*world.fluid, FluidKind::kWall) == 8);  // the wall boxes only
}

TEST_CASE("a wall box's name: plain, unique among the wall boxes, kept in the model") {
  const std::string first = "low = [0.12, -0.01, 0.005]\nhigh = [0.125, 0.01, 0.01]";
  const std::string second = "low = [0.12, -0.01, 0.005]\nhigh = [0.13, 0.01, 0.01]";
  std::string text = replace_once(test::fluid_scene_text(), first, "name = \"step\"\n" + first);
  const Model model = parse_scene(text, "named.toml");
  CHECK(model.fluid.wall_boxes[0].name == "step");
  CHECK(model.fluid.wall_boxes[1].name.empty());
  std::vector<std::string> problems = problems_of(replace_once(text, second, "name = \"step\"\n" + second));
  REQUIRE(problems.size() == 1);
  CHECK(problems[0].find("fluid.wall_boxes[1].name: \"step\" already names fluid.wall_boxes[0]") != std::string::npos);
  problems = problems_of(replace_once(test::fluid_scene_text(), first, "name = \"a step\"\n" + first));
  REQUIRE(problems.size() == 1);
  CHECK(problems[0].find("fluid.wall_boxes[0].name: expected a name of letters, digits") != std::string::npos);
}

TEST_CASE("the top-level key list names the fluid table") {
  const std::vector<std::string> problems = problems_of(test::fluid_scene_text("[fluidd]\n"));
  REQUIRE(problems.size() == 1);
  CHECK(problems[0].find("fluidd: unknown key (known keys here: contact, coupling, fluid, materials, mean_flow, output, run, solids, tank)") !=
        std::string::npos);
}

TEST_CASE("the initial fluid follows the closed forms with fluid in the first slots") {
  const Model model = test::fluid_model();
  const World world = initial_world(model);
  REQUIRE(world.fluid.has_value());
  REQUIRE(world.fluid_neighbours.has_value());
  REQUIRE(world.fluid_summary.has_value());
  CHECK_FALSE(world.solids.has_value());
  REQUIRE(world.walls.has_value());
  CHECK(world.walls->size() == 5);  // grain walls stay: the open top has none
  CHECK(world.fluid_neighbours->particle_count() == 0);

  const FluidParticles& particles = *world.fluid;
  check_field_sizes(particles, "fluid");
  const std::size_t fluid_count = 4 * 4 * 3 + 4 * 4 * 1;
  // 8 x 4 x 6 cells, z_max open, r_e = 2.4 l0: one wall layer and ceil(2.4) - 1 = 2 dummy layers.
  const std::array<double, 3> cells = {8, 4, 6};
  const std::array<bool, 6> closed = {true, true, true, true, true, false};
  const std::size_t tank_walls = shell_count(cells, closed, 1);
  const std::size_t tank_dummies = shell_count(cells, closed, 3) - tank_walls;
  CHECK(tank_walls == 228);
  CHECK(tank_dummies == 840);
  const std::size_t wall_box_points = 8;  // 4 + 8 lattice points, 4 of them shared
  CHECK(count_kind(particles, FluidKind::kFluid) == fluid_count);
  CHECK(count_kind(particles, FluidKind::kWall) == tank_walls + wall_box_points);
  CHECK(count_kind(particles, FluidKind::kDummy) == tank_dummies);
  CHECK(particles.size() == fluid_count + tank_walls + tank_dummies + wall_box_points);
  CHECK(world.fluid_summary->fluid_count == fluid_count);

  // Fluid in slots [0, F), the boxes in scene order, each with its velocity; then walls and dummies.
  for (std::size_t i = 0; i < particles.size(); ++i) {
    CAPTURE(i);
    CHECK((particles.kind[i] == static_cast<std::int32_t>(FluidKind::kFluid)) == (i < fluid_count));
    CHECK(particles.id[i] == i);
    CHECK(particles.rest_position[i] == particles.position[i]);  // the tank starts at its rest position
    CHECK(particles.predicted_position[i] == particles.position[i]);
    CHECK(particles.pressure[i] == 0.0);
    // Water at rest: the gradient coupled grains sample before the first solve (buoyancy from the first sub-step).
    CHECK(particles.pressure_gradient[i] == (i < fluid_count ? Vec3(model.fluid.density * model.gravity) : Vec3::Zero()));
  }
  CHECK(particles.next_id == particles.size());
  const Vec3 half_cell(0.0025, 0.0025, 0.0025);
  CHECK((particles.position[0] - (model.tank.origin + half_cell)).norm() < 1e-15);
  CHECK(particles.velocity[0] == Vec3(0.1, 0.0, -0.2));
  CHECK(particles.velocity[47] == Vec3(0.1, 0.0, -0.2));
  CHECK(particles.velocity[48] == Vec3::Zero());
  CHECK(particles.position[48].z() == doctest::Approx(0.0025).epsilon(1e-12));
  // Walls move with the tank: x = -A sin(2 pi f t) starts at rest position but with velocity -2 pi f A.
  const TankMotion tank = tank_kinematics(model.tank.motion, 0.0);
  CHECK(tank.velocity.norm() > 0.1);
  for (std::size_t i = fluid_count; i < particles.size(); ++i) CHECK(particles.velocity[i] == tank.velocity);

  // No two particles share a lattice point.
  std::set<std::array<long long, 3>> cells_seen;
  for (const Vec3& position : particles.position) {
    const Vec3 cell = (position - model.tank.origin) / model.fluid.spacing - Vec3(0.5, 0.5, 0.5);
    CHECK(cells_seen.insert({std::llround(cell.x()), std::llround(cell.y()), std::llround(cell.z())}).second);
  }
}

TEST_CASE("the tank shell grows with the effective radius and every closed face") {
  std::string text =
      replace_once(test::fluid_scene_text(), "spacing = 0.005", "spacing = 0.005\neffective_radius = 3.1");
  text = replace_once(text, "open_faces = [\"z_max\"]\n", "");
  const World world = initial_world(parse_scene(text, "closed.toml"));
  // ceil(3.1) - 1 = 3 dummy layers behind the wall layer, on all six faces.
  const std::array<double, 3> cells = {8, 4, 6};
  const std::array<bool, 6> closed = {true, true, true, true, true, true};
  CHECK(count_kind(*world.fluid, FluidKind::kWall) == shell_count(cells, closed, 1) + 8);
  CHECK(count_kind(*world.fluid, FluidKind::kDummy) == shell_count(cells, closed, 4) - shell_count(cells, closed, 1));
  CHECK(world.walls->size() == 6);
}

// [fluid.initial_velocity]: every fluid particle starts with its box's velocity plus the profile along x at its
// height, written out here from the formulas of docs/SCENES.md (not through initial_profile_velocity): 0 at and below
// z0, u_top (z - z0)/(z1 - z0) (linear) or u_top ((z - z0)/(z1 - z0))^(1/7) (power, seed 003's Eq. 27) between, u_top
// above z1. The fluid scene's particles sit at z = 2.5, 7.5 and 12.5 mm: one in each branch for z0 = 4, z1 = 12 mm.
// Walls and dummies keep the tank's velocity.
TEST_CASE("the initial velocity profile is the formula at every fluid particle") {
  for (const char* kind : {"linear", "power"}) {
    CAPTURE(kind);
    const std::string extra = std::string("[fluid.initial_velocity]\nkind = \"") + kind +
                              "\"\nbottom = 0.004\ntop = 0.012\nvelocity = 0.3\n";
    const Model plain = parse_scene(test::fluid_scene_text(), "fluid.toml");
    const Model model = parse_scene(test::fluid_scene_text(extra), "fluid.toml");
    const World start = initial_world(plain);
    const World world = initial_world(model);
    const FluidParticles& particles = *world.fluid;
    REQUIRE(particles.size() == start.fluid->size());
    int below = 0, between = 0, above = 0;
    for (std::size_t i = 0; i < particles.size(); ++i) {
      CAPTURE(i);
      const double z = particles.position[i].z();
      double expected = 0.0;
      if (particles.kind[i] == static_cast<std::int32_t>(FluidKind::kFluid)) {
        if (z <= 0.004) {
          ++below;
        } else if (z >= 0.012) {
          expected = 0.3;
          ++above;
        } else {
          const double eta = (z - 0.004) / 0.008;
          expected = std::string(kind) == "linear" ? 0.3 * eta : 0.3 * std::pow(eta, 1.0 / 7.0);
          ++between;
        }
      }
      CHECK(particles.velocity[i].x() == doctest::Approx(start.fluid->velocity[i].x() + expected).epsilon(1e-14));
      CHECK(particles.velocity[i].y() == start.fluid->velocity[i].y());
      CHECK(particles.velocity[i].z() == start.fluid->velocity[i].z());
    }
    CHECK(below == 16 + 16);  // the first box's bottom layer and the second box
    CHECK(between == 16);
    CHECK(above == 16);
  }
}

TEST_CASE("fluid.preconditioner: two_level by default, jacobi, and boomeramg where the build has hypre") {
  const std::string plain = test::fluid_scene_text();
  CHECK(parse_scene(plain, "plain.toml").fluid.preconditioner == FluidModel::Preconditioner::kTwoLevel);
  const auto with = [&](const std::string& value) {
    return replace_once(plain, "[fluid]\nspacing = 0.005\n", "[fluid]\nspacing = 0.005\npreconditioner = " + value + "\n");
  };
  CHECK(parse_scene(with("\"jacobi\""), "jacobi.toml").fluid.preconditioner == FluidModel::Preconditioner::kJacobi);
  const std::string amg = with("\"boomeramg\"");
  if (hypre_available()) {
    CHECK(parse_scene(amg, "amg.toml").fluid.preconditioner == FluidModel::Preconditioner::kBoomerAmg);
  } else {
    const std::vector<std::string> problems = problems_of(amg);
    REQUIRE(problems.size() == 1);
    CAPTURE(problems[0]);
    CHECK(problems[0].rfind(marked_location(amg, "\"boomeramg\"", "bad.toml") + "fluid.preconditioner: ", 0) == 0);
    CHECK(problems[0].find("built with hypre") != std::string::npos);
  }
  const std::vector<std::string> problems = problems_of(with("\"amg\""));
  REQUIRE(problems.size() == 1);
  CHECK(problems[0].find("boomeramg") != std::string::npos);  // the choices are listed
}
