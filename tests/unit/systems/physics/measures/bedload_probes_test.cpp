// The bed-load probes (engine/output/bedload_probes.*, systems/physics/bedload.*): known answers on grains and
// particles set directly in the components (fraction moving, planar packing density of a square lattice, flux of a
// rigid block, layer means of a linear shear, the floor's viscous stress of a linear shear on the MPS lattice, the
// Shields number), the scene keys and their errors, and the probe files a short run writes.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "systems/physics/measures/bedload_probes.hpp"
#include "engine/output/probes.hpp"
#include "engine/scene/scene.hpp"
#include "systems/physics/measures/bedload.hpp"
#include "systems/physics/mps/mps_kernel.hpp"
#include "tests/support/test_support.hpp"
#include "tests/support/scene_builder.hpp"

using namespace riffle;
using riffle::test::SceneBuilder;

namespace {
// A layer of glass grains on the floor of test::fluid_scene_text's tank, under its water.
const std::string kGlassGrains = SceneBuilder().within("solids")
    .block({.min = {0.105, -0.005, 0.002}, .max = {0.135, 0.005, 0.004}, .spacing = 0.002, .radius = 0.0009,
            .material = "glass"})
    .toml();

TankFrame box_frame(const Vec3& size, const Vec3& displacement = Vec3::Zero(), const Vec3& velocity = Vec3::Zero()) {
  TankFrame frame;
  frame.size = size;
  frame.displacement = displacement;
  frame.velocity = velocity;
  return frame;
}

/// A square lattice of touching spheres of diameter d, nx by ny, centres at height z, offset by `shift`.
void add_lattice(Solids& solids, std::size_t nx, std::size_t ny, double d, double z, const Vec3& shift,
                 std::int32_t size_class, const Vec3& velocity = Vec3::Zero()) {
  for (std::size_t j = 0; j < ny; ++j)
    for (std::size_t i = 0; i < nx; ++i)
      solids.add(shift + Vec3((static_cast<double>(i) + 0.5) * d, (static_cast<double>(j) + 0.5) * d, z), velocity,
                 0.5 * d, 2500.0, 0, size_class);
}
}  // namespace

TEST_CASE("sphere_slab_volume, covered_length and shields_number") {
  const double r = 0.002;
  const double sphere = 4.0 / 3.0 * std::numbers::pi * r * r * r;
  CHECK(sphere_slab_volume(r, 0.0, -1.0, 1.0) == doctest::Approx(sphere).epsilon(1e-14));
  CHECK(sphere_slab_volume(r, 0.0, 0.0, 1.0) == doctest::Approx(0.5 * sphere).epsilon(1e-14));
  // A cap of height h = r/2: pi h^2 (3r - h)/3.
  CHECK(sphere_slab_volume(r, 0.0, 0.5 * r, 1.0) ==
        doctest::Approx(std::numbers::pi * 0.25 * r * r * (3.0 * r - 0.5 * r) / 3.0).epsilon(1e-13));
  CHECK(sphere_slab_volume(r, 0.0, 2.0 * r, 3.0 * r) == 0.0);

  std::vector<std::pair<double, double>> intervals = {{0.1, 0.3}, {0.2, 0.4}, {0.6, 0.7}};
  CHECK(covered_length(intervals, 1.0) == doctest::Approx(0.4));
  intervals = {{0.9, 1.2}, {-0.05, 0.1}};  // over the end and over the start: wrapped, [0.9, 1) + [0, 0.2) + [0.95, 1)
  CHECK(covered_length(intervals, 1.0) == doctest::Approx(0.3));
  intervals = {{0.0, 2.0}};
  CHECK(covered_length(intervals, 1.0) == 1.0);

  // Theta = tau / ((rho_p - rho_f) g d): 1 Pa on 1 mm quartz in water.
  CHECK(shields_number(1.0, 2650.0, 1000.0, 9.81, 1e-3) == doctest::Approx(1.0 / (1650.0 * 9.81 * 1e-3)));
  CHECK(shields_number(-2.0, 2650.0, 1000.0, -9.81, 2e-3) == doctest::Approx(-2.0 / (1650.0 * 9.81 * 2e-3)));
  CHECK(std::isnan(shields_number(1.0, 1000.0, 1000.0, 9.81, 1e-3)));
}

TEST_CASE("the moving fraction per class counts grains faster than the threshold relative to the tank") {
  const Vec3 tank_velocity(0.3, -0.1, 0.05);
  Solids solids;
  // Class 0: half of 8 small grains at 0.02 m/s relative to the tank, half at rest in it; class 2: 3 large at rest.
  for (int k = 0; k < 8; ++k)
    solids.add(Vec3(0.01 * k, 0.0, 0.01), tank_velocity + (k % 2 ? Vec3(0.02, 0.0, 0.0) : Vec3::Zero()), 0.0005,
               2500.0, 0, 0);
  for (int k = 0; k < 3; ++k) solids.add(Vec3(0.01 * k, 0.05, 0.01), tank_velocity, 0.001, 2500.0, 0, 2);
  const GrainClasses classes = grain_classes(solids);
  REQUIRE(classes.classes == std::vector<std::int32_t>{0, 2});
  CHECK(classes.diameter[0] == doctest::Approx(0.001));
  CHECK(classes.diameter[1] == doctest::Approx(0.002));
  CHECK(classes.density[1] == doctest::Approx(2500.0));
  const TankFrame frame = box_frame(Vec3(0.1, 0.1, 0.1), Vec3(0.01, 0.0, 0.0), tank_velocity);
  const std::vector<double> fractions = moving_fractions(solids, classes, frame, 0.01);
  REQUIRE(fractions.size() == 3);
  CHECK(fractions[0] == 0.5);
  CHECK(fractions[1] == 0.0);
  CHECK(fractions[2] == doctest::Approx(4.0 / 11.0));
  // A threshold above the speed: nothing moves; in the lab frame (tank at rest) every grain would.
  CHECK(moving_fractions(solids, classes, frame, 0.025)[2] == 0.0);
  CHECK(moving_fractions(solids, classes, box_frame(Vec3(0.1, 0.1, 0.1)), 0.01)[2] == 1.0);
  // Fixed grains (a rough floor) count in neither the moving nor the total: one moving, one resting small grain
  // and every large one fixed leave 3 of 6 small grains moving and no large grain counted.
  solids.fixed[1] = solids.fixed[2] = 1;
  for (int k = 8; k < 11; ++k) solids.fixed[static_cast<std::size_t>(k)] = 1;
  const std::vector<double> floor_left_out = moving_fractions(solids, classes, frame, 0.01);
  CHECK(floor_left_out[0] == 0.5);
  CHECK(std::isnan(floor_left_out[1]));
  CHECK(floor_left_out[2] == 0.5);
}

TEST_CASE("the planar packing density of a top layer of touching spheres on a square lattice is pi/4") {
  const double d = 0.002;
  const std::size_t nx = 10, ny = 8;
  const Vec3 displacement(0.0123, -0.0031, 0.004);  // the tank moved: the lattice moved with it
  const TankFrame frame = box_frame(Vec3(nx * d, ny * d, 0.05), displacement);
  Solids solids;
  // The top layer at 5 mm, a lower layer 1.5 d below in its holes (not in the top layer), off the lattice by
  // 0.3 d in x so that some discs reach over the side (wrapped: the footprint is periodic).
  add_lattice(solids, nx, ny, d, 0.005, displacement + Vec3(0.3 * d, 0.0, 0.0), 1);
  add_lattice(solids, nx, ny, d, 0.005 - 1.5 * d, displacement + Vec3(0.8 * d, 0.5 * d, 0.0), 1);
  TopLayerSettings settings;
  const PackingDensity top = packing_density(solids, frame, settings);
  CHECK(top.grains == nx * ny);
  CHECK(top.lambda == doctest::Approx(std::numbers::pi / 4.0).epsilon(1e-3));  // rows d/64 apart: 6e-4 from the midpoint rule

  SUBCASE("moving grains are not in the layer") {
    Solids single_layer;
    add_lattice(single_layer, nx, ny, d, 0.005, displacement + Vec3(0.3 * d, 0.0, 0.0), 1);
    for (std::size_t i = 0; i < nx * ny; i += 2) single_layer.velocity[i] = Vec3(0.05, 0.0, 0.0);  // even columns
    const PackingDensity half = packing_density(single_layer, frame, settings);
    CHECK(half.grains == nx * ny / 2);
    CHECK(half.lambda == doctest::Approx(std::numbers::pi / 8.0).epsilon(1e-3));
    // Where the top grain moves, the resting grain below it is the local top: it is in the layer.
    for (std::size_t i = 0; i < nx * ny; i += 2) solids.velocity[i] = Vec3(0.05, 0.0, 0.0);
    CHECK(packing_density(solids, frame, settings).grains > nx * ny / 2);
  }
  SUBCASE("a fixed bottom height takes the seed's definition") {
    // Everything above the floor: both layers, whose discs overlap: the union, not the sum.
    settings.bottom = 0.0;
    const PackingDensity both = packing_density(solids, frame, settings);
    CHECK(both.grains == 2 * nx * ny);
    CHECK(both.lambda < std::numbers::pi / 2.0);
    CHECK(both.lambda > std::numbers::pi / 4.0);
    settings.bottom = 0.005 - 0.5 * d;  // between the layers: the top layer only
    const PackingDensity upper = packing_density(solids, frame, settings);
    CHECK(upper.grains == nx * ny);
    CHECK(upper.lambda == doctest::Approx(std::numbers::pi / 4.0).epsilon(1e-3));
  }
  SUBCASE("a single disc") {
    Solids one;
    one.add(Vec3(0.01, 0.008, 0.003), Vec3::Zero(), 0.0015, 2500.0, 0, 0);
    const PackingDensity single = packing_density(one, box_frame(Vec3(0.02, 0.016, 0.05)), settings);
    CHECK(single.grains == 1);
    CHECK(single.lambda == doctest::Approx(std::numbers::pi * 0.0015 * 0.0015 / (0.02 * 0.016)).epsilon(1e-3));
  }
}

TEST_CASE("the bed-load flux of a rigid block of grains moving at U is its solid volume times U over L W") {
  const double U = 0.07;
  const Vec3 tank_velocity(-0.2, 0.0, 0.0);
  Solids solids;
  add_lattice(solids, 5, 4, 0.002, 0.01, Vec3::Zero(), 0, tank_velocity + Vec3(U, 0.01, 0.0));
  add_lattice(solids, 3, 2, 0.004, 0.02, Vec3::Zero(), 1, tank_velocity + Vec3(U, 0.01, 0.0));
  add_lattice(solids, 3, 2, 0.004, 0.002, Vec3::Zero(), 1, tank_velocity);  // resting grains add nothing
  const TankFrame frame = box_frame(Vec3(0.03, 0.02, 0.1), Vec3::Zero(), tank_velocity);
  const std::vector<double> flux = bedload_flux(solids, grain_classes(solids), frame);
  const double small = 20 * 4.0 / 3.0 * std::numbers::pi * 1e-9, large = 6 * 4.0 / 3.0 * std::numbers::pi * 8e-9;
  REQUIRE(flux.size() == 3);
  CHECK(flux[0] == doctest::Approx(small * U / (0.03 * 0.02)).epsilon(1e-12));
  CHECK(flux[1] == doctest::Approx(large * U / (0.03 * 0.02)).epsilon(1e-12));
  CHECK(flux[2] == doctest::Approx((small + large) * U / (0.03 * 0.02)).epsilon(1e-12));

  RunningMean mean;
  CHECK(mean.add(0.0, {1.0}) == std::vector<double>{1.0});
  CHECK(mean.add(0.1, {3.0})[0] == doctest::Approx(3.0));
  CHECK(mean.add(0.4, {1.0})[0] == doctest::Approx((0.1 * 3.0 + 0.3 * 1.0) / 0.4));
}

TEST_CASE("the velocity profile of a linear shear has its layer means on the line, grains by volume") {
  const double h = 0.004, a = 2.0;  // [m], [1/s]: u_x = a z
  const Vec3 tank_velocity(0.1, 0.0, 0.0);
  const Vec3 displacement(0.0, 0.0, 0.002);
  FluidParticles fluid;
  // Two fluid particles per layer at (k + 1/4) h and (k + 3/4) h above the floor; a wall particle that never counts.
  for (int k = 0; k < 5; ++k)
    for (double part : {0.25, 0.75}) {
      const double z = (k + part) * h;
      fluid.add(Vec3(0.01, 0.01, z + displacement.z()), tank_velocity + Vec3(a * z, 0.0, 0.3), FluidKind::kFluid);
    }
  fluid.add(Vec3(0.01, 0.01, 0.5 * h), Vec3(9.0, 0.0, 0.0), FluidKind::kWall);
  Solids solids;
  // One grain of radius h/2 centred on the boundary of layers 1 and 2: half its volume in each.
  solids.add(Vec3(0.01, 0.01, 2.0 * h + displacement.z()), tank_velocity + Vec3(0.05, 0.0, 0.0), 0.5 * h, 2500.0, 0,
             0);
  const TankFrame frame = box_frame(Vec3(0.02, 0.03, 0.02), displacement, tank_velocity);
  const std::vector<ProfileLayer> layers = velocity_profile(&solids, &fluid, frame, h, 5);
  REQUIRE(layers.size() == 5);
  const double half_volume = 2.0 / 3.0 * std::numbers::pi * std::pow(0.5 * h, 3);
  for (std::size_t k = 0; k < 5; ++k) {
    CAPTURE(k);
    CHECK(layers[k].z_low == doctest::Approx(k * h));
    CHECK(layers[k].fluid_particles == 2);
    CHECK(layers[k].fluid_ux == doctest::Approx(a * (k + 0.5) * h).epsilon(1e-12));
    if (k == 1 || k == 2) {
      CHECK(layers[k].grain_ux == doctest::Approx(0.05));
      CHECK(layers[k].solid_fraction == doctest::Approx(half_volume / (0.02 * 0.03 * h)).epsilon(1e-12));
    } else {
      CHECK(std::isnan(layers[k].grain_ux));
      CHECK(layers[k].solid_fraction == 0.0);
    }
  }
}

TEST_CASE("the bed shear stress: the water's x force on the grains plus the floor's viscous share, per area") {
  // A linear shear u_x = a z over the whole MPS lattice, fluid above the floor plane z = 0 and boundary (wall and
  // dummy) particles below it, 3 layers deep (r_e = 2.4 l0) and reaching r_e beyond the fluid's columns: the
  // lambda0 Laplacian is exact for it, and the momentum it carries across the floor plane is rho nu a per area
  // exactly on the lattice (sum over pairs across the plane of w dz^2 = lambda0 n0 / 6 per particle column).
  const double l0 = 0.005, a = 3.0;
  ShearSettings settings;
  settings.spacing = l0;
  settings.effective_radius = 2.4 * l0;
  settings.density = 1000.0;
  settings.kinematic_viscosity = 1e-6;
  const LatticeConstants constants = lattice_constants(3, l0, settings.effective_radius);
  settings.number_density = constants.number_density;
  settings.laplacian_lambda = constants.laplacian_lambda;
  const int columns = 4, margin = 3, fluid_layers = 4, boundary_layers = 3;
  FluidParticles fluid;
  for (int k = -boundary_layers; k < fluid_layers; ++k)
    for (int j = -margin; j < columns + margin; ++j)
      for (int i = -margin; i < columns + margin; ++i) {
        const bool inside = i >= 0 && i < columns && j >= 0 && j < columns;
        if (k >= 0 && !inside) continue;
        const Vec3 position((i + 0.5) * l0, (j + 0.5) * l0, (k + 0.5) * l0);
        fluid.add(position, Vec3(a * position.z(), 0.0, 0.0),
                  k >= 0 ? FluidKind::kFluid : (k == -1 ? FluidKind::kWall : FluidKind::kDummy));
      }
  const TankFrame frame = box_frame(Vec3(columns * l0, columns * l0, 0.1));
  BedShear shear = bed_shear_stress(nullptr, &fluid, settings, frame);
  CHECK(shear.grains_fx == 0.0);
  CHECK(shear.tau == doctest::Approx(settings.density * settings.kinematic_viscosity * a).epsilon(1e-10));

  Solids solids;
  for (int k = 0; k < 4; ++k) {
    const std::size_t slot = solids.add(Vec3(0.01, 0.01, 0.01), Vec3::Zero(), 0.001, 2650.0, 0, 0);
    solids.drag_force[slot] = Vec3(1e-4, 5.0, 0.0);
    solids.pressure_force[slot] = Vec3(2e-5, 0.0, 1.0);
    solids.added_mass_force[slot] = Vec3(-1e-5, 0.0, 0.0);
    solids.history_force[slot] = Vec3(3e-6, 0.0, 0.0);
    solids.lubrication_force[slot] = Vec3(1.0, 0.0, 0.0);  // grain-grain through the water: not the bed's load
  }
  shear = bed_shear_stress(&solids, &fluid, settings, frame);
  CHECK(shear.grains_fx == doctest::Approx(4 * (1e-4 + 2e-5 - 1e-5 + 3e-6)).epsilon(1e-12));
  CHECK(shear.tau == doctest::Approx(shear.grains_fx / frame.area() + 1000.0 * 1e-6 * a).epsilon(1e-10));
}

TEST_CASE("the bed-load probes' scene keys: defaults and errors") {
  const std::string grains = test::small_scene_text(SceneBuilder().output()
      .probe("moving_fraction").set("interval", 0.01)
      .probe("packing_density").set("threshold", 0.02).set("layer_bottom", 0.004).probe("bedload_flux")
      .probe("velocity_profile").set("layer_thickness", 0.002).toml());
  const Model model = parse_scene(grains, "bedload.toml");
  REQUIRE(model.output.probes.size() == 4);
  CHECK(model.output.probes[0].kind == ProbeModel::Kind::kMovingFraction);
  CHECK(model.output.probes[0].threshold == 0.01);
  CHECK(model.output.probes[0].file == "probe_moving_fraction.csv");
  CHECK(model.output.probes[1].threshold == 0.02);
  CHECK(model.output.probes[1].layer_bottom == 0.004);
  CHECK(model.output.probes[1].layer_depth == 0.0);
  CHECK(model.output.probes[2].kind == ProbeModel::Kind::kBedloadFlux);
  CHECK(model.output.probes[3].layer_thickness == 0.002);

  // With [fluid], a velocity profile's layers default to l0; the shear stress has no lid column (no moving lid).
  const Model water = parse_scene(test::fluid_scene_text(kGlassGrains + SceneBuilder().output()
      .probe("velocity_profile").probe("bed_shear_stress").toml()),
                                  "water.toml");
  REQUIRE(water.output.probes.size() == 2);
  CHECK(water.output.probes[0].layer_thickness == 0.005);
  CHECK_FALSE(water.output.probes[1].lid);

  struct Bad {
    std::string scene;
    const char* key;
    const char* message;
  };
  const std::vector<Bad> cases = {
      {test::small_scene_text("[output]\n[[output.probes]]\nkind = \"moving_fraction\"\nthreshold = -0.1\n"),
       "output.probes[0].threshold", "expected a number > 0"},
      {test::small_scene_text(
           "[output]\n[[output.probes]]\nkind = \"packing_density\"\nlayer_depth = 0.01\nlayer_bottom = 0.01\n"),
       "output.probes[0].layer_bottom", "not both"},
      {test::small_scene_text("[output]\n[[output.probes]]\nkind = \"velocity_profile\"\n"),
       "output.probes[0].layer_thickness", "missing required key"},
      {test::small_scene_text(
           "[output]\n[[output.probes]]\nkind = \"velocity_profile\"\nlayer_thickness = 1e-9\n"),
       "output.probes[0].layer_thickness", "more than 1e5 layers"},
      {test::small_scene_text("[output]\n[[output.probes]]\nkind = \"bed_shear_stress\"\n"),
       "output.probes[0].kind", "has no [fluid]"},
      {test::fluid_scene_text("[output]\n[[output.probes]]\nkind = \"bedload_flux\"\n"), "output.probes[0].kind",
       "measures grains"},
      {test::small_scene_text("[output]\n[[output.probes]]\nkind = \"bedload_flux\"\nthreshold = 0.1\n"),
       "output.probes[0].threshold", "unknown key"},
  };
  for (const Bad& bad : cases) {
    CAPTURE(bad.scene);
    const std::vector<std::string> problems = test::problems_of(bad.scene, "bad.toml");
    REQUIRE(problems.size() == 1);
    CHECK_MESSAGE(problems[0].find(std::string(": ") + bad.key + ": ") != std::string::npos, problems[0]);
    CHECK_MESSAGE(problems[0].find(bad.message) != std::string::npos, problems[0]);
    CHECK(problems[0].rfind("bad.toml:", 0) == 0);
  }
}

namespace {
std::vector<std::string> file_lines(const std::filesystem::path& path) {
  std::ifstream file(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(file, line);) lines.push_back(line);
  return lines;
}
std::vector<std::string> fields_of(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  for (std::size_t comma; (comma = line.find(',', start)) != std::string::npos; start = comma + 1)
    fields.push_back(line.substr(start, comma - start));
  fields.push_back(line.substr(start));
  return fields;
}
}  // namespace

TEST_CASE("the bed-load probe files: headers per class and rows from the grains and water set in the World") {
  Model model = parse_scene(test::fluid_scene_text(kGlassGrains + SceneBuilder().output().probe("moving_fraction")
      .probe("packing_density").probe("bedload_flux").probe("velocity_profile").probe("bed_shear_stress").toml()),
                            "water.toml");
  REQUIRE(model.output.probes.size() == 5);
  // Two small grains (class 0, one moving at 0.02 m/s relative to the tank) and one large grain at rest (class 1)
  // in the tank (inner box x 0.1-0.14, y -0.01-0.01, z 0-0.03 at rest), which moves at 0.1 m/s along x.
  World world;
  world.tank_motion.emplace();
  world.tank_motion->velocity = Vec3(0.1, 0.0, 0.0);
  world.solids.emplace();
  Solids& solids = *world.solids;
  solids.add(Vec3(0.11, 0.0, 0.001), Vec3(0.12, 0.0, 0.0), 0.0009, 2500.0, 0, 0);
  solids.add(Vec3(0.12, 0.0, 0.001), Vec3(0.1, 0.0, 0.0), 0.0009, 2500.0, 0, 0);
  solids.add(Vec3(0.13, 0.0, 0.002), Vec3(0.1, 0.0, 0.0), 0.002, 2500.0, 0, 1);
  for (std::size_t i = 0; i < 3; ++i) solids.drag_force[i] = Vec3(1e-4, 0.0, 0.0);
  world.fluid.emplace();
  world.fluid->add(Vec3(0.12, 0.0, 0.0125), Vec3(0.3, 0.0, 0.0), FluidKind::kFluid);
  const std::filesystem::path directory = test::scratch_dir("bedload_probe_files");
  for (const ProbeModel& probe : model.output.probes) ProbeWriter(model, probe, directory, world, true).write(world);

  const auto moving = file_lines(directory / "probe_moving_fraction.csv");
  REQUIRE(moving.size() == 2);
  CHECK(moving[0] == "time_s,step,class_0_moving_fraction,class_1_moving_fraction,all_moving_fraction");
  CHECK(moving[1] == "0,0,0.5,0,0.333333333");

  const auto packing = file_lines(directory / "probe_packing_density.csv");
  REQUIRE(packing.size() == 2);
  CHECK(packing[0] == "time_s,step,lambda,top_layer_grains");
  // The plan is cut into 10 x 5 columns 4 mm wide: each grain is alone in its column and so the top of it; the
  // moving one is left out: two discs, pi (0.9^2 + 2^2) mm^2 over 40 x 20 mm^2.
  const auto packing_fields = fields_of(packing[1]);
  REQUIRE(packing_fields.size() == 4);
  CHECK(packing_fields[3] == "2");
  CHECK(std::stod(packing_fields[2]) == doctest::Approx(std::numbers::pi * (0.81 + 4.0) * 1e-6 / 8e-4).epsilon(1e-3));

  const auto flux = file_lines(directory / "probe_bedload_flux.csv");
  REQUIRE(flux.size() == 2);
  CHECK(flux[0] == "time_s,step,class_0_q_m2_s,class_1_q_m2_s,all_q_m2_s,class_0_q_mean_m2_s,class_1_q_mean_m2_s,"
                   "all_q_mean_m2_s");
  const auto flux_fields = fields_of(flux[1]);
  REQUIRE(flux_fields.size() == 8);
  const double q0 = 4.0 / 3.0 * std::numbers::pi * std::pow(0.0009, 3) * 0.02 / 8e-4;
  CHECK(std::stod(flux_fields[2]) == doctest::Approx(q0).epsilon(1e-8));
  CHECK(std::stod(flux_fields[3]) == 0.0);
  CHECK(std::stod(flux_fields[5]) == doctest::Approx(q0).epsilon(1e-8));  // the mean of one row is itself

  const auto profile = file_lines(directory / "probe_velocity_profile.csv");
  REQUIRE(profile.size() == 7);  // header + 6 layers of l0 = 5 mm over the 3 cm tank
  CHECK(profile[0] == "time_s,step,layer,z_low_m,z_high_m,fluid_particles,fluid_ux_m_s,grain_ux_m_s,solid_fraction");
  CHECK(profile[3] == "0,0,2,0.01,0.015,1,0.2,,0");

  const auto shear = file_lines(directory / "probe_bed_shear_stress.csv");
  REQUIRE(shear.size() == 2);
  CHECK(shear[0] == "time_s,step,grains_fx_N,floor_fx_N,tau_b_Pa,class_0_diameter_m,class_1_diameter_m,"
                    "class_0_shields_b,class_1_shields_b");
  const auto shear_fields = fields_of(shear[1]);
  REQUIRE(shear_fields.size() == 9);
  const double tau = 3e-4 / 8e-4;
  CHECK(std::stod(shear_fields[4]) == doctest::Approx(tau).epsilon(1e-8));
  CHECK(std::stod(shear_fields[8]) == doctest::Approx(tau / (1500.0 * 9.81 * 0.004)).epsilon(1e-8));
}

TEST_CASE("the lid's shear stress is the x force the first moving lid exerts on the water over its area") {
  Model model;
  model.fluid.enabled = true;
  ParticleBoxModel still_lid, moving_lid, plain_wall;
  still_lid.lid = true;  // a lid at rest is a no-slip wall, not the drive
  moving_lid.lid = true;
  moving_lid.lid_velocity = 0.5;
  moving_lid.lid_area = 0.02;
  model.fluid.wall_boxes = {plain_wall, still_lid, moving_lid};
  CHECK(model_has_lid(model));
  World world;
  CHECK_FALSE(lid_shear_stress(model, world).has_value());  // no step has summed the lids' forces yet
  world.fluid_summary.emplace();
  world.fluid_summary->lid_force = {Vec3(1.0, 0.0, 0.0), Vec3(0.004, 0.0, -3.0)};  // per lid, in scene order
  REQUIRE(lid_shear_stress(model, world).has_value());
  CHECK(*lid_shear_stress(model, world) == doctest::Approx(0.2).epsilon(1e-14));
  model.fluid.wall_boxes = {plain_wall, still_lid};
  CHECK_FALSE(model_has_lid(model));
  CHECK_FALSE(lid_shear_stress(model, world).has_value());
}
