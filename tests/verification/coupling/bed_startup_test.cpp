// Seed 003's start-up in embryo (docs/SCENES.md, "The start-up"): a bed settled dry, put under water and a lid at
// rest, held for a while and released, must not move: no grain faster than the seed's 0.01 m/s threshold of a
// "moving" grain (seed 003 Sec. 5, its Eq. 29) at any step after the release: "a settled bed under a lid too slow
// to move it: no grain moves" with the lid at rest; the seed's large (2 mm) grains in the
// seed's own 2 cm x 2 cm plan (273 grains, a closed box), so it runs in seconds.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "systems/physics/measures/bedload_probes.hpp"
#include "engine/output/checkpoint.hpp"
#include "engine/run/simulation.hpp"
#include "systems/physics/mps/mps_common.hpp"
#include "tests/support/test_support.hpp"
#include "tests/support/scene_builder.hpp"

using namespace riffle;
using riffle::test::SceneBuilder;

namespace {
/// The sheared-bed scenes: a run to `end_time` at dt = 0.5 ms, their material and contact law, and a 2 cm x 2 cm box
/// `height` high; `tank_keys`: more [tank] keys, such as periodic.
SceneBuilder sheared_box(double end_time, const std::string& tank_keys = "", double height = 0.0275) {
  SceneBuilder scene;
  scene.run({.end_time = end_time, .dt = 5.0e-4})
      .material("grain", {.density = 2650.0, .young_modulus = 1.0e7, .poisson_ratio = 0.3})
      .contact({.law = "hertz_mindlin", .restitution = 0.5, .friction = 0.5, .rolling_friction = 0.05,
                .max_impact_speed = 1.0})
      .set("rolling_law", "constant_torque")  // seed 003 Eq. 20, as the sheared-bed scenes name it
      .tank({.size = {0.02, 0.02, height}, .wall_material = "grain"}).verbatim(tank_keys);
  return scene;
}

/// `value` as printf's `format` writes it and a scene reads it back.
double as_written(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return std::strtod(text, nullptr);
}

double max_grain_speed(const Solids& grains) {
  double fastest = 0.0;
  for (const Vec3& velocity : grains.velocity) fastest = std::max(fastest, velocity.norm());
  return fastest;
}

/// The seed's 2 cm plan with its 273 grains of 2 mm generated loose, to settle dry for 0.3 s (`tank_keys`: more
/// [tank] keys, such as periodic).
std::string dry_bed_scene(const std::string& tank_keys) {
  return sheared_box(0.3, tank_keys).solids()
      .layered_bed({.layers = 3, .layer_thickness = 0.002, .loose_factor = 2.0, .seed = 1})
      .bed_class({.diameter = 0.002, .count = 273, .material = "grain"}).toml();
}

/// Runs a dry_bed_scene to its end (0.3 s).
auto settle_dry_bed(const std::string& dry) {
  auto settle = Simulation::from_model(parse_scene(dry, "settle.toml"));
  while (settle->world().time < 0.3 - 1e-9) settle->step();
  REQUIRE(settle->world().step_status.ok());
  return settle;
}
}  // namespace

TEST_CASE("a bed settled dry, held under water and a lid at rest, then released: no grain moves") {
  const std::string dry = dry_bed_scene("");
  auto settle = settle_dry_bed(dry);
  const double settled_speed = max_grain_speed(*settle->world().solids);
  CHECK(settled_speed < 0.01);  // at rest dry after 0.3 s (the scenes settle 0.5 s)
  const auto directory = test::scratch_dir("bed_startup");
  const std::string bed = (directory / "settled.ckpt").string();
  write_checkpoint(bed, settle->checkpoint_data());
  settle.reset();

  const std::string wet = sheared_box(0.25).solids().set("initial_state", bed).set("hold_until", 0.05)
      .fluid({.spacing = 0.0025, .clamp_negative_pressure = false}).set("turbulence", "sps")
      .set("smagorinsky_constant", 0.15).fluid_box({0.0, 0.0, 0.0}, {0.02, 0.02, 0.02})
      .wall_box({.low = {0.0, 0.0, 0.02}, .high = {0.02, 0.02, 0.0275}, .lid = "no_slip", .velocity = 0.0})
      .coupling().set("fluid_velocity", "mixture").toml();
  auto run = Simulation::from_model(parse_scene(wet, "wet.toml"));
  REQUIRE(run->world().solids->size() == 273);
  double held_speed = 0.0, released_speed = 0.0;
  while (run->world().time < 0.25 - 1e-9) {
    run->step();
    REQUIRE(run->world().step_status.ok());
    double& worst = run->world().time <= 0.05 ? held_speed : released_speed;
    worst = std::max(worst, max_grain_speed(*run->world().solids));
  }
  MESSAGE("largest grain speed: settled dry ", settled_speed, " m/s; held ", held_speed, " m/s; after the release ",
          released_speed, " m/s (the seed's threshold 0.01 m/s)");
  CHECK(held_speed == 0.0);
  CHECK(released_speed < 0.01);

  // The control: the same water over the bed as generated (loose, not settled) sets grains moving well past the
  // threshold, so the check above can fail (docs/SCENES.md measured 0.87 of the grains moving at 0.04 s).
  std::string loose = wet;
  const std::size_t from = loose.find("initial_state"), to = loose.find("[fluid]");
  loose.replace(from, to - from, dry.substr(dry.find("[[solids.layered_beds]]")) + "\n");
  auto generated = Simulation::from_model(parse_scene(loose, "loose.toml"));
  double loose_speed = 0.0;
  while (generated->world().time < 0.05 - 1e-9) {
    generated->step();
    loose_speed = std::max(loose_speed, max_grain_speed(*generated->world().solids));
  }
  MESSAGE("the loose bed in water: largest grain speed ", loose_speed, " m/s in its first 0.05 s");
  CHECK(loose_speed > 0.01);
}

namespace {
/// Sum over the fluid particles of u_x (fluid slots [0, F): the water's x momentum per rho l0^3).
double fluid_momentum_x(const FluidParticles& fluid) {
  double sum = 0.0;
  for (std::size_t i = 0; i < fluid_slot_count(fluid); ++i) sum += fluid.velocity[i].x();
  return sum;
}

/// What one slow-lid run measured (time means over the window after the start's transient).
struct SlowLidBalance {
  double worst_moving = 0.0;    ///< largest moving fraction (|v| > 0.01 m/s) after the release
  double released_speed = 0.0;  ///< [m/s] largest grain speed after the release
  double tau_b = 0.0;           ///< [Pa] bed shear stress (bedload_probes' bed_shear_stress)
  double tau_lid = 0.0;         ///< [Pa] the lid's drag per plan area
  double unsteady = 0.0;        ///< [Pa] (1/A) dP_x/dt of the water over the window
  double standard_error = 0.0;  ///< [Pa] of the closure, from the spread of 8 consecutive stretches' closures
  double couette = 0.0;         ///< [Pa] rho nu U / H from the bed's top
  double closure() const { return tau_b - (tau_lid - unsteady); }
};

/// The slow-lid case: a no-slip lid at kLidHeight moving at kLidSpeed over water of kSlowLidViscosity.
constexpr double kLidHeight = 0.02, kLidSpeed = 0.02, kSlowLidViscosity = 1.0e-4;
/// The slow-lid runs' end [s]: the grains held to 0.05 s, the balance measured from 0.1 s.
constexpr double kSlowLidEnd = 0.2;

/// The slow-lid case's wet scene on the settled bed `bed` (top at `bed_top`): water of spacing `spacing` and
/// nu = 1e-4 m^2/s in the 2 cm periodic box under a no-slip lid at 0.02 m/s, the grains held until 0.05 s, to
/// kSlowLidEnd, with or without [coupling] viscous_stress; `fluid_keys`: more [fluid] keys.
std::string slow_lid_scene(const std::string& bed, double bed_top, double spacing, bool viscous,
                           const std::string& fluid_keys = "") {
  const double lid_z = kLidHeight, lid_top = kLidHeight + 3.0 * spacing;  // the lid three layers thick at any spacing
  // The tank as tall as the lid's top (its walls need a height in whole spacings; 0.0275 m at 2.5 mm).
  return sheared_box(kSlowLidEnd, "periodic = [\"x\", \"y\"]\n", as_written("%.12g", lid_top))
      .solids().set("initial_state", bed).set("hold_until", 0.05)
      .fluid({.spacing = spacing, .kinematic_viscosity = kSlowLidViscosity, .clamp_negative_pressure = false})
      .verbatim(fluid_keys).fluid_box({0.0, 0.0, 0.0}, {0.02, 0.02, 0.02})
      .table("fluid.initial_velocity").set("kind", "linear").set("bottom", as_written("%.6f", bed_top))
      .set("top", lid_z).set("velocity", kLidSpeed)
      .wall_box({.low = {0.0, 0.0, lid_z}, .high = {0.02, 0.02, as_written("%.12g", lid_top)}, .lid = "no_slip",
                 .velocity = kLidSpeed})
      .coupling().set("fluid_velocity", "mixture").set("viscous_stress", viscous).toml();
}

/// The slow-lid case run (slow_lid_scene) and its momentum balance measured.
SlowLidBalance run_slow_lid(const std::string& bed, double bed_top, double spacing, bool viscous) {
  const double held = 0.05, end = kSlowLidEnd;
  const std::string wet = slow_lid_scene(bed, bed_top, spacing, viscous);
  const Model model = parse_scene(wet, "wet.toml");
  auto run = Simulation::from_model(model);
  const World& world = run->world();
  const TankFrame frame = tank_frame(model, nullptr);
  const ShearSettings settings = shear_settings(model);
  const double area = frame.area();
  // Rows every 5 steps from 0.1 s (after the start's transient: the first projection and the release at 0.05 s) to
  // the end: tau_b, tau_lid and the water's x momentum.
  const double window_start = 0.1;
  SlowLidBalance result;
  std::vector<double> times, difference, momentum;  // per row: t, tau_b - tau_lid, the water's x momentum
  std::size_t steps = 0;
  while (world.time < end - 1e-9) {
    run->step();
    REQUIRE_MESSAGE(world.step_status.ok(), "problem ", static_cast<int>(world.step_status.problem), " in ",
                    world.step_status.phase, " at t = ", world.time);
    ++steps;
    if (world.time > held + 1e-9) {
      const std::vector<double> moving = moving_fractions(*world.solids, grain_classes(*world.solids), frame, 0.01);
      result.worst_moving = std::max(result.worst_moving, moving.back());
      result.released_speed = std::max(result.released_speed, max_grain_speed(*world.solids));
    }
    if (world.time >= window_start - 1e-9 && steps % 5 == 0) {
      const double tau_b = bed_shear_stress(&*world.solids, &*world.fluid, settings, frame).tau;
      const std::optional<double> tau_lid = lid_shear_stress(model, world);
      REQUIRE(tau_lid.has_value());
      result.tau_b += tau_b;
      result.tau_lid += *tau_lid;
      times.push_back(world.time);
      difference.push_back(tau_b - *tau_lid);
      momentum.push_back(fluid_momentum_x(*world.fluid));
    }
  }
  const std::size_t rows = times.size();
  REQUIRE(rows > 40);  // 0.1 s of rows: at least 41 at the scene's run.dt, 5e-4 s
  result.tau_b /= static_cast<double>(rows);
  result.tau_lid /= static_cast<double>(rows);
  // The water's momentum balance, lid drag - bed drag = d(momentum)/dt / area, over the window and over each of
  // kBatches consecutive stretches of it: the stretches' closures scatter with the rows' noise and the momentum's
  // fluctuations together, and successive rows are correlated, so their spread (batch means) gives the standard
  // error of the window's closure where the rows' own spread would understate it.
  const double mass = model.fluid.density * std::pow(model.fluid.spacing, 3);
  const auto unsteady = [&](std::size_t first, std::size_t last) {
    return mass * (momentum[last] - momentum[first]) / (area * (times[last] - times[first]));
  };
  result.unsteady = unsteady(0, rows - 1);
  constexpr std::size_t kBatches = 8;
  std::vector<double> batch_closures;
  for (std::size_t k = 0; k < kBatches; ++k) {
    const std::size_t first = k * (rows - 1) / kBatches, last = (k + 1) * (rows - 1) / kBatches;
    double sum = 0.0;
    for (std::size_t row = first; row < last; ++row) sum += difference[row];
    batch_closures.push_back(sum / static_cast<double>(last - first) + unsteady(first, last));
  }
  double batch_mean = 0.0, scatter = 0.0;
  for (double c : batch_closures) batch_mean += c / static_cast<double>(kBatches);
  for (double c : batch_closures) scatter += (c - batch_mean) * (c - batch_mean);
  result.standard_error = std::sqrt(scatter / static_cast<double>(kBatches - 1) / static_cast<double>(kBatches));
  result.couette = model.fluid.density * kSlowLidViscosity * kLidSpeed / (kLidHeight - bed_top);
  MESSAGE("spacing ", spacing, " m, viscous stress ", viscous, ": moving fraction after the release at most ",
          result.worst_moving, "; largest grain speed ", result.released_speed, " m/s; tau_b ", result.tau_b,
          " Pa, tau_lid ", result.tau_lid, " Pa (Couette rho nu U / H = ", result.couette, " Pa); unsteady residual ",
          result.unsteady, " Pa; momentum balance tau_b - (tau_lid - unsteady) = ", result.closure(), " Pa (",
          result.closure() / result.tau_lid, " of tau_lid), standard error ", result.standard_error, " Pa");
  return result;
}
}  // namespace

TEST_CASE("a settled bed under a lid too slow to move it, periodic in x and y: no grain moves, the lid drags as Couette") {
  // A settled bed under a slow lid, in the seed's 2 cm plan made periodic along x and y (its sheared beds' box): the bed
  // settled dry in the periodic box, then water and a no-slip lid at U = 0.02 m/s. The water is made viscous
  // (nu = 1e-4 m^2/s, 100 x water) so that the layer (H ~ 13 mm from the bed's top to the lid) is laminar plane
  // Couette flow (Re = U H / nu ~ 3) whose stresses are large enough to measure: tau ~ rho nu U / H ~ 0.15 Pa, a
  // Shields number 0.15 / ((2650 - 1000) 9.81 0.002) ~ 0.005, far below the threshold of motion (0.12 in laminar
  // flow, Ouriemi, Aussillous & Guazzelli 2009, J. Fluid Mech. 636; 0.03-0.05 turbulent, Shields 1936): no grain may
  // move. The balance checked, the lid's drag carried down to the bed, is the same statement at any Reynolds number.
  // The water starts with the linear Couette profile ([fluid.initial_velocity]) but is not steady within the run
  // (H^2/nu ~ 1.7 s; the flow also enters the bed's pores): the water's momentum balance, tau_lid - tau_b =
  // (1/A) dP_x/dt, names the difference, and the unsteady term is measured from the run's own momentum change.
  // With nu raised further the explicit drag reaction on the water in the pores (relaxation time ~ rho_f eps / beta,
  // beta ~ 18 mu (1 - eps) / d^2) fell below the step and the run blew up (measured before the drag's step limit:
  // nu = 2e-3 within 3 ms); the limit now shortens the step instead ([coupling] drag_number).
  const std::string periodic = "periodic = [\"x\", \"y\"]\n";
  auto settle = settle_dry_bed(dry_bed_scene(periodic));
  double bed_top = 0.0;
  for (std::size_t i = 0; i < settle->world().solids->size(); ++i)
    bed_top = std::max(bed_top, settle->world().solids->position[i].z() + settle->world().solids->radius[i]);
  const auto directory = test::scratch_dir("bed_under_slow_lid");
  const std::string bed = (directory / "settled.ckpt").string();
  write_checkpoint(bed, settle->checkpoint_data());
  settle.reset();

  // Without and with [coupling] viscous_stress at l0 = 2.5 mm, then with it at finer water. In the mixture reading
  // the water takes the grains' drag over eps; without the viscous stress force V rho <nu lap u> on the grains
  // (Anderson & Jackson's other half of the generalised buoyancy) the grains get only the drag, and tau_b fell short
  // of the balance by 16 % of tau_lid (the share (1 - eps)/eps of the drag). With it the balance must close
  // (docs/COUPLING.md, "The viscous stress on the grains"), and keep closing as the water is refined: an error that
  // grew with refinement would be a model error, not sampling noise. The finer water needs the drag's step limit
  // ([coupling] drag_number): at l0 <= d the voidage kernel narrows, the bed's sampled voidage falls and the water's
  // relaxation time under the drag with it (about 1e-4 s at 1.67 mm); at the scene's run.dt of 5e-4 s the pore water
  // oscillated and blew up within 0.02 s, the grains still held.
  struct Case {
    double spacing;
    bool viscous;
  };
  // 1.67 mm, between the two, closed to +1.0 % (at deb9a2c) and is not run: it cost 30 % of the test's time.
  for (const Case& c : {Case{0.0025, false}, Case{0.0025, true}, Case{0.00125, true}}) {
    CAPTURE(c.spacing);
    CAPTURE(c.viscous);
    const SlowLidBalance balance = run_slow_lid(bed, bed_top, c.spacing, c.viscous);
    CHECK(balance.worst_moving == 0.0);
    CHECK(balance.released_speed < 0.01);
    // The lid's drag against plane Couette flow from the bed's top: within 15 %, the tolerance of the MPS wall
    // traction in driven_flow_test.cpp (4 mu U / h); the bed's no-slip plane lies somewhere in its top grain layer
    // (d / H ~ 14 %).
    CHECK(std::abs(balance.tau_lid - balance.couette) < 0.15 * balance.couette);
    // The water's momentum balance, tau_b = tau_lid - (1/A) dP_x/dt. With the viscous stress force it closes to
    // within 5 % of tau_lid at every spacing, a third of the 15 % the lid's traction itself is held to against Couette
    // above; without it tau_b falls short by 16-18 % beyond the unsteady term. Measured (the closure over tau_lid, its
    // standard error 0.01-0.02 %) at deb9a2c: -0.3 % at l0 = 2.5 mm, -1.5 % at 1.25 mm (d / l0 = 0.8-1.6:
    // it does not grow with refinement; the remainder is systematic, not noise: the discrete voidage and nu lap u the
    // grains sample against those the water's reaction used, and the floor under the bed's pores); without the
    // force -18 % (2.5 mm, deb9a2c) and -18 % (1.25 mm, one run at run.dt = 1e-4 s, earlier). Those runs ended at
    // 0.3 s; ended at 0.2 s (a third less time; the window 0.1-0.2 s) the same three read -0.2 %, -1.2 % and -17.5 %.
    if (c.viscous) {
      CHECK(std::abs(balance.closure()) < 0.05 * balance.tau_lid);
    } else {
      CHECK(balance.closure() < -0.1 * balance.tau_lid);  // the loss the viscous stress force closes: not noise
    }
  }

  // A drag limit below fluid.min_dt stops the run with a diagnosis that names it: at l0 = 1.25 mm the limit is about
  // 5e-5 s (the rate near 1e4 1/s), so with min_dt = 2e-4 s the first step stops.
  const Model stiff = parse_scene(slow_lid_scene(bed, bed_top, 0.00125, true, "min_dt = 2.0e-4\n"), "stiff.toml");
  auto collapse = Simulation::from_model(stiff);
  collapse->step();
  const World& world = collapse->world();
  REQUIRE_FALSE(world.step_status.ok());
  CHECK(world.step_status.problem == StepProblem::kTimeStepCollapse);
  CHECK(world.last_step.limit == StepLimit::kDrag);
  CHECK(world.last_step.drag_rate * 2.0e-4 > stiff.coupling.drag_number);
  const std::string text = diagnosis(world, stiff);
  CHECK(text.find("drag limit") != std::string::npos);
  CHECK(text.find("below fluid.min_dt") != std::string::npos);
  CHECK(text.find(" 1/s") != std::string::npos);
  CHECK(world.time == 0.0);  // the step did not run
}
