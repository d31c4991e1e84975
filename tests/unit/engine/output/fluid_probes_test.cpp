// Fluid probes (engine/probes.*): the pressure sensor, wave gauge and surge front on a still water block on the MPS
// lattice, with hand-set hydrostatic pressures; reading [[output.probes]] of the fluid kinds and its errors
// (file:line:column: key); the CSV a ProbeWriter writes for each kind.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "engine/setup/fluid_layout.hpp"
#include "systems/physics/mps/mps_common.hpp"
#include "engine/output/probes.hpp"
#include "engine/scene/output_scene.hpp"
#include "engine/scene/scene.hpp"
#include "engine/run/simulation.hpp"
#include "systems/physics/mps/mps_kernel.hpp"
#include "tests/support/test_support.hpp"
#include "tests/support/scene_builder.hpp"

using namespace riffle;
using riffle::test::SceneBuilder, riffle::test::Triple, riffle::test::TomlValue;
namespace fs = std::filesystem;

namespace {

constexpr double kProbeSpacing = 0.01;     // [m] l0
constexpr double kRadiusRatio = 2.4;  // r_e / l0
constexpr double kDensity = 1000.0;   // [kg/m^3]
constexpr double kGravity = 9.81;     // [m/s^2]
const Vec3 kTankSize(0.1, 0.06, 0.1);  // [m] open top, inner min corner at the origin
const Vec3 kWater(0.06, 0.06, 0.05);   // [m] the water block from the origin: a dam-break column, H = 5 cm
constexpr double kDepth = 0.05;        // [m] H

FluidProbeSettings settings() {
  FluidProbeSettings s;
  s.spacing = kProbeSpacing;
  s.effective_radius = kRadiusRatio * kProbeSpacing;
  s.density = kDensity;
  s.gravity = Vec3(0.0, 0.0, -kGravity);
  s.reference_number_density = lattice_constants(3, kProbeSpacing, s.effective_radius).number_density;
  s.floor_height = 0.0;
  return s;
}

/// The water block (fluid slots first) in the tank's wall and dummy particles, hydrostatic p = rho g (H - z);
/// `extra` fluid particles (drops) are added after the block. Number densities are left at zero: no probe reads them.
FluidParticles still_water(const std::vector<Vec3>& extra = {}) {
  FluidParticles particles;
  append_layout(particles, fluid_box_layout(Vec3::Zero(), Vec3::Zero(), kWater, kProbeSpacing));
  for (const Vec3& drop : extra) particles.add(drop, Vec3::Zero(), FluidKind::kFluid);
  append_layout(particles, tank_wall_layout(Vec3::Zero(), kTankSize, {"z_max"}, kProbeSpacing, kRadiusRatio * kProbeSpacing));
  for (std::size_t j = 0; j < particles.size(); ++j)
    if (particles.kind[j] == static_cast<std::int32_t>(FluidKind::kFluid))
      particles.pressure[j] = kDensity * kGravity * (kDepth - particles.position[j].z());
  return particles;
}

/// Moves every particle with the tank (the water at rest in the tank frame).
void shift(FluidParticles& particles, const Vec3& displacement) {
  for (Vec3& position : particles.position) position += displacement;
}

// Tolerance of the pressure sensor on a linear field: every term p_j + rho (g - a) . (x_s - x_j) equals the exact
// value up to rounding, so the Shepard average does too: a few ulp of the largest term, rho g (H + r_e) ~ 700 Pa,
// i.e. ~1e-13 Pa. 1e-9 of rho g H leaves room for any summation order and still catches a missing l0/2 or a wrong
// sign (errors of order rho g l0 ~ 100 Pa).
constexpr double kPressureTolerance = 1e-9 * kDensity * kGravity * kDepth;

}  // namespace

TEST_CASE("a pressure sensor reads the hydrostatic pressure inside the water and on the walls") {
  const FluidParticles water = still_water();
  const FluidProbeSettings s = settings();
  const TankMotion at_rest;
  struct Sensor {
    Vec3 point;
    const char* where;
  };
  const std::vector<Sensor> sensors = {
      {{0.03, 0.03, 0.02}, "inside, between lattice sites"},
      {{0.035, 0.025, 0.025}, "on a particle"},
      {{0.03, 0.03, 0.0}, "on the floor (l0/2 below the first layer)"},
      {{0.0, 0.03, 0.01}, "on the x_min wall"},
      {{0.0, 0.0, 0.0}, "in the floor corner"},
      {{0.06, 0.03, 0.03}, "on the water's free side face (dam-break front)"},
      {{0.03, 0.03, kDepth}, "at the free surface"},
  };
  for (const Sensor& sensor : sensors) {
    CAPTURE(sensor.where);
    const double pressure = fluid_pressure_at(water, s, at_rest, sensor.point);
    CHECK(std::abs(pressure - kDensity * kGravity * (kDepth - sensor.point.z())) <= kPressureTolerance);
  }
  // A sensor farther than r_e from every fluid particle is dry: no value, not zero.
  CHECK(std::isnan(fluid_pressure_at(water, s, at_rest, Vec3(0.03, 0.03, 0.08))));   // 3.5 l0 above the top layer
  CHECK(std::isnan(fluid_pressure_at(water, s, at_rest, Vec3(0.095, 0.03, 0.005))));  // 3 l0 ahead of the front
}

TEST_CASE("a pressure sensor moves with the tank and uses the tank's acceleration") {
  const FluidProbeSettings s = settings();
  SUBCASE("the sensor's lab position is its point plus the tank displacement") {
    const FluidParticles water = still_water();  // left where it is: only the sensor moves
    TankMotion tank;
    tank.displacement = Vec3(0.0, 0.0, -0.01);
    CHECK(std::abs(fluid_pressure_at(water, s, tank, Vec3(0.03, 0.03, 0.02)) -
                   kDensity * kGravity * (kDepth - 0.01)) <= kPressureTolerance);
    tank.displacement = Vec3(0.04, 0.0, 0.0);  // a sensor 1 l0 ahead of the front is carried 4 l0 further: dry
    CHECK(!std::isnan(fluid_pressure_at(water, s, TankMotion{}, Vec3(0.07, 0.03, 0.02))));
    CHECK(std::isnan(fluid_pressure_at(water, s, tank, Vec3(0.07, 0.03, 0.02))));
  }
  SUBCASE("in an accelerated tank the pressure field tilts: grad p = rho (g - a)") {
    FluidParticles water = still_water();
    TankMotion tank;
    tank.displacement = Vec3(0.007, -0.002, 0.0);
    tank.acceleration = Vec3(3.0, -1.0, 0.0);
    shift(water, tank.displacement);
    const Vec3 body = s.gravity - tank.acceleration;
    const Vec3 reference = Vec3(0.0, 0.0, kDepth) + tank.displacement;  // any point: the field is affine
    for (std::size_t j = 0; j < water.size(); ++j)
      water.pressure[j] = kDensity * body.dot(water.position[j] - reference);
    for (const Vec3& point : {Vec3(0.0, 0.03, 0.02), Vec3(0.06, 0.01, 0.0), Vec3(0.031, 0.017, 0.033)}) {
      CAPTURE(point.transpose());
      const double expected = kDensity * body.dot(point + tank.displacement - reference);
      CHECK(std::abs(fluid_pressure_at(water, s, tank, point) - expected) <= kPressureTolerance);
    }
  }
}

TEST_CASE("a wave gauge reads the top of the water and ignores isolated spray") {
  const FluidProbeSettings s = settings();
  // A lone particle 4 l0 above the surface over the middle gauge: n = 0 (nothing within r_e = 2.4 l0).
  const FluidParticles water = still_water({Vec3(0.035, 0.035, 0.085)});
  for (const Vec3& gauge : {Vec3(0.035, 0.035, 0.0), Vec3(0.03, 0.03, 0.0), Vec3(0.005, 0.03, 0.0)}) {
    CAPTURE(gauge.transpose());
    // The top layer's centres are at H - l0/2; the surface is l0/2 higher, exactly H (to rounding).
    CHECK(wave_gauge_height(water, s, TankMotion{}, gauge, kProbeSpacing) == doctest::Approx(kDepth).epsilon(1e-12));
  }
  // Beyond the front no particle is within the radius: no value.
  CHECK(std::isnan(wave_gauge_height(water, s, TankMotion{}, Vec3(0.08, 0.03, 0.0), kProbeSpacing)));
  // A radius of 3 l0 reaches the front column from there (its nearest centres are 2.55 l0 away); its top edge
  // particle has n = 0.55 n0 (a quarter space of support), just above the threshold.
  CHECK(wave_gauge_height(water, s, TankMotion{}, Vec3(0.08, 0.03, 0.0), 3.0 * kProbeSpacing) ==
        doctest::Approx(kDepth).epsilon(1e-12));

  // Two drops l0 apart are still spray: n = w(l0) = 0.31 < 0.5 n0 = 1.6 for r_e = 2.4 l0.
  const FluidParticles pair = still_water({Vec3(0.035, 0.035, 0.085), Vec3(0.035, 0.045, 0.085)});
  CHECK(wave_gauge_height(pair, s, TankMotion{}, Vec3(0.035, 0.035, 0.0), kProbeSpacing) ==
        doctest::Approx(kDepth).epsilon(1e-12));

  SUBCASE("in the tank frame") {
    FluidParticles moved = still_water();
    TankMotion tank;
    tank.displacement = Vec3(0.013, 0.004, 0.002);
    shift(moved, tank.displacement);
    CHECK(wave_gauge_height(moved, s, tank, Vec3(0.005, 0.03, 0.0), kProbeSpacing) ==
          doctest::Approx(kDepth).epsilon(1e-12));
  }
}

TEST_CASE("the surge front is the far face of the water and ignores lone drops") {
  const FluidProbeSettings s = settings();
  const double inf = std::numeric_limits<double>::infinity();
  const FluidParticles water = still_water();
  CHECK(surge_front_position(water, s, TankMotion{}, Vec3::UnitX(), inf) == doctest::Approx(kWater.x()));
  CHECK(surge_front_position(water, s, TankMotion{}, -Vec3::UnitX(), inf) == doctest::Approx(0.0));
  CHECK(surge_front_position(water, s, TankMotion{}, Vec3::UnitY(), inf) == doctest::Approx(kWater.y()));

  SUBCASE("a lone drop ahead does not count, two drops together do") {
    const FluidParticles one_drop = still_water({Vec3(0.085, 0.03, 0.005)});
    CHECK(surge_front_position(one_drop, s, TankMotion{}, Vec3::UnitX(), inf) == doctest::Approx(kWater.x()));
    const FluidParticles two_drops = still_water({Vec3(0.08, 0.03, 0.045), Vec3(0.09, 0.03, 0.045)});
    CHECK(surge_front_position(two_drops, s, TankMotion{}, Vec3::UnitX(), inf) == doctest::Approx(0.095));
    // ... unless they are higher than `below` above the floor.
    CHECK(surge_front_position(two_drops, s, TankMotion{}, Vec3::UnitX(), 0.03) == doctest::Approx(kWater.x()));
  }
  SUBCASE("in the tank frame") {
    FluidParticles moved = still_water();
    TankMotion tank;
    tank.displacement = Vec3(-0.008, 0.001, 0.0);
    shift(moved, tank.displacement);
    CHECK(surge_front_position(moved, s, tank, Vec3::UnitX(), inf) == doctest::Approx(kWater.x()));
  }
  SUBCASE("no fluid: no value") {
    CHECK(std::isnan(surge_front_position(FluidParticles{}, s, TankMotion{}, Vec3::UnitX(), inf)));
  }
}

namespace {

/// The fluid-free model of the reading tests with [fluid] switched on by hand (the [fluid] table is read
/// elsewhere): the tank above, l0 = 1 cm.
Model fluid_model() {
  Model model;
  model.dt = 1e-3;
  model.tank.size = kTankSize;
  model.fluid.enabled = true;
  model.fluid.spacing = kProbeSpacing;
  model.fluid.effective_radius_ratio = kRadiusRatio;
  fill_mps_constants(model.fluid);
  return model;
}

/// Reads the [output] table of `text` into `model`; returns the problems.
std::vector<std::string> read_output_probes(const std::string& text, Model& model) {
  SceneProblems problems{"fluid.toml", {}};
  const std::optional<toml::table> root = parse_toml(text, problems);
  REQUIRE(root);
  TableReader scene(*root, "", problems);
  std::optional<TableReader> output = scene.table("output", true);
  REQUIRE(output);
  read_probes(*output, model);
  output->finish();
  return problems.lines;
}


/// A bad [[output.probes]] table, and the one problem it must raise.
struct BadProbe {
  const char* probe;    // the [[output.probes]] table
  const char* at;       // where the problem is reported ('^' = the column)
  const char* key;
  const char* message;  // fragment
};

/// `text` (read as fluid.toml) gives exactly one problem, at bad.at, naming bad.key, with bad.message in it.
void check_one_problem(const std::string& text, Model& model, const BadProbe& bad) {
  const std::vector<std::string> problems = read_output_probes(text, model);
  std::string all_problems;
  for (const std::string& problem : problems) all_problems += problem + "\n";
  CAPTURE(all_problems);
  REQUIRE(problems.size() == 1);
  const std::string expected_start = test::first_location("fluid.toml", text, bad.at) + bad.key + ": ";
  CHECK_MESSAGE(problems[0].rfind(expected_start, 0) == 0, problems[0], " should start with ", expected_start);
  CHECK_MESSAGE(problems[0].find(bad.message) != std::string::npos, problems[0]);
}

}  // namespace

TEST_CASE("fluid probes are read with their defaults") {
  Model model = fluid_model();
  const std::vector<std::string> problems = read_output_probes(SceneBuilder().output()
      .probe("fluid_pressure").set("points", TomlValue::verbatim("[[0.0, 0.03, 0.01], [0.1, 0.06, 0]]"))
      .set("interval", 0.005)
      .probe("wave_gauge").set("points", TomlValue::verbatim("[[0.005, 0.03], [0.05, 0.03]]"))
      .probe("wave_gauge").set("name", "wide").set("points", TomlValue::verbatim("[[0.05, 0.03]]")).set("radius", 0.02)
      .probe("surge_front")
      .probe("surge_front").set("name", "low_front").set("direction", std::vector<int>{0, -2, 0}).set("below", 0.01)
      .probe("fluid_totals").toml(),
                                                               model);
  CHECK(problems.empty());
  REQUIRE(model.output.probes.size() == 6);
  const std::vector<ProbeModel>& probes = model.output.probes;
  CHECK(probes[0].kind == ProbeModel::Kind::kFluidPressure);
  CHECK(probes[0].file == "probe_fluid_pressure.csv");
  CHECK(probes[0].points == std::vector<Vec3>{Vec3(0.0, 0.03, 0.01), Vec3(0.1, 0.06, 0.0)});
  CHECK(probes[1].kind == ProbeModel::Kind::kWaveGauge);
  CHECK(probes[1].points == std::vector<Vec3>{Vec3(0.005, 0.03, 0.0), Vec3(0.05, 0.03, 0.0)});
  CHECK(probes[1].radius == kProbeSpacing);  // default: l0
  CHECK(probes[2].radius == 0.02);
  CHECK(probes[3].kind == ProbeModel::Kind::kSurgeFront);
  CHECK(probes[3].direction == Vec3::UnitX());
  CHECK(probes[3].below == std::numeric_limits<double>::infinity());
  CHECK(probes[4].direction == -Vec3::UnitY());  // normalised
  CHECK(probes[4].below == 0.01);
  CHECK(probes[5].kind == ProbeModel::Kind::kFluidTotals);
  CHECK(probes[5].file == "probe_fluid_totals.csv");
}

TEST_CASE("bad fluid probes are reported as file:line:column: key: message") {
  using Bad = BadProbe;
  const std::vector<Bad> cases = {
      {"kind = \"fluid_pressure\"\n", "^[[output.probes]]", "output.probes[0].points", "missing required key"},
      {"kind = \"fluid_pressure\"\npoints = []\n", "points = ^[]", "output.probes[0].points",
       "expected at least one point"},
      {"kind = \"fluid_pressure\"\npoints = 1\n", "points = ^1", "output.probes[0].points",
       "expected an array of points, each an array of 3 numbers [m], got an integer"},
      {"kind = \"fluid_pressure\"\npoints = [[0.01, 0.02]]\n", "points = [^[0.01", "output.probes[0].points[0]",
       "expected an array of 3 numbers [m], got an array of 2 items"},
      {"kind = \"fluid_pressure\"\npoints = [[0.01, 0.02, 0.03], 4]\n", "0.03], ^4", "output.probes[0].points[1]",
       "got an integer"},
      {"kind = \"fluid_pressure\"\npoints = [[0.01, \"a\", 0.03]]\n", "0.01, ^\"a\"",
       "output.probes[0].points[0][1]", "expected a finite number [m], got a string"},
      {"kind = \"fluid_pressure\"\npoints = [[0.01, 0.02, 0.03], [0.01, 0.02, 0.3]]\n", "0.03], ^[0.01",
       "output.probes[0].points[1]", "the point lies outside the tank"},
      {"kind = \"wave_gauge\"\npoints = [[0.01, 0.02, 0.03]]\n", "points = [^[", "output.probes[0].points[0]",
       "expected an array of 2 numbers [m], got an array of 3 items"},
      {"kind = \"wave_gauge\"\npoints = [[-0.01, 0.02]]\n", "points = [^[", "output.probes[0].points[0]",
       "the point lies outside the tank"},
      {"kind = \"wave_gauge\"\npoints = [[0.01, 0.02]]\nradius = 0\n", "radius = ^0", "output.probes[0].radius",
       "expected a number > 0 [m], got 0"},
      {"kind = \"fluid_pressure\"\npoints = [[0.01, 0.02, 0.03]]\nradius = 0.01\n", "^radius",
       "output.probes[0].radius", "unknown key"},
      {"kind = \"surge_front\"\ndirection = [1, 0, 1]\n", "direction = ^[", "output.probes[0].direction",
       "expected a horizontal direction"},
      {"kind = \"surge_front\"\ndirection = [0, 0, 0]\n", "direction = ^[", "output.probes[0].direction",
       "expected a non-zero direction"},
      {"kind = \"surge_front\"\nbelow = -0.1\n", "below = ^-0.1", "output.probes[0].below",
       "expected a number > 0 [m], got -0.1"},
      {"kind = \"fluid_totals\"\npoints = [[0.01, 0.02, 0.03]]\n", "^points", "output.probes[0].points",
       "unknown key"},
      {"kind = \"surge_frnt\"\npoints = [[0.01, 0.02, 0.03]]\n", "kind = ^\"surge_frnt\"", "output.probes[0].kind",
       "expected one of"},
  };
  for (const Bad& bad : cases) {
    const std::string text = std::string("[output]\n[[output.probes]]\n") + bad.probe;
    CAPTURE(text);
    Model model = fluid_model();
    check_one_problem(text, model, bad);
  }
}

TEST_CASE("a fluid probe in a scene without [fluid] is an error at its kind") {
  for (const char* kind :
       {"fluid_pressure", "wave_gauge", "surge_front", "fluid_totals", "pressure_transducer", "driven_flow"}) {
    CAPTURE(kind);
    std::string probe = std::string("[[output.probes]]\nkind = \"") + kind + "\"\n";
    if (std::string(kind) == "fluid_pressure") probe += "points = [[0.1, 0.1, 0.1]]\n";
    if (std::string(kind) == "pressure_transducer") probe += "points = [[0.0, 0.1, 0.1]]\ndiameter = 0.01\n";
    if (std::string(kind) == "wave_gauge") probe += "points = [[0.1, 0.1]]\n";
    const std::string text = test::small_scene_text("\n[output]\n" + probe);
    try {
      parse_scene(text, "dry.toml");
      FAIL_CHECK("the scene was accepted");
    } catch (const SceneError& error) {
      REQUIRE(error.problems().size() == 1);
      const std::string expected = test::first_location("dry.toml", text, std::string("kind = ^\"") + kind) +
                                   "output.probes[0].kind: \"" + kind + "\" probes need a [fluid] table";
      CHECK_MESSAGE(error.problems()[0].rfind(expected, 0) == 0, error.problems()[0]);
    }
  }
}

TEST_CASE("ProbeWriter writes one column per sensor, empty fields where nothing is measured") {
  Model model = fluid_model();
  read_output_probes(SceneBuilder().output()
      .probe("fluid_pressure").set("points", std::vector<Triple>{{0.03, 0.03, 0.0}, {0.03, 0.03, 0.09}})
      .probe("wave_gauge").set("points", TomlValue::verbatim("[[0.005, 0.03], [0.09, 0.03]]")).probe("surge_front")
      .probe("fluid_totals").toml(),
                     model);
  REQUIRE(model.output.probes.size() == 4);
  const fs::path directory = test::scratch_dir("fluid_probes_writer");
  World world;
  world.tank_motion.emplace();
  world.fluid = still_water();
  world.fluid_summary.emplace();
  world.fluid_summary->fluid_count = 180;
  world.fluid_summary->volume = 1.8e-4;
  world.fluid_summary->solver_iterations = 42;
  world.fluid_summary->solver_residual = 5e-9;
  for (const ProbeModel& probe : model.output.probes) ProbeWriter(model, probe, directory, world, true).write(world);

  // 6 x 6 x 5 fluid particles; the floor sensor reads rho g H (to the rounding of %.9g), the one above is dry.
  const std::vector<std::string> pressure = test::file_lines(directory / "probe_fluid_pressure.csv");
  REQUIRE(pressure.size() == 2);
  CHECK(pressure[0] == "time_s,step,p0_Pa,p1_Pa");
  CHECK(pressure[1] == "0,0,490.5,");
  const std::vector<std::string> gauges = test::file_lines(directory / "probe_wave_gauge.csv");
  REQUIRE(gauges.size() == 2);
  CHECK(gauges[0] == "time_s,step,gauge0_z_m,gauge1_z_m");
  CHECK(gauges[1] == "0,0,0.05,");
  const std::vector<std::string> front = test::file_lines(directory / "probe_surge_front.csv");
  REQUIRE(front.size() == 2);
  CHECK(front[0] == "time_s,step,front_m");
  CHECK(front[1] == "0,0,0.06");
  const std::vector<std::string> totals = test::file_lines(directory / "probe_fluid_totals.csv");
  REQUIRE(totals.size() == 2);
  CHECK(totals[0] == "time_s,step,fluid_particles,volume_m3,kinetic_energy_J,max_speed_m_s,mean_density_ratio,"
                     "surface_particles,ppe_iterations,ppe_residual,removed_particles,removed_mass_kg,"
                     "removed_volume_m3,removed_left_domain,removed_lone_droplets");
  CHECK(totals[1] == "0,0,180,0.00018,0,0,1,0,42,5e-09,0,0,0,0,0");

  SUBCASE("particles removed as escaped: counted, rho l0^3 and l0^3 each, by reason") {
    world.fluid_summary->initial_fluid_count = 183;  // 3 of the 183 laid out were removed (fluid_escape)
    world.fluid_summary->removed_left_domain = 1;
    world.fluid_summary->removed_lone_droplet = 2;
    for (const ProbeModel& probe : model.output.probes) ProbeWriter(model, probe, directory, world, true).write(world);
    CHECK(test::file_lines(directory / "probe_fluid_totals.csv")[1] ==
          "0,0,180,0.00018,0,0,1,0,42,5e-09,3,0.003,3e-06,1,2");
  }
  SUBCASE("without fluid particles or summary (yet) every field is empty") {
    World empty;
    for (const ProbeModel& probe : model.output.probes) ProbeWriter(model, probe, directory, empty, true).write(empty);
    CHECK(test::file_lines(directory / "probe_fluid_pressure.csv")[1] == "0,0,,");
    CHECK(test::file_lines(directory / "probe_surge_front.csv")[1] == "0,0,");
    CHECK(test::file_lines(directory / "probe_fluid_totals.csv")[1] == "0,0,,,,,,,,,,,,,");
  }
}

// ---- The point sensor in air (a sensor that averaged in the air particles would read down to -226 Pa above a thin
// layer of water) ----

TEST_CASE("a pressure sensor above the water reads 0, not its negative hydrostatic extrapolation") {
  const FluidParticles water = still_water();
  FluidProbeSettings s = settings();
  // Above the free surface (z = H) the extrapolation rho g (H - z) is negative: the sensor is in air and reads 0.
  // Extrapolated, they would read -24.5, -49, -98 and -147 Pa.
  for (const Vec3& point : {Vec3(0.03, 0.03, kDepth + 0.25 * kProbeSpacing), Vec3(0.03, 0.03, kDepth + 0.5 * kProbeSpacing),
                            Vec3(0.03, 0.03, kDepth + kProbeSpacing), Vec3(0.0, 0.03, kDepth + 1.5 * kProbeSpacing)}) {
    CAPTURE(point.transpose());
    CHECK(fluid_pressure_at(water, s, TankMotion{}, point) == 0.0);
  }
  // With tension allowed ([fluid] clamp_negative_pressure = false) the extrapolation stands where the support is
  // wet (l0/4 above the surface: a third of it holds water), and is 0 where it is dry (l0 above: 3 %).
  s.allow_tension = true;
  CHECK(std::abs(fluid_pressure_at(water, s, TankMotion{}, Vec3(0.03, 0.03, kDepth + 0.25 * kProbeSpacing)) +
                 0.25 * kDensity * kGravity * kProbeSpacing) <= kPressureTolerance);
  CHECK(fluid_pressure_at(water, s, TankMotion{}, Vec3(0.03, 0.03, kDepth + kProbeSpacing)) == 0.0);
  // Inside the water nothing changes.
  CHECK(std::abs(fluid_pressure_at(water, s, TankMotion{}, Vec3(0.0, 0.03, 0.01)) -
                 kDensity * kGravity * (kDepth - 0.01)) <= kPressureTolerance);
}

TEST_CASE("a pressure sensor in air below a lone drop reads 0, not the drop's extrapolated pressure") {
  // A drop at p = 0 half a spacing above a sensor far from the water: the extrapolation gives rho g l0/2 = 49 Pa,
  // but a drop fills at most a quarter of the support: the sensor is in air.
  FluidParticles water = still_water({Vec3(0.085, 0.03, 0.08)});
  for (std::size_t j = 0; j < water.size(); ++j)
    if (water.position[j] == Vec3(0.085, 0.03, 0.08)) water.pressure[j] = 0.0;
  CHECK(fluid_pressure_at(water, settings(), TankMotion{}, Vec3(0.085, 0.03, 0.075)) == 0.0);
  CHECK(std::isnan(fluid_pressure_at(water, settings(), TankMotion{}, Vec3(0.085, 0.03, 0.02))));  // nothing near
}

// ---- Pressure transducers: discs on the walls ----

using test::half_submerged_mean;

TEST_CASE("a transducer reads rho g h at its centre, the wetted-area mean at the water line, 0 in air") {
  const FluidParticles water = still_water();
  const FluidProbeSettings s = settings();
  const double rho_g = kDensity * kGravity;
  // Below the water: the disc's mean of a linear field is its value at the centre, to rounding.
  CHECK(std::abs(pressure_transducer_reading(water, s, TankMotion{}, Vec3(0.0, 0.03, 0.02), -Vec3::UnitX(), 0.01) -
                 rho_g * (kDepth - 0.02)) <= kPressureTolerance);
  CHECK(std::abs(pressure_transducer_reading(water, s, TankMotion{}, Vec3(0.03, 0.0, 0.015), -Vec3::UnitY(), 0.02) -
                 rho_g * (kDepth - 0.015)) <= kPressureTolerance);
  CHECK(std::abs(pressure_transducer_reading(water, s, TankMotion{}, Vec3(0.03, 0.03, 0.0), -Vec3::UnitZ(), 0.01) -
                 rho_g * kDepth) <= kPressureTolerance);
  // Across the water line: the mean of rho g max(0, H - z) over the disc; the quadrature's error is below 0.25 % of
  // rho g R (pressure_sensor_test: 4 rings, the fewest a transducer uses).
  for (const double centre : {kDepth, kDepth - 0.004, kDepth + 0.006}) {
    CAPTURE(centre);
    const double radius = 0.01;
    const double reading =
        pressure_transducer_reading(water, s, TankMotion{}, Vec3(0.0, 0.03, centre), -Vec3::UnitX(), 2 * radius);
    CHECK(std::abs(reading - rho_g * half_submerged_mean(kDepth - centre, radius)) <= 0.0025 * rho_g * radius);
  }
  // In air: exactly 0, whether water is within reach (just above the water line, on the dry wall ahead of the
  // front) or not.
  CHECK(pressure_transducer_reading(water, s, TankMotion{}, Vec3(0.0, 0.03, kDepth + 0.006), -Vec3::UnitX(), 0.01) ==
        0.0);
  CHECK(pressure_transducer_reading(water, s, TankMotion{}, Vec3(0.1, 0.03, 0.02), Vec3::UnitX(), 0.01) == 0.0);
  CHECK(pressure_transducer_reading(water, s, TankMotion{}, Vec3(0.0, 0.03, 0.09), -Vec3::UnitX(), 0.01) == 0.0);
}

TEST_CASE("a transducer moves with the tank and reads the field tilted by the tank's acceleration") {
  const FluidProbeSettings s = settings();
  FluidParticles water = still_water();
  TankMotion tank;
  tank.displacement = Vec3(0.007, -0.002, 0.003);
  tank.acceleration = Vec3(3.0, -1.0, 2.0);
  shift(water, tank.displacement);
  const Vec3 body = s.gravity - tank.acceleration;
  const Vec3 reference = Vec3(0.03, 0.03, kDepth) + tank.displacement;
  for (std::size_t j = 0; j < water.size(); ++j)
    water.pressure[j] = kDensity * body.dot(water.position[j] - reference);
  struct Disc {
    Vec3 point, normal;
  };
  for (const Disc& disc : {Disc{Vec3(0.0, 0.03, 0.02), -Vec3::UnitX()}, Disc{Vec3(0.03, 0.0, 0.01), -Vec3::UnitY()},
                           Disc{Vec3(0.03, 0.03, 0.0), -Vec3::UnitZ()}}) {
    CAPTURE(disc.point.transpose());
    const double expected = kDensity * body.dot(disc.point + tank.displacement - reference);
    CHECK(std::abs(pressure_transducer_reading(water, s, tank, disc.point, disc.normal, 0.01) - expected) <=
          kPressureTolerance);
  }
}

TEST_CASE("WindowMean: the time average over the window ending at the latest reading, each held over its step") {
  WindowMean lone(0.5);
  CHECK(lone.mean().empty());
  lone.add(0.0, {7.0, -1.0});
  CHECK(lone.mean() == std::vector<double>{7.0, -1.0});  // a lone reading is its own mean
  WindowMean window(0.15);
  window.add(0.0, {1.0});
  window.add(0.1, {3.0});
  window.add(0.2, {5.0});
  // (0.05, 0.2]: half of the step (0, 0.1] at 3 and all of (0.1, 0.2] at 5: (0.05 * 3 + 0.1 * 5) / 0.15.
  CHECK(window.mean()[0] == doctest::Approx((0.05 * 3.0 + 0.1 * 5.0) / 0.15).epsilon(1e-14));
  WindowMean uneven(1.0);
  uneven.add(0.0, {0.0});
  uneven.add(0.01, {10.0});
  uneven.add(0.04, {40.0});
  CHECK(uneven.mean()[0] == doctest::Approx((0.01 * 10.0 + 0.03 * 40.0) / 0.04).epsilon(1e-14));
  CHECK(uneven.latest_time() == 0.04);
  WindowMean resumed(0.1);  // after a resume at 0.5 s: the window holds only the time since
  resumed.add(0.5, {100.0});
  resumed.add(0.52, {2.0});
  CHECK(resumed.mean()[0] == doctest::Approx(2.0).epsilon(1e-14));
}

TEST_CASE("pressure transducers are read with their defaults, their face inferred or named") {
  Model model = fluid_model();
  const std::vector<std::string> problems = read_output_probes(SceneBuilder().output()
      .probe("pressure_transducer")
      .set("points", std::vector<Triple>{{0.0, 0.03, 0.02}, {0.1, 0.03, 0.005}, {0.05, 0.06, 0.05}, {0.05, 0.03, 0.0}})
      .set("diameter", 0.01)
      .probe("pressure_transducer").set("name", "sides").set("face", "x_max")
      .set("points", std::vector<Triple>{{0.1, 0.03, 0.05}}).set("diameter", 0.006).set("average_window", 0.002)
      .set("interval", 0.001)
      .toml(),
                                                               model);
  CHECK(problems.empty());
  REQUIRE(model.output.probes.size() == 2);
  const ProbeModel& first = model.output.probes[0];
  CHECK(first.kind == ProbeModel::Kind::kPressureTransducer);
  CHECK(first.file == "probe_pressure_transducer.csv");
  CHECK(first.diameter == 0.01);
  CHECK(first.average_window == 0.0);
  CHECK(first.normals == std::vector<Vec3>{-Vec3::UnitX(), Vec3::UnitX(), Vec3::UnitY(), -Vec3::UnitZ()});
  const ProbeModel& second = model.output.probes[1];
  CHECK(second.normals == std::vector<Vec3>{Vec3::UnitX()});
  CHECK(second.average_window == 0.002);
  CHECK(second.file == "probe_sides.csv");
}

namespace {

/// fluid_model() with two wall boxes: "block", on the lattice but given 3 mm off it at x (its particles' cells start
/// at x = 0.06), and "shelf", unnamed (probes cannot refer to it).
Model fluid_model_with_block() {
  Model model = fluid_model();
  model.tank.open_faces = {"z_max"};
  ParticleBoxModel block;
  block.name = "block";
  block.low = Vec3(0.063, 0.0, 0.0);
  block.high = Vec3(0.1, 0.06, 0.04);
  model.fluid.wall_boxes.push_back(block);
  ParticleBoxModel shelf;
  shelf.low = Vec3(0.0, 0.0, 0.08);
  shelf.high = Vec3(0.02, 0.06, 0.1);
  model.fluid.wall_boxes.push_back(shelf);
  return model;
}

}  // namespace

TEST_CASE("pressure transducers on a named wall box: normals into the box, discs on its particles' cells' faces") {
  Model model = fluid_model_with_block();
  const std::vector<std::string> problems = read_output_probes(SceneBuilder().output()
      .probe("pressure_transducer").set("name", "block_faces").set("wall_box", "block")
      .set("points", std::vector<Triple>{{0.063, 0.03, 0.02}, {0.08, 0.03, 0.04}, {0.08, 0.0, 0.02}})
      .set("diameter", 0.01)
      .probe("pressure_transducer").set("name", "block_top").set("wall_box", "block").set("face", "z_max")
      .set("points", std::vector<Triple>{{0.08, 0.03, 0.04}}).set("diameter", 0.02)
      .toml(),
                                                               model);
  CHECK(problems.empty());
  REQUIRE(model.output.probes.size() == 2);
  const ProbeModel& faces = model.output.probes[0];
  // Out of the water into the box: its x_min face +x, its top -z, its y_min face (on the tank's wall) +y.
  CHECK(faces.normals == std::vector<Vec3>{Vec3::UnitX(), -Vec3::UnitZ(), Vec3::UnitY()});
  // The lattice's particles of [0.063, 0.1] along x sit at 0.065 ... 0.095: their cells' face is x = 0.06, where
  // the water meets the block; the top's cells end at z = 0.04 (particles at 0.005 ... 0.035), as given.
  REQUIRE(faces.points.size() == 3);
  CHECK(faces.points[0].x() == doctest::Approx(0.06).epsilon(1e-12));
  CHECK(faces.points[0].z() == 0.02);
  CHECK(faces.points[1].z() == doctest::Approx(0.04).epsilon(1e-12));
  CHECK(faces.points[2].y() == doctest::Approx(0.0).scale(1.0).epsilon(1e-12));
  CHECK(model.output.probes[1].normals == std::vector<Vec3>{-Vec3::UnitZ()});
}

TEST_CASE("bad transducers on wall boxes are reported as file:line:column: key: message") {
  using Bad = BadProbe;
  const char* kind = "kind = \"pressure_transducer\"\ndiameter = 0.01\n";
  const std::vector<Bad> cases = {
      {"wall_box = \"blok\"\npoints = [[0.063, 0.03, 0.02]]\n", "wall_box = ^\"blok\"", "output.probes[0].wall_box",
       "no [[fluid.wall_boxes]] entry is named \"blok\" (named: \"block\")"},
      {"wall_box = \"block\"\npoints = [[0.07, 0.03, 0.02]]\n", "points = [^[", "output.probes[0].points[0]",
       "the point lies on no face of wall box \"block\""},
      {"wall_box = \"block\"\npoints = [[0.063, 0.03, 0.05]]\n", "points = [^[", "output.probes[0].points[0]",
       "the point lies on no face of wall box \"block\""},  // in the face's plane, above the box
      {"wall_box = \"block\"\npoints = [[0.063, 0.03, 0.04]]\n", "points = [^[", "output.probes[0].points[0]",
       "the point lies on the edge of the x_min and z_max faces of wall box \"block\""},
      {"wall_box = \"block\"\npoints = [[0.063, 0.03, 0.037]]\n", "points = [^[", "output.probes[0].points[0]",
       "the disc (diameter 0.01 m) reaches beyond the x_min face of wall box \"block\" (y 0 to 0.06 m, z 0 to 0.04 m"},
      {"wall_box = \"block\"\nface = \"x_max\"\npoints = [[0.063, 0.03, 0.02]]\n", "points = [^[",
       "output.probes[0].points[0]", "the point is not on the x_max face of wall box \"block\" (x = 0.1 m"},
  };
  for (const Bad& bad : cases) {
    std::string text = "[output]\n[[output.probes]]\n";  // appended, not std::string(...) + ...: GCC 12's
    text += kind;                                         // -Warray-bounds misreads the temporary
    text += bad.probe;
    CAPTURE(text);
    Model model = fluid_model_with_block();
    check_one_problem(text, model, bad);
  }
}

TEST_CASE("bad pressure transducers are reported as file:line:column: key: message") {
  using Bad = BadProbe;
  const char* kind = "kind = \"pressure_transducer\"\n";
  const std::vector<Bad> cases = {
      {"points = [[0.0, 0.03, 0.02]]\ndiameter = -0.01\n", "diameter = ^-0.01", "output.probes[0].diameter",
       "expected a number > 0 [m], got -0.01"},
      {"points = [[0.0, 0.03, 0.02]]\n", "^[[output.probes]]", "output.probes[0].diameter", "missing required key"},
      {"diameter = 0.01\n", "^[[output.probes]]", "output.probes[0].points", "missing required key"},
      {"points = [[0.05, 0.03, 0.02]]\ndiameter = 0.01\n", "points = [^[", "output.probes[0].points[0]",
       "the point lies on no closed wall of the tank"},
      {"points = [[0.05, 0.03, 0.1]]\ndiameter = 0.01\n", "points = [^[", "output.probes[0].points[0]",
       "the point lies on no closed wall of the tank"},  // z_max is open
      {"points = [[0.0, 0.03, 0.0]]\ndiameter = 0.01\n", "points = [^[", "output.probes[0].points[0]",
       "the point lies on the edge of the x_min and z_min walls"},
      {"points = [[0.0, 0.03, 0.003]]\ndiameter = 0.01\n", "points = [^[", "output.probes[0].points[0]",
       "the disc (diameter 0.01 m) reaches beyond the x_min wall (y 0 to 0.06 m, z 0 to 0.1 m"},
      {"points = [[0.0, 0.03, 0.02]]\ndiameter = 0.01\nface = \"x_mx\"\n", "face = ^\"x_mx\"",
       "output.probes[0].face", "expected one of"},
      {"points = [[0.0, 0.03, 0.02]]\ndiameter = 0.01\nface = \"z_max\"\n", "face = ^\"z_max\"",
       "output.probes[0].face", "the z_max face is open"},
      {"points = [[0.0, 0.03, 0.02]]\ndiameter = 0.01\nface = \"x_max\"\n", "points = [^[",
       "output.probes[0].points[0]", "the point is not on the x_max face (x = 0.1 m"},
      {"points = [[0.0, 0.03, 0.02]]\ndiameter = 0.01\naverage_window = -0.001\n", "average_window = ^-0.001",
       "output.probes[0].average_window", "expected a number in [0, 1] [s]"},
      {"points = [[0.0, 0.03, 0.02]]\ndiameter = 0.01\naverage_window = 2\n", "average_window = ^2",
       "output.probes[0].average_window", "expected a number in [0, 1] [s]"},
      {"points = [[0.0, 0.03, 0.02]]\ndiameter = 0.01\nradius = 0.01\n", "^radius", "output.probes[0].radius",
       "unknown key"},
  };
  for (const Bad& bad : cases) {
    std::string text = "[output]\n[[output.probes]]\n";  // appended, not std::string(...) + ...: GCC 12's
    text += kind;                                         // -Warray-bounds misreads the temporary
    text += bad.probe;
    CAPTURE(text);
    Model model = fluid_model();
    model.tank.open_faces = {"z_max"};
    check_one_problem(text, model, bad);
  }
}

TEST_CASE("ProbeWriter: a transducer's rows, instant or the time-weighted mean over its window") {
  Model model = fluid_model();
  model.tank.open_faces = {"z_max"};
  read_output_probes(SceneBuilder().output()
      .probe("pressure_transducer").set("name", "instant")
      .set("points", std::vector<Triple>{{0.03, 0.03, 0.0}, {0.0, 0.03, 0.09}}).set("diameter", 0.01)
      .set("interval", 0.003)
      .probe("pressure_transducer").set("name", "mean").set("points", std::vector<Triple>{{0.03, 0.03, 0.0}})
      .set("diameter", 0.01).set("interval", 0.003).set("average_window", 0.002)
      .toml(),
                     model);
  REQUIRE(model.output.probes.size() == 2);
  const fs::path directory = test::scratch_dir("transducer_writer");
  World world;
  world.tank_motion.emplace();
  world.fluid = still_water();
  const FluidParticles at_rest = *world.fluid;
  std::vector<ProbeWriter> writers;
  for (const ProbeModel& probe : model.output.probes) writers.emplace_back(model, probe, directory, world, true);
  for (ProbeWriter& writer : writers) writer.write(world);
  // Steps of 1 ms; after step k every fluid pressure is 100 k Pa above the hydrostatic one, so the floor disc
  // reads rho g H + 100 k = 490.5 + 100 k.
  for (int k = 1; k <= 6; ++k) {
    world.step = static_cast<std::uint64_t>(k);
    world.time = 1e-3 * k;
    for (std::size_t j = 0; j < world.fluid->size(); ++j) world.fluid->pressure[j] = at_rest.pressure[j] + 100.0 * k;
    for (ProbeWriter& writer : writers) writer.write_if_due(world);
  }
  // Instant: the reading at t = 0, 3 and 6 ms; the disc high on the x_min wall is in air: 0, not empty.
  CHECK(test::file_lines(directory / "probe_instant.csv") ==
        std::vector<std::string>{"time_s,step,p0_Pa,p1_Pa", "0,0,490.5,0", "0.0030000000000000001,3,790.5,0",
                                 "0.0060000000000000001,6,1090.5,0"});
  // Mean over 2 ms: the steps that ended in (1, 3] ms and (4, 6] ms, equally long: +250 and +550 Pa.
  CHECK(test::file_lines(directory / "probe_mean.csv") ==
        std::vector<std::string>{"time_s,step,p0_Pa", "0,0,490.5", "0.0030000000000000001,3,740.5",
                                 "0.0060000000000000001,6,1040.5"});
}

TEST_CASE("a scene with pressure transducers runs and writes their CSV, and on resume the rows go on") {
  const std::string output = SceneBuilder(SceneBuilder::kSpaced).output().set("checkpoint_interval", 0.005)
      .probe("pressure_transducer").set("name", "walls")
      .set("points", std::vector<Triple>{{0.1, 0.0, 0.005}, {0.12, 0.0, 0.0}, {0.14, 0.0, 0.025}})
      .set("diameter", 0.005).set("interval", 0.002)
      .probe("pressure_transducer").set("name", "mean").set("face", "x_min")
      .set("points", std::vector<Triple>{{0.1, 0.0, 0.005}}).set("diameter", 0.005).set("interval", 0.002)
      .set("average_window", 0.003)
      .toml();
  const fs::path directory = test::scratch_dir("transducer_run");
  const fs::path a = directory / "a";
  auto simulation = Simulation::from_model(parse_scene(test::fluid_scene_text(output), "fluid.toml"));
  RunOptions options;
  options.out_dir = a.string();
  options.threads = 1;
  REQUIRE(simulation->run(options).exit_code == kExitOk);
  const std::vector<std::string> walls = test::file_lines(a / "probe_walls.csv");
  REQUIRE(walls.size() == 7);  // t = 0, 0.002, ..., 0.01
  CHECK(walls[0] == "time_s,step,p0_Pa,p1_Pa,p2_Pa");
  for (std::size_t row = 1; row < walls.size(); ++row) {
    CAPTURE(walls[row]);
    std::vector<double> values;
    std::stringstream fields(walls[row]);
    for (std::string field; std::getline(fields, field, ',');) values.push_back(std::stod(field));
    REQUIRE(values.size() == 5);
    // Under water on the x_min wall and the floor: positive; high on the x_max wall, in air: 0.
    CHECK(values[2] > 0.0);
    CHECK(values[3] > 0.0);
    CHECK(values[4] == 0.0);
  }
  const std::vector<std::string> mean = test::file_lines(a / "probe_mean.csv");
  REQUIRE(mean.size() == 7);
  CHECK(mean[0] == "time_s,step,p0_Pa");
  CHECK(mean[1] == walls[1].substr(0, walls[1].find(',', 4)));  // t = 0: the initial reading alone

  // Resumed from t = 0.005: the instant readings go on identically; the mean's window restarts at the resume, so
  // only its rows up to the checkpoint are the same as before (docs/SCENES.md).
  const fs::path b = directory / "b";
  fs::copy(a, b, fs::copy_options::recursive);
  auto resumed = Simulation::from_checkpoint((b / "checkpoints" / "step_0000000005.ckpt").string());
  options.out_dir = b.string();
  REQUIRE(resumed->run(options).exit_code == kExitOk);
  CHECK(test::file_lines(b / "probe_walls.csv") == walls);
  const std::vector<std::string> resumed_mean = test::file_lines(b / "probe_mean.csv");
  REQUIRE(resumed_mean.size() == 7);
  CHECK(std::vector<std::string>(resumed_mean.begin(), resumed_mean.begin() + 4) ==
        std::vector<std::string>(mean.begin(), mean.begin() + 4));
}

TEST_CASE("driven_flow probe: body force, bulk velocity and each lid's force and shear over its area") {
  Model model = fluid_model();
  ParticleBoxModel lid;
  lid.lid = true;
  lid.lid_area = 0.01;
  model.fluid.wall_boxes = {lid, ParticleBoxModel{}, lid};  // two lids and a plain wall box between them
  read_output_probes("[output]\n[[output.probes]]\nkind = \"driven_flow\"\n", model);
  REQUIRE(model.output.probes.size() == 1);
  CHECK(model.output.probes[0].lid_areas == std::vector<double>{0.01, 0.01});
  const fs::path directory = test::scratch_dir("driven_flow_probe");
  World world;
  world.tank_motion.emplace();
  world.fluid = still_water();
  for (std::size_t i = 0; i < world.fluid->size(); ++i)
    if (world.fluid->kind[i] == kFluidKind) world.fluid->velocity[i] = Vec3(0.25, 0.0, 0.0);
  world.fluid_summary.emplace();
  world.fluid_summary->body_force = 0.5;
  world.fluid_summary->lid_force = {Vec3(0.02, 0.0, -0.01), Vec3(-0.005, 0.0, 0.0)};
  ProbeWriter(model, model.output.probes[0], directory, world, true).write(world);
  const std::vector<std::string> lines = test::file_lines(directory / "probe_driven_flow.csv");
  REQUIRE(lines.size() == 2);
  CHECK(lines[0] == "time_s,step,body_force_m_s2,bulk_velocity_m_s,lid0_fx_N,lid0_fy_N,lid0_fz_N,lid0_shear_Pa,"
                    "lid1_fx_N,lid1_fy_N,lid1_fz_N,lid1_shear_Pa");
  CHECK(lines[1] == "0,0,0.5,0.25,0.02,0,-0.01,2,-0.005,0,0,-0.5");
}

TEST_CASE("in a tank periodic along x a pressure sensor on the seam reads the particles across it") {
  // Water filling a tank periodic along x, p = rho g (H - z) + A sin(2 pi x / L): the Shepard average of a sensor at a
  // point where the sine is odd (x = 0 on the seam, and x = L/2) cancels the sine term when the support is whole, so
  // both read rho g (H - z) to rounding (kPressureTolerance). A sensor that did not see across the seam would keep
  // only the particles at x > 0 and read about A/2 too much.
  const double amplitude = 100.0;  // [Pa]
  const double length = kTankSize.x();
  FluidParticles particles;
  append_layout(particles,
                fluid_box_layout(Vec3::Zero(), Vec3::Zero(), Vec3(length, kTankSize.y(), kDepth), kProbeSpacing));
  append_layout(particles, tank_wall_layout(Vec3::Zero(), kTankSize, {"z_max"}, kProbeSpacing, kRadiusRatio * kProbeSpacing,
                                            {true, false, false}));
  for (std::size_t j = 0; j < particles.size(); ++j)
    if (particles.kind[j] == static_cast<std::int32_t>(FluidKind::kFluid))
      particles.pressure[j] = kDensity * kGravity * (kDepth - particles.position[j].z()) +
                              amplitude * std::sin(2.0 * std::numbers::pi * particles.position[j].x() / length);
  FluidProbeSettings s = settings();
  s.period = Vec3(length, 0.0, 0.0);
  const TankMotion at_rest;
  for (const double x : {0.0, 0.5 * length}) {
    const double z = 0.02;
    const double reading = fluid_pressure_at(particles, s, at_rest, Vec3(x, 0.03, z));
    INFO("sensor at x = " << x);
    CHECK(std::abs(reading - kDensity * kGravity * (kDepth - z)) < kPressureTolerance);
  }
  // Without the period the seam's sensor sees one side only.
  const double one_sided = fluid_pressure_at(particles, settings(), at_rest, Vec3(0.0, 0.03, 0.02));
  CHECK(one_sided - kDensity * kGravity * (kDepth - 0.02) > 0.1 * amplitude);
}
