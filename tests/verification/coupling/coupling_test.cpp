// Fluid-grain coupling (seed 000 Secs. 3.2-3.3, numerics.md 5): the drag law's limits, the settling velocity of a
// single grain, a neutrally buoyant grain, and exact momentum exchange between grains and fluid.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "engine/setup/fluid_layout.hpp"
#include "engine/run/simulation.hpp"
#include "systems/physics/coupling/drag_law.hpp"
#include "systems/coupling/fluid_drag_reaction.hpp"
#include "systems/coupling/solid_drag.hpp"
#include "systems/coupling/solid_drag_law.hpp"
#include "systems/physics/coupling/voidage_grid.hpp"
#include "tests/support/test_support.hpp"
#include "tests/support/scene_builder.hpp"

using namespace riffle;
using riffle::test::SceneBuilder;

namespace {
constexpr double kWaterDensity = 1000.0, kViscosity = 1.0e-3, kGravity = 9.81;

/// Slip speed at which drag_per_volume * V * u equals the net weight (rho_s - rho) V g: bisection.
double terminal_slip(double voidage, double diameter, double solid_density, const CouplingModel& coupling) {
  double low = 0.0, high = 10.0;
  for (int k = 0; k < 200; ++k) {
    const double speed = 0.5 * (low + high);
    const double drag = drag_per_volume(voidage, diameter, speed, kWaterDensity, kViscosity, coupling) * speed;
    (drag > (solid_density - kWaterDensity) * kGravity ? high : low) = speed;
  }
  return 0.5 * (low + high);
}

std::string settling_scene(double solid_density, double height = 0.25) {
  return SceneBuilder().run({.end_time = 1.0, .dt = 1.0e-3, .solid_substeps = 10})
      .material("grain", {.density = solid_density}).material("glass", {.density = 2500.0})
      .tank({.size = {0.1, 0.1, 0.3}, .open_faces = {"z_max"}, .wall_material = "glass"})
      .sphere({.position = {0.05, 0.05, height}, .radius = 0.005, .material = "grain"})
      .fluid({.spacing = 0.01}).fluid_box({0.0, 0.0, 0.0}, {0.1, 0.1, 0.28}).toml();
}
}  // namespace

TEST_CASE("the drag law reduces to single-sphere drag and to Ergun's viscous term") {
  const CouplingModel coupling;
  // eps -> 1: F = 1/2 C_D rho (pi d^2 / 4) u^2 with C_D = 24/Re (1 + 0.15 Re^0.687) (numerics 5.1 check)
  const double d = 0.005, u = 0.1;
  const double reynolds = kWaterDensity * d * u / kViscosity;
  const double drag_coefficient = 24.0 / reynolds * (1.0 + 0.15 * std::pow(reynolds, 0.687));
  const double expected = 0.5 * drag_coefficient * kWaterDensity * std::numbers::pi * d * d / 4.0 * u * u;
  const double volume = std::numbers::pi / 6.0 * d * d * d;
  CHECK(drag_per_volume(1.0, d, u, kWaterDensity, kViscosity, coupling) * volume * u ==
        doctest::Approx(expected).epsilon(1e-12));
  // Creeping flow in a packed bed: beta/(1 - eps) -> 150 mu (1 - eps) / (eps d^2) (Ergun's viscous term)
  const double eps = 0.4;
  CHECK(drag_per_volume(eps, d, 0.0, kWaterDensity, kViscosity, coupling) ==
        doctest::Approx(150.0 * kViscosity * (1.0 - eps) / (eps * d * d)).epsilon(1e-12));
  // Ergun's inertial term with the standard constant F_ch = 1.75/(sqrt(150) eps^1.5) is Gidaspow's
  // beta = 1.75 (1 - eps) rho |du| / d, i.e. beta/(1 - eps) = 1.75 rho |du| / d (numerics 5.1)
  const double inertial = drag_per_volume(eps, d, u, kWaterDensity, kViscosity, coupling) -
                          drag_per_volume(eps, d, 0.0, kWaterDensity, kViscosity, coupling);
  CHECK(inertial == doctest::Approx(1.75 * kWaterDensity * u / d).epsilon(1e-12));
  // The seed's printed exponent 3 makes it eps^-1.5 larger (numerics 5.1): about 4x at eps = 0.4
  CouplingModel printed;
  printed.ergun_inertial_exponent = 3.0;
  const double printed_inertial = drag_per_volume(eps, d, u, kWaterDensity, kViscosity, printed) -
                                  drag_per_volume(eps, d, 0.0, kWaterDensity, kViscosity, printed);
  CHECK(printed_inertial / inertial == doctest::Approx(std::pow(eps, -1.5)).epsilon(1e-12));
}

TEST_CASE("a grain settling in still water reaches the terminal slip velocity of the drag law") {
  auto simulation = Simulation::from_model(parse_scene(settling_scene(1318.0), "settle.toml"));
  for (int step = 0; step < 600; ++step) simulation->step();  // terminal after ~0.4 s (relaxation time ~0.05 s)
  REQUIRE(simulation->world().step_status.ok());
  const Solids& solids = *simulation->world().solids;
  const double slip = (solids.fluid_velocity[0] - solids.velocity[0]).norm();
  const double expected = terminal_slip(solids.voidage[0], 0.01, 1318.0, simulation->model().coupling);
  // The drag's reaction pushes the fluid around the grain, which adds a pressure gradient of about
  // |F_drag| / V_kernel over the sampling sphere of radius d/2 + r_e = 29 mm: a force V/V_kernel ~ 0.5 % of the
  // weight on the grain; the sampled fields move with the grain by at most one spacing. 3 % covers both.
  CHECK(slip == doctest::Approx(expected).epsilon(0.03));
  CHECK(solids.velocity[0][2] < 0.0);
  CHECK(solids.voidage[0] > 0.9);  // a lone grain: only its own volume in the voidage kernel
}

// The same grain read with the ellipsoidal sampling kernel ([coupling] sampling_vertical_radius = 1.5 l0, half the
// kernel's 29 mm along z; docs/COUPLING.md, "A thin bed's sampling"): the water's flow around a lone grain is not
// layered, so a kernel symmetric about the grain reads the same slip (the linear part of the field exactly), within
// the test above's 3 %.
TEST_CASE("a grain settling in still water reaches the same terminal slip with an ellipsoidal sampling kernel") {
  const Model model =
      parse_scene(settling_scene(1318.0) + "[coupling]\nsampling_vertical_radius = 0.015\n", "settle.toml");
  REQUIRE(model.coupling.sampling_vertical_radius == 0.015);
  auto simulation = Simulation::from_model(model);
  for (int step = 0; step < 600; ++step) simulation->step();
  REQUIRE(simulation->world().step_status.ok());
  const Solids& solids = *simulation->world().solids;
  const double slip = (solids.fluid_velocity[0] - solids.velocity[0]).norm();
  const double expected = terminal_slip(solids.voidage[0], 0.01, 1318.0, simulation->model().coupling);
  MESSAGE("terminal slip with R_v = 15 mm: ", slip, " m/s; the drag law's ", expected, " m/s");
  CHECK(slip == doctest::Approx(expected).epsilon(0.03));
  CHECK(solids.velocity[0][2] < 0.0);
}

// [solids] hold_until in water: a steel grain (7800 kg/m^3) held in still water stays exactly in place, then, released,
// starts to settle with the acceleration of its net weight over its mass and added mass (on by default, C_a = 1/2 for
// a lone grain), (rho_s - rho) g / (rho_s + rho/2) = 8.037 m/s^2 (the drag starts at zero). Over the first 19.9 ms its velocity is a tau less what the drag takes: at
// 0.17 m/s Wen & Yu's drag on the 10 mm sphere (Re = 1700) is 1.5 % of the net weight, so the velocity is at most
// ~1 % below a tau; the buoyancy's 2 % error (the test above) is 0.3 % of the net weight. Tolerance: -2 %, +0.5 %.
TEST_CASE("a grain held in still water until hold_until stays put, then settles from rest at its net weight over its "
          "mass and added mass") {
  std::string scene = settling_scene(7800.0, 0.15);
  scene.replace(scene.find("[solids]\n"), 9, "[solids]\nhold_until = 0.10005\n");  // mid-way between sub-steps
  auto simulation = Simulation::from_model(parse_scene(scene, "held_steel.toml"));
  const Solids& solids = *simulation->world().solids;
  const Vec3 start = solids.position[0];
  for (int step = 0; step < 100; ++step) simulation->step();
  REQUIRE(simulation->world().step_status.ok());
  CHECK(solids.position[0] == start);
  CHECK(solids.velocity[0] == Vec3::Zero());
  CHECK(solids.pressure_force[0].z() > 0.0);  // forces are computed while held: its buoyancy
  for (int step = 100; step < 120; ++step) simulation->step();
  REQUIRE(simulation->world().step_status.ok());
  const double tau = simulation->world().time - 0.1001;  // released at the first sub-step start after 0.10005 s
  const double acceleration = (7800.0 - 1000.0) * 9.81 / (7800.0 + 0.5 * 1000.0);
  MESSAGE("after ", tau, " s: v_z = ", solids.velocity[0].z(), " m/s against -a tau = ", -acceleration * tau,
          "; fallen ", start.z() - solids.position[0].z(), " m against a tau^2 / 2 = ", 0.5 * acceleration * tau * tau);
  CHECK(-solids.velocity[0].z() < 1.005 * acceleration * tau);
  CHECK(-solids.velocity[0].z() > 0.98 * acceleration * tau);
  CHECK(start.z() - solids.position[0].z() < 1.005 * 0.5 * acceleration * tau * tau);
  CHECK(start.z() - solids.position[0].z() > 0.98 * 0.5 * acceleration * tau * tau);
  CHECK(std::abs(solids.velocity[0].x()) + std::abs(solids.velocity[0].y()) < 0.01 * acceleration * tau);
}

TEST_CASE("a neutrally buoyant grain stays where it is") {
  // 13 cm deep: the sampling sphere (radius d/2 + r_e = 29 mm) stays clear of the free surface, where the
  // truncated gradient of the surface particles would read low.
  auto simulation = Simulation::from_model(parse_scene(settling_scene(1000.0, 0.15), "neutral.toml"));
  for (int step = 0; step < 500; ++step) simulation->step();
  REQUIRE(simulation->world().step_status.ok());
  const Solids& solids = *simulation->world().solids;
  // numerics 5.4: -V <grad p> must return rho g V within about 2 % in still water.
  const double buoyancy = 1000.0 * 9.81 * std::numbers::pi / 6.0 * 1e-6;
  CHECK(solids.pressure_force[0][2] == doctest::Approx(buoyancy).epsilon(0.02));
  CHECK(std::abs(solids.pressure_force[0][0]) < 0.01 * buoyancy);
  // What is left over drives a creeping drift: under 1 mm/s means an imbalance below ~1e-4 of the weight (Stokes
  // drag of a 10 mm sphere at 1 mm/s is 3 pi mu d u = 1e-7 N against a weight of 5e-3 N), and less than d/10 moved.
  CHECK(std::abs(solids.position[0][2] - 0.15) < 1e-3);
  CHECK(solids.velocity[0].norm() < 1e-3);
}

TEST_CASE("a submerged settled bed leaves the hydrostatic pressure unchanged") {
  // docs/COUPLING.md: the water fills all space, grains included, so a bed at rest changes neither the water's
  // volume nor its pressure; the grains take their buoyancy from the water's pressure gradient. Two runs of 10 cm of
  // still water, one with three layers of 10 mm grains (300, touching, on the floor) left to settle: the mean
  // pressure of every 1 cm layer must agree within the still-water error of MPS itself (0.1 % of rho g H RMS,
  // fluid_hydrostatic_test), and the bed must have come to rest. A water that made room for the grains would rise
  // by the bed's volume over the tank's area, 16 mm, and change the pressure by 16 % of rho g H.
  const std::string water = SceneBuilder().run({.end_time = 1.0, .dt = 1.0e-3})
      .material("grain", {.density = 1318.0, .young_modulus = 1.0e7, .poisson_ratio = 0.3})
      .material("glass", {.density = 2500.0, .young_modulus = 1.0e8, .poisson_ratio = 0.3})
      .contact({.law = "hertz_mindlin", .restitution = 0.5, .friction = 0.4, .max_impact_speed = 0.5})
      .tank({.size = {0.1, 0.1, 0.15}, .open_faces = {"z_max"}, .wall_material = "glass"}).fluid({.spacing = 0.01})
      .fluid_box({0.0, 0.0, 0.0}, {0.1, 0.1, 0.1}).coupling().set("fluid_velocity", "mixture").toml();
  const std::string bed = SceneBuilder()
      .block({.min = {0.005, 0.005, 0.005}, .max = {0.095, 0.095, 0.025}, .spacing = 0.01, .radius = 0.005,
              .material = "grain"})
      .toml();
  auto with_bed = Simulation::from_model(parse_scene(water + bed, "bed.toml"));
  // The same water with one grain far above it (a scene with [contact] needs grains): dry, so it touches nothing.
  auto clear = Simulation::from_model(parse_scene(water + SceneBuilder()
      .sphere({.position = {0.05, 0.05, 0.14}, .radius = 0.005, .material = "grain"}).toml(), "clear.toml"));
  REQUIRE(with_bed->world().solids->size() == 300);
  for (int step = 0; step < 300; ++step) {
    with_bed->step();
    clear->step();
  }
  REQUIRE(with_bed->world().step_status.ok());
  REQUIRE(clear->world().step_status.ok());
  // Hydrostatics is a statement about the pressure against depth: compare the mean pressure of each 1 cm layer
  // of water (particle by particle the two runs drift apart like any two MPS runs a rounding apart).
  const double rho_g_h = kWaterDensity * kGravity * 0.1;
  const auto layer_means = [](const FluidParticles& fluid) {
    std::vector<double> sums(10, 0.0), counts(10, 0.0);
    for (std::size_t i = 0; i < fluid.size(); ++i) {
      if (fluid.kind[i] != static_cast<std::int32_t>(FluidKind::kFluid)) continue;
      const int layer = std::clamp(static_cast<int>(fluid.position[i].z() / 0.01), 0, 9);
      sums[layer] += fluid.pressure[i];
      counts[layer] += 1.0;
    }
    for (int layer = 0; layer < 10; ++layer) sums[layer] /= std::max(counts[layer], 1.0);
    return sums;
  };
  const std::vector<double> bed_layers = layer_means(*with_bed->world().fluid);
  const std::vector<double> clear_layers = layer_means(*clear->world().fluid);
  double largest = 0.0;
  for (int layer = 0; layer < 10; ++layer)
    largest = std::max(largest, std::abs(bed_layers[layer] - clear_layers[layer]) / rho_g_h);
  MESSAGE("largest difference of a layer's mean pressure with and without the bed: " << largest << " rho g H");
  CHECK(largest < 1e-3);
  // The bed has settled: every grain slower than 1 mm/s, and it has sunk by less than a tenth of its diameter.
  const Solids& solids = *with_bed->world().solids;
  double fastest = 0.0, lowest = 1.0;
  for (std::size_t i = 0; i < solids.size(); ++i) {
    fastest = std::max(fastest, solids.velocity[i].norm());
    lowest = std::min(lowest, solids.position[i].z());
  }
  CHECK(fastest < 1e-3);
  CHECK(lowest > 0.005 - 0.001);
}

namespace {
/// The drag impulses given to three grains (2.5, 5 and 7.5 mm) at these centres in a 10 cm cube of water.
const Vec3 kImpulses[] = {Vec3(1.0e-4, -2.0e-5, 3.0e-4), Vec3(-5.0e-5, 7.0e-5, 1.0e-5), Vec3(2.0e-5, 0.0, -4.0e-5)};
const Vec3 kCentres[] = {Vec3(0.05, 0.05, 0.05), Vec3(0.013, 0.021, 0.009), Vec3(0.08, 0.02, 0.06)};

/// A World of water filling a 10 cm cube at l0 = 1 cm and the three grains of kImpulses, each with its impulse;
/// returns their slots.
std::vector<std::size_t> water_cube_with_grains(World& world) {
  test::fill_with_water(world, Vec3(0.1, 0.1, 0.1), 0.01);
  world.solids.emplace();
  std::vector<std::size_t> slots;
  for (int k = 0; k < 3; ++k) {
    slots.push_back(world.solids->add(kCentres[k], Vec3::Zero(), 0.0025 * (k + 1), 1318.0, 0, 0));
    world.solids->drag_impulse[slots.back()] = kImpulses[k];
  }
  return slots;
}

/// Runs the fluid_drag_reaction system once (dt = 1 ms).
void run_drag_reaction(World& world, const Model& model) {
  FluidDragReaction reaction(model);
  const Access access = reaction.access();
  SystemContext context(world, model, reaction, access, 0.0, 1.0e-3);
  reaction.run(context);
}
}  // namespace

TEST_CASE("the fluid receives exactly minus the drag impulse of the grains") {
  const Model model = test::small_coupled_model(0.01);
  World world;
  water_cube_with_grains(world);
  Vec3 given = Vec3::Zero();
  for (const Vec3& impulse : kImpulses) given += impulse;
  run_drag_reaction(world, model);
  Vec3 received = Vec3::Zero();
  for (const Vec3& per_volume : world.fluid->drag_reaction) received += per_volume * 1.0e-6;  // times l0^3
  // Each grain's weights are normalised to one: equal to rounding (a few ulps of the largest impulse).
  CHECK((received + given).norm() < 1e-15);
  for (const Vec3& impulse : world.solids->drag_impulse) CHECK(impulse.isZero(0.0));
}

TEST_CASE("with the self-induced correction, the kernel spreading gives the fluid exactly minus the drag impulse") {
  // docs/COUPLING.md "The undisturbed fluid velocity": the impulse goes to the fluid particles within r + r_e with
  // the normalised sampling weights; each grain's weights sum to one, so the sum is exact to rounding, in both
  // readings (the mixture reading gives the water the impulse over eps: checked against that), with a grain of a
  // bed (eps <= 0.8, grid spreading) among them.
  for (const bool mixture : {false, true}) {
    Model model = test::small_coupled_model(0.01);
    model.coupling.self_induced_velocity = true;
    model.coupling.fluid_velocity = mixture ? CouplingModel::FluidVelocity::kMixture : CouplingModel::FluidVelocity::kPore;
    World world;
    const std::vector<std::size_t> slots = water_cube_with_grains(world);
    const double voidages[] = {0.9, 0.5, 1.0};  // the second, in a bed, keeps the grid spreading
    Vec3 expected = Vec3::Zero();
    for (int k = 0; k < 3; ++k) {
      world.solids->voidage[slots[k]] = voidages[k];
      expected -= mixture ? Vec3(kImpulses[k] / voidages[k]) : kImpulses[k];
    }
    run_drag_reaction(world, model);
    Vec3 received = Vec3::Zero();
    std::size_t touched = 0;
    for (const Vec3& per_volume : world.fluid->drag_reaction) {
      received += per_volume * 1.0e-6;  // times l0^3
      touched += per_volume.isZero(0.0) ? 0 : 1;
    }
    CHECK((received - expected).norm() < 1e-15);
    CHECK(touched > 100);  // spread over the kernel's sphere (r + 2.4 l0), not a few nodes
    for (const Vec3& impulse : world.solids->drag_impulse) CHECK(impulse.isZero(0.0));
  }
}

TEST_CASE("mixture reading: the pore water passes a grain at (u - u_s) / eps and the water takes the drag over eps") {
  // docs/COUPLING.md "The water inside the bed": with fluid_velocity = "mixture" the sampled MPS velocity u is the
  // mixture's volume flux, so the slip in the drag law is (u - u_s) / eps, and the water's share of each grain's
  // impulse is divided by eps. Steady Darcy flow through a fixed bed then balances -grad p with beta q / eps^2
  // per volume (q = u the flux), which is Ergun's permeability, and the grains take -eps grad p as drag.
  Model model = test::small_coupled_model(0.01);
  model.fluid.density = kWaterDensity;
  model.fluid.kinematic_viscosity = kViscosity / kWaterDensity;
  const double eps = 0.4, d = 0.005;
  const Vec3 flux(0.004, 0.0, -0.001), grain_velocity(0.001, 0.002, 0.0);
  for (const bool mixture : {false, true}) {
    CAPTURE(mixture);
    model.coupling.fluid_velocity = mixture ? CouplingModel::FluidVelocity::kMixture : CouplingModel::FluidVelocity::kPore;
    World world;
    test::fill_with_water(world, Vec3(0.1, 0.1, 0.1), 0.01);
    world.solids.emplace();
    const std::size_t slot = world.solids->add(Vec3(0.05, 0.05, 0.05), grain_velocity, 0.5 * d, 1318.0, 0, 0);
    world.solids->fluid_velocity[slot] = flux;
    world.solids->voidage[slot] = eps;
    world.solids->fluid_weight[slot] = 1.0;
    SolidDragLaw drag_law(model);  // the law at the grain's voidage, as every step's start sets it
    const Access law_access = drag_law.access();
    SystemContext law_context(world, model, drag_law, law_access, 0.0, 1.0e-3);
    drag_law.run(law_context);
    SolidDrag drag(model);
    const Access drag_access = drag.access();
    SystemContext drag_context(world, model, drag, drag_access, 0.0, 1.0e-3);
    drag.run(drag_context);
    const Vec3 slip = mixture ? Vec3((flux - grain_velocity) / eps) : Vec3(flux - grain_velocity);
    const double volume = std::numbers::pi / 6.0 * d * d * d;
    const Vec3 expected = drag_per_volume(eps, d, slip.norm(), kWaterDensity, kViscosity, model.coupling) * volume * slip;
    CHECK((world.solids->drag_force[slot] - expected).norm() < 1e-12 * expected.norm());
    const Vec3 impulse = world.solids->drag_impulse[slot];
    CHECK((impulse - 1.0e-3 * expected).norm() < 1e-12 * impulse.norm());
    FluidDragReaction reaction(model);
    const Access access = reaction.access();
    SystemContext context(world, model, reaction, access, 0.0, 1.0e-3);
    reaction.run(context);
    Vec3 received = Vec3::Zero();
    for (const Vec3& per_volume : world.fluid->drag_reaction) received += per_volume * 1.0e-6;
    const Vec3 expected_received = -(mixture ? 1.0 / eps : 1.0) * impulse;
    CHECK((received - expected_received).norm() < 1e-12 * impulse.norm());
  }
}

TEST_CASE("the voidage of a submerged simple cubic packing is 1 - pi/6") {
  // Spheres of d = 10 mm touching on a cubic lattice fill pi/6 of space; fluid particles at l0 = 5 mm fill the box.
  std::vector<Vec3> grains, fluid;
  std::vector<double> volumes;
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 12; ++j)
      for (int k = 0; k < 12; ++k) {
        grains.emplace_back(0.005 + 0.01 * i, 0.005 + 0.01 * j, 0.005 + 0.01 * k);
        volumes.push_back(std::numbers::pi / 6.0 * 1e-6);
      }
  for (int i = 0; i < 24; ++i)
    for (int j = 0; j < 24; ++j)
      for (int k = 0; k < 24; ++k) fluid.emplace_back(0.0025 + 0.005 * i, 0.0025 + 0.005 * j, 0.0025 + 0.005 * k);
  VoidageGrid grid;
  grid.build(grains, volumes, fluid, fluid.size(), 1.25e-7, 0.668 * 0.03, Vec3::Constant(-1.0), Vec3::Constant(1.0));
  // Away from the box faces the deposits are exact partitions of unity of a periodic arrangement: the fraction
  // is pi/6 up to the lattice's aliasing against the 20 mm cells (the grain and fluid lattices are commensurate
  // with 10 mm, not 20.04 mm): allow 2 %.
  for (const Vec3& point : {Vec3(0.06, 0.06, 0.06), Vec3(0.043, 0.071, 0.052)})
    CHECK(grid.solid_fraction(point) == doctest::Approx(std::numbers::pi / 6.0).epsilon(0.02));
  // Near a face the fluid deposit is truncated exactly like the solid one: still pi/6, not less.
  CHECK(grid.solid_fraction(Vec3(0.06, 0.06, 0.004)) == doctest::Approx(std::numbers::pi / 6.0).epsilon(0.05));
}

TEST_CASE("momentum stays closed with every fluid force on: the water takes minus all but the pressure force") {
  // docs/COUPLING.md, "Added mass and history force": drag, added mass and history force go back to the water
  // through the grains' drag impulse; the pressure-gradient force does not (docs/COUPLING.md, "Back to the water").
  // A shaken tank of water with three free grains (light, neutral, heavy; no contacts) and every force on. Step by
  // step, what the grains received from the water apart from the pressure force is their momentum change less
  // gravity and the pressure impulse the kicks applied; the water must receive exactly minus that. Two offsets of
  // velocity Verlet are accounted for: a half kick at the start of each step still applies the last force sum of
  // the step before (its pressure force and drag), and solid_drag books each sub-step's drag for a whole sub-step
  // while the kicks apply its second half in the next sub-step.
  const std::string scene = SceneBuilder().run({.end_time = 1.0, .dt = 1.0e-3, .solid_substeps = 10})
      .material("grain", {.density = 1318.0}).material("light", {.density = 900.0})
      .material("neutral", {.density = 1000.0}).material("heavy", {.density = 2500.0})
      .tank({.size = {0.12, 0.08, 0.12}, .open_faces = {"z_max"}, .wall_material = "heavy"})
      .tank_motion({.amplitude = 0.01, .frequency = 1.7, .ramp_time = 0.05})
      .sphere({.position = {0.03, 0.04, 0.06}, .radius = 0.005, .material = "light"})
      .sphere({.position = {0.06, 0.04, 0.05}, .radius = 0.004, .material = "neutral"})
      .sphere({.position = {0.09, 0.04, 0.07}, .radius = 0.006, .material = "heavy"}).fluid({.spacing = 0.01})
      .fluid_box({0.0, 0.0, 0.0}, {0.12, 0.08, 0.1})
      .coupling().set("added_mass", true).set("history_force", true).set("history_window", 0.05)
      .set("self_induced_velocity", true).set("fluid_velocity", "pore")
      .toml();
  // The pore reading: there the water's momentum is the pore water's, one-for-one with the grains'. (In the mixture
  // reading, the default, the water stands for the mixture's volume flux and takes each grain's impulse over its
  // voidage by design: docs/COUPLING.md, "The water inside the bed".)
  auto simulation = Simulation::from_model(parse_scene(scene, "closed.toml"));
  const Model& model = simulation->model();
  REQUIRE(model.coupling.drag);
  REQUIRE(model.coupling.pressure_gradient);
  const Solids& grains = *simulation->world().solids;
  const auto momentum = [&] {
    Vec3 sum = Vec3::Zero();
    for (std::size_t i = 0; i < grains.size(); ++i) sum += grains.mass[i] * grains.velocity[i];
    return sum;
  };
  const auto total = [&](const std::vector<Vec3>& field) {
    Vec3 sum = Vec3::Zero();
    for (const Vec3& value : field) sum += value;
    return sum;
  };
  double grain_mass = 0.0;
  for (const double mass : grains.mass) grain_mass += mass;
  Vec3 last_pressure = total(grains.pressure_force);  // the initial-forces pass's, in the first half kick
  Vec3 last_drag = total(grains.drag_force);          // zero: that pass has no drag
  Vec3 previous = momentum();
  double largest = 0.0, largest_exchange = 0.0, largest_added = 0.0, largest_history = 0.0;
  for (int step = 0; step < 200; ++step) {
    simulation->step();
    REQUIRE(simulation->world().step_status.ok());
    const StepLengths& lengths = simulation->world().last_step;
    const double half = 0.5 * lengths.substep;
    const Vec3 pressure = total(grains.pressure_force), drag = total(grains.drag_force);
    const Vec3 applied_pressure =
        half * last_pressure + (2.0 * static_cast<double>(lengths.substeps) - 1.0) * half * pressure;
    const Vec3 now = momentum();
    const Vec3 from_water = now - previous - grain_mass * lengths.dt * model.gravity - applied_pressure -
                            half * (last_drag - drag);
    Vec3 received = Vec3::Zero();
    for (const Vec3& per_volume : simulation->world().fluid->drag_reaction) received += per_volume * 1.0e-6;
    largest = std::max(largest, (received + from_water).norm());
    largest_exchange = std::max(largest_exchange, from_water.norm());
    largest_added = std::max(largest_added, total(grains.added_mass_force).norm());
    largest_history = std::max(largest_history, total(grains.history_force).norm());
    previous = now;
    last_pressure = pressure;
    last_drag = drag;
  }
  MESSAGE("largest step imbalance " << largest << " N s against an exchange of up to " << largest_exchange
                                    << " N s a step; added-mass force up to " << largest_added
                                    << " N, history up to " << largest_history << " N");
  // The forces are there (the test would pass trivially without them) ...
  CHECK(largest_added > 1e-5);
  CHECK(largest_history > 1e-6);
  // ... and the water takes exactly minus what they, with the drag, gave the grains: to rounding of the sums of
  // momenta of about 1e-5 N s a step (1e-11 of it; measured 1e-18).
  CHECK(largest < 1e-16);
}
