// The grains and the mean-flow fluid together (docs/cases/bedload.md, "The mean-flow fluid"), through the real
// pipeline: each grain's drag is the drag law's at the column's velocity at its centre height; the momentum the
// grains take is the momentum the water loses, to rounding (the water's change is its walls' stresses and the grains'
// impulse, nothing else); one and two threads, and a resumed run, give the same bytes.
#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <map>
#include <numbers>
#include <string>

#include "engine/output/checkpoint.hpp"
#include "engine/run/simulation.hpp"
#include "engine/scene/scene.hpp"
#include "systems/physics/mean_flow/column_model.hpp"
#include "systems/physics/coupling/drag_law.hpp"
#include "systems/physics/mean_flow/column.hpp"
#include "systems/physics/mean_flow/grain_forces.hpp"
#include "systems/physics/math/counter_random.hpp"
#include "tests/support/scene_builder.hpp"
#include "tests/support/test_support.hpp"

using riffle::test::SceneBuilder;

namespace riffle {
namespace {

/// A periodic box 2 cm x 2 cm x 2 cm of a viscous liquid (nu = 1e-3 m^2/s: the lid's shear reaches the grains within
/// 0.1 s) under a lid at 0.2 m/s, grains of 2 mm in a block 5 to 12 mm above the floor (spacing 4 mm: no contacts),
/// `gravity` along z, the liquid laminar or turbulent.
/// `read_more`: the grains also read the shear lift ([coupling] lift) and, in turbulent water, Langevin velocity
/// fluctuations ([mean_flow] fluctuations = "langevin"). `pulled`: a free top instead of the lid, the water pulled
/// towards a 1/7-power profile of 0.2 m/s at the top ([mean_flow.profile_forcing]) and started on it.
std::string couette_scene(double gravity, bool fixed, const char* turbulence, int cells = 64, bool read_more = false,
                          bool pulled = false) {
  SceneBuilder scene;
  scene.run({.name = "mean_flow_couette", .end_time = 1.0, .dt = 1.0e-3, .gravity = {0.0, 0.0, gravity}})
      .material("quartz", {.density = 2650.0, .young_modulus = 1.0e7, .poisson_ratio = 0.3})
      .contact({.restitution = 0.5, .friction = 0.5, .max_impact_speed = 0.5})
      .tank({.size = {0.02, 0.02, 0.02}, .periodic = {"x", "y"}, .wall_material = "quartz"})
      .solids();
  if (fixed) scene.set("fixed_below", 0.02);
  scene.block({.min = {0.002, 0.002, 0.005}, .max = {0.018, 0.018, 0.012}, .spacing = 0.004, .radius = 0.001,
               .material = "quartz"});
  scene.table("mean_flow").set("cells", cells).set("kinematic_viscosity", 1.0e-3).set("turbulence", turbulence);
  if (pulled) scene.set("top", "free").set("initial", "target_profile");
  else scene.set("top", "lid").set("lid_velocity", 0.2).set("initial", "rest");
  if (read_more && std::string(turbulence) == "mixing_length") scene.set("fluctuations", "langevin");
  if (pulled)
    scene.table("mean_flow.profile_forcing")
        .set("velocity", 0.2)
        .set("base", 0.004)
        .set("strength", 2.0)
        .set("volume_fraction", 0.5);
  if (read_more) scene.coupling().set("lift", true);
  return scene.toml();
}

/// The water's momentum along x per plan area, sum rho eps h u, less the grains' impulse it has yet to lose
/// (pending in the column: the next step takes it), times the plan area; and the grains' sum m v_x less the drag
/// impulse they have received but not yet handed over.
double booked_momentum(const World& world, const Model& model) {
  const MeanFlowColumn& column = *world.mean_flow;
  const ColumnGrid grid = column_grid(model.mean_flow);
  const double area = column_plan_area(model);
  long double sum = static_cast<long double>(
      area * column_momentum(grid, column.solid_fraction, column.velocity_x, model.mean_flow.density));
  for (double impulse : column.impulse_x) sum -= static_cast<long double>(area * impulse);
  const Solids& grains = *world.solids;
  for (std::size_t g = 0; g < grains.size(); ++g)
    sum += static_cast<long double>(grains.mass[g] * grains.velocity[g].x()) -
           static_cast<long double>(grains.drag_impulse[g].x());
  return static_cast<double>(sum);
}

}  // namespace

TEST_CASE("a grain's drag is the drag law's at the column's velocity at its centre height") {
  auto simulation = Simulation::from_model(parse_scene(couette_scene(0.0, true, "laminar"), "couette.toml"));
  for (int step = 0; step < 200; ++step) simulation->step();
  REQUIRE(simulation->world().step_status.ok());
  const World& world = simulation->world();
  const Model& model = simulation->model();
  const ColumnGrid grid = column_grid(model.mean_flow);
  const ColumnEnds ends = column_ends(model.mean_flow, true);
  const Solids& grains = *world.solids;
  REQUIRE(grains.size() > 20);
  const double density = model.mean_flow.density;
  const double viscosity = model.mean_flow.kinematic_viscosity * density;
  double worst = 0.0;
  for (std::size_t g = 0; g < grains.size(); ++g) {
    REQUIRE(grains.fixed[g] == 1);
    const double z = grains.position[g].z();
    const double u = profile_at(grid, world.mean_flow->velocity_x, z, ends);
    const double solid = profile_at(grid, world.mean_flow->solid_fraction, z, ColumnEnds{});
    const double voidage = std::clamp(1.0 - solid, model.coupling.min_voidage, 1.0);
    CHECK(grains.voidage[g] == doctest::Approx(voidage).epsilon(1e-14));
    const double diameter = 2.0 * grains.radius[g];
    const double expected = drag_per_volume(voidage, diameter, std::abs(u), density, viscosity, model.coupling) *
                            grain_volume(grains.radius[g]) * u;
    REQUIRE(u > 0.0);
    worst = std::max(worst, std::abs(grains.drag_force[g].x() - expected) / std::abs(expected));
  }
  MESSAGE("worst relative difference of the drag from the law at the centre's velocity: " << worst);
  CHECK(worst < 1e-12);
}

TEST_CASE("the momentum the grains take is the momentum the water loses, to rounding") {
  // No gravity: the grains keep their heights, so the solid fraction stays and nothing but the exchange and the
  // walls' stresses moves the momentum.
  auto simulation = Simulation::from_model(parse_scene(couette_scene(0.0, false, "mixing_length"), "couette.toml"));
  const Model& model = simulation->model();
  const double area = column_plan_area(model);
  const double start = booked_momentum(simulation->world(), model);
  double walls = 0.0;        // sum of dt A (tau_lid - tau_floor): what the walls put in
  double largest_drag = 0.0;  // for the sub-steps' half kicks (bounded by one sub-step's drag impulse)
  for (int step = 0; step < 100; ++step) {
    simulation->step();
    REQUIRE(simulation->world().step_status.ok());
    const MeanFlowColumn& column = *simulation->world().mean_flow;
    walls += simulation->world().last_step.dt * area * (column.top_stress - column.floor_stress);
    for (const Vec3& force : simulation->world().solids->drag_force) largest_drag = std::max(largest_drag, force.norm());
  }
  const World& world = simulation->world();
  const double change = booked_momentum(world, model) - start;
  const double grains_momentum = [&] {
    double sum = 0.0;
    for (std::size_t g = 0; g < world.solids->size(); ++g) sum += world.solids->mass[g] * world.solids->velocity[g].x();
    return sum;
  }();
  // Velocity Verlet kicks each sub-step's force in halves: the grains' momentum and the booked impulse differ by
  // dt_s (F_first - F_last) / 2 per grain over the run.
  const double half_kicks = static_cast<double>(world.solids->size()) * world.last_step.substep * largest_drag;
  MESSAGE("momentum change " << change << " against the walls' " << walls << "; grains hold " << grains_momentum
                             << "; half-kick bound " << half_kicks);
  REQUIRE(grains_momentum > 0.0);
  CHECK(std::abs(change - walls) <= half_kicks + 1e-12 * std::abs(walls));
}

TEST_CASE("a grain's shear lift is Wiberg & Smith's at the column's velocities over its top and under its bottom") {
  // Held grains in the laminar Couette column: the vertical fluid force less the buoyancy is the lift alone.
  auto simulation =
      Simulation::from_model(parse_scene(couette_scene(-9.81, true, "laminar", 64, true), "couette.toml"));
  for (int step = 0; step < 200; ++step) simulation->step();
  REQUIRE(simulation->world().step_status.ok());
  const World& world = simulation->world();
  const Model& model = simulation->model();
  const ColumnGrid grid = column_grid(model.mean_flow);
  const ColumnEnds ends = column_ends(model.mean_flow, true);
  const Solids& grains = *world.solids;
  const double density = model.mean_flow.density;
  double worst = 0.0, largest = 0.0;
  for (std::size_t g = 0; g < grains.size(); ++g) {
    const double z = grains.position[g].z(), r = grains.radius[g];
    const double top = profile_at(grid, world.mean_flow->velocity_x, z + r, ends);
    const double bottom = profile_at(grid, world.mean_flow->velocity_x, z - r, ends);
    const double expected = 0.5 * density * 0.2 * std::numbers::pi * r * r * (top * top - bottom * bottom);
    const double buoyancy = grain_volume(r) * density * 9.81;
    REQUIRE(expected > 0.0);
    largest = std::max(largest, expected);
    worst = std::max(worst, std::abs(grains.pressure_force[g].z() - buoyancy - expected) / expected);
  }
  MESSAGE("largest lift " << largest << " N; worst relative difference from the formula " << worst);
  CHECK(worst < 1e-9);  // the buoyancy's rounding over a lift ~1e-4 of it

  // Free grains without gravity, moving with the water: the lift is of the velocities relative to the grain's own at
  // the step's start (its sampling), horizontal parts only, at the heights of its top and bottom then.
  auto free = Simulation::from_model(parse_scene(couette_scene(0.0, false, "laminar", 64, true), "couette.toml"));
  for (int step = 0; step < 100; ++step) free->step();
  std::map<EntityId, std::pair<Vec3, Vec3>> start;  // the grain's position and velocity as its sampling reads them
  for (std::size_t g = 0; g < free->world().solids->size(); ++g)
    start[free->world().solids->id[g]] = {free->world().solids->position[g], free->world().solids->velocity[g]};
  free->step();
  REQUIRE(free->world().step_status.ok());
  const Solids& moving = *free->world().solids;
  const MeanFlowColumn& column = *free->world().mean_flow;
  double worst_moving = 0.0, fastest = 0.0, largest_moving = 0.0;
  for (std::size_t g = 0; g < moving.size(); ++g) {
    const double z = start.at(moving.id[g]).first.z(), r = moving.radius[g];
    const Vec3 v = start.at(moving.id[g]).second;
    fastest = std::max(fastest, std::hypot(v.x(), v.y()));
    const double top = profile_at(grid, column.velocity_x, z + r, ends) - v.x();
    const double bottom = profile_at(grid, column.velocity_x, z - r, ends) - v.x();
    const double expected = 0.5 * density * 0.2 * std::numbers::pi * r * r * (top * top - bottom * bottom);
    worst_moving = std::max(worst_moving, std::abs(moving.pressure_force[g].z() - expected));
    largest_moving = std::max(largest_moving, std::abs(expected));
  }
  worst_moving /= largest_moving;  // over the largest lift: grains level with the water feel almost none
  MESSAGE("free grains up to " << fastest << " m/s: worst difference from the formula over the largest lift " << worst_moving);
  REQUIRE(fastest > 1e-3);
  CHECK(worst_moving < 1e-12);
}

TEST_CASE("each grain's velocity fluctuation is its Langevin state's, advanced over the step at its own height") {
  // Held grains in the turbulent Couette column, through the real pipeline: after every step each grain's state is
  // the exact Ornstein-Uhlenbeck step of its state before, with the Lagrangian time of the shear at its centre and
  // the draws named by (seed, step, id), and the velocity its drag read is the mean at its centre plus that state's
  // fluctuation. The statistics of the process (unit variance, exp(-t/T_L) memory, Nezu & Nakagawa's intensities,
  // -<u'w'> = the closure's stress) are the unit tests' (tests/unit/systems/physics/mean_flow/grain_forces_test.cpp).
  auto simulation =
      Simulation::from_model(parse_scene(couette_scene(0.0, true, "mixing_length", 64, true), "couette.toml"));
  const Model& model = simulation->model();
  const ColumnGrid grid = column_grid(model.mean_flow);
  const ColumnEnds ends_x = column_ends(model.mean_flow, true), ends_y = column_ends(model.mean_flow, false);
  const TurbulenceIntensities intensities;
  std::map<EntityId, Vec3> before;
  double largest = 0.0, worst_state = 0.0, worst_velocity = 0.0;
  for (int step = 0; step < 150; ++step) {
    for (std::size_t g = 0; g < simulation->world().solids->size(); ++g)
      before[simulation->world().solids->id[g]] = simulation->world().solids->fluctuation_state[g];
    simulation->step();
    REQUIRE(simulation->world().step_status.ok());
    // The grains read the column the step's momentum balance left (its velocities and eddy viscosity; the step's
    // end changes only the solid fraction and the impulse).
    const World& world = simulation->world();
    const MeanFlowColumn& column = *world.mean_flow;
    const Solids& grains = *world.solids;
    for (std::size_t g = 0; g < grains.size(); ++g) {
      const double z = grains.position[g].z();
      const TurbulentShear shear = turbulent_shear_at(grid, column, ends_x, ends_y, z);
      const Vec3 state = advance_langevin(
          before.at(grains.id[g]), world.last_step.dt,
          lagrangian_time_scale(shear.shear_rate, model.mean_flow.langevin_c0, intensities),
          counter_normals(model.mean_flow.fluctuation_seed, world.step - 1, grains.id[g]));
      worst_state = std::max(worst_state, (grains.fluctuation_state[g] - state).norm());
      const Vec3 mean(profile_at(grid, column.velocity_x, z, ends_x), profile_at(grid, column.velocity_y, z, ends_y), 0);
      const Vec3 fluctuation = fluctuation_velocity(state, shear, intensities);
      largest = std::max(largest, fluctuation.norm() / std::max(shear.friction_velocity(), 1e-300));
      worst_velocity = std::max(worst_velocity, (grains.fluid_velocity[g] - mean - fluctuation).norm() /
                                                    std::max(mean.norm(), 1e-300));
    }
  }
  MESSAGE("largest |u'| / u* " << largest << "; worst state difference " << worst_state
                               << "; worst velocity difference over the mean " << worst_velocity);
  CHECK(largest > 1.0);  // the fluctuations are there, of the local friction velocity's size
  CHECK(worst_state < 1e-12);
  CHECK(worst_velocity < 1e-12);
}

TEST_CASE("a mean-flow run is byte-identical on one and two threads and after a resume") {
  // With the lift and the velocity fluctuations on: their draws are named by grain and step, not by the thread. Under
  // a lid, and pulled towards a profile under a free top.
  for (const bool pulled : {false, true}) {
    CAPTURE(pulled);
    const std::string scene = couette_scene(-9.81, false, "mixing_length", 48, true, pulled);
    const auto bytes_after = [&](int threads, int steps) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
      auto simulation = Simulation::from_model(parse_scene(scene, "couette.toml"));
      for (int step = 0; step < steps; ++step) simulation->step();
      REQUIRE(simulation->world().step_status.ok());
      return encode_checkpoint(simulation->checkpoint_data());
    };
    const std::string one = bytes_after(1, 40);
    CHECK(one == bytes_after(2, 40));
    const auto directory = test::scratch_dir("mean_flow_resume");
    auto first = Simulation::from_model(parse_scene(scene, "couette.toml"));
    for (int step = 0; step < 17; ++step) first->step();
    const std::string path = (directory / "part.ckpt").string();
    write_checkpoint(path, first->checkpoint_data());
    first.reset();
    auto resumed = Simulation::from_checkpoint(path);
    for (int step = 17; step < 40; ++step) resumed->step();
    CHECK(encode_checkpoint(resumed->checkpoint_data()) == one);
    if (pulled) CHECK(resumed->world().mean_flow->velocity_x.back() > 0.1);  // the pull holds the water up
  }
}

}  // namespace riffle
