// Grains in free flight against the analytic trajectory x(t) = x0 + v0 t + g t^2 / 2.
// Velocity Verlet integrates a constant acceleration exactly, so the only error is floating-point rounding:
// about (number of sub-steps) x (machine epsilon) x |x|, i.e. 1000 x 2.2e-16 x 0.2 m = 5e-14 m here.
#include <doctest/doctest.h>

#include <algorithm>

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "engine/output/checkpoint.hpp"
#include "engine/run/simulation.hpp"
#include "systems/physics/geometry/tank_kinematics.hpp"
#include "tests/support/test_support.hpp"
#include "tests/support/scene_builder.hpp"

using namespace riffle;
using riffle::test::SceneBuilder;

TEST_CASE("free flight follows the parabola to rounding error, whatever the sub-step count") {
  for (int substeps : {1, 4, 10}) {
    Model model = test::small_model();
    model.solid_substeps = substeps;
    auto simulation = Simulation::from_model(model);
    std::map<EntityId, std::pair<Vec3, Vec3>> start;
    const Solids& solids = *simulation->world().solids;
    for (std::size_t i = 0; i < solids.size(); ++i) start[solids.id[i]] = {solids.position[i], solids.velocity[i]};
    const int steps = 100;
    for (int step = 0; step < steps; ++step) simulation->step();
    REQUIRE(simulation->world().step_status.ok());
    const double t = simulation->world().time;
    CHECK(t == doctest::Approx(steps * model.dt).epsilon(1e-12));
    const double rounding_bound = 4.0 * steps * substeps * 2.2e-16 * 0.3 + 1e-15;
    double worst_position = 0.0, worst_velocity = 0.0;
    for (std::size_t i = 0; i < solids.size(); ++i) {
      const auto& [x0, v0] = start.at(solids.id[i]);
      const Vec3 x = x0 + v0 * t + 0.5 * model.gravity * t * t;
      const Vec3 v = v0 + model.gravity * t;
      worst_position = std::max(worst_position, (solids.position[i] - x).norm());
      worst_velocity = std::max(worst_velocity, (solids.velocity[i] - v).norm());
    }
    INFO("substeps = " << substeps);
    CHECK(worst_position < rounding_bound);
    CHECK(worst_velocity < rounding_bound * 10.0);
  }
}

TEST_CASE("free flight conserves kinetic plus potential energy and leaves spin untouched") {
  auto simulation = Simulation::from_model(test::small_model());
  Solids& solids = *simulation->world().solids;
  for (std::size_t i = 0; i < solids.size(); ++i) solids.angular_velocity[i] = Vec3(1.0, -2.0, 3.0 * i);
  simulation->step();
  const SolidSummary first = *simulation->world().solid_summary;
  for (int step = 0; step < 80; ++step) simulation->step();
  const SolidSummary last = *simulation->world().solid_summary;
  const double total_first = first.translational_energy + first.potential_energy;
  const double total_last = last.translational_energy + last.potential_energy;
  CHECK(std::abs(total_last - total_first) < 1e-12 * std::abs(total_first) + 1e-15);
  CHECK(last.rotational_energy == doctest::Approx(first.rotational_energy).epsilon(1e-14));
  CHECK(last.translational_energy != doctest::Approx(first.translational_energy));  // it did move
}

TEST_CASE("a grain that leaves the domain stops the run with a diagnosis naming it") {
  const std::string scene = test::small_scene_text(SceneBuilder().within("solids")
      .sphere({.position = {0.2, 0.08, 0.1}, .radius = 0.005, .material = "grain", .velocity = {5.0, 0.0, 0.0}})
      .toml());
  auto simulation = Simulation::from_model(parse_scene(scene, "escape.toml"));
  const EntityId runaway = simulation->world().solids->id[0];  // explicit spheres come first
  int steps = 0;
  while (simulation->world().step_status.ok() && steps < 100) {
    simulation->step();
    ++steps;
  }
  const StepStatus& status = simulation->world().step_status;
  REQUIRE(status.problem == StepProblem::kLeftDomain);
  CHECK(status.entity == runaway);
  // The domain ends 0.05 m + A = 0.06 m beyond x = 0.24 m, at x = 0.30 m; at 5 m/s from 0.2 m the grain reaches
  // it at t = 0.02 s (step 20, still inside: the boundary belongs to the domain) and is past it after step 21.
  CHECK(steps == 21);
  CHECK(status.position[0] > 0.30);
}

TEST_CASE("a non-finite state is diagnosed as such") {
  auto simulation = Simulation::from_model(test::small_model());
  Solids& solids = *simulation->world().solids;
  solids.velocity[3] = Vec3(std::nan(""), 0.0, 0.0);
  const EntityId bad = solids.id[3];
  simulation->step();
  CHECK(simulation->world().step_status.problem == StepProblem::kNonFinite);
  CHECK(simulation->world().step_status.entity == bad);
}

namespace {
/// Two grains in a still tank, held until `hold_until` ([solids] hold_until), with an upward initial velocity that
/// the hold must wipe: dt = 1 ms, 4 sub-steps of 0.25 ms.
std::string held_grains_scene(const std::string& hold) {
  return SceneBuilder().run({.end_time = 0.05, .dt = 1.0e-3, .solid_substeps = 4})
      .material("grain", {.density = 1318.0}).tank({.size = {0.24, 0.16, 0.20}, .wall_material = "grain"})
      .solids().verbatim(hold + "\n")
      .sphere({.position = {0.1, 0.08, 0.15}, .radius = 0.0025, .material = "grain", .velocity = {0.0, 0.0, 0.5}})
      .sphere({.position = {0.15, 0.08, 0.12}, .radius = 0.003, .material = "grain",
               .angular_velocity = {0.0, 3.0, 0.0}})
      .toml();
}
}  // namespace

// [solids] hold_until = T: the grains keep their place with zero velocity and spin through every sub-step that starts
// before T, then fall freely from rest: x = x0 + g (t - t_r)^2 / 2 with t_r the first sub-step start at or after T
// (velocity Verlet is exact for a constant force, so the bound is rounding, as above). T = 20.125 ms lies mid-way
// between sub-step starts, so t_r = 20.25 ms whatever the rounding of the sub-step times.
TEST_CASE("grains held until hold_until stay in place, then fall freely from rest, and a resume keeps the hold") {
  const std::string text = held_grains_scene("hold_until = 0.020125");
  auto simulation = Simulation::from_model(parse_scene(text, "held.toml"));
  const Solids& solids = *simulation->world().solids;
  const std::vector<Vec3> start(solids.position.begin(), solids.position.end());
  for (int step = 0; step < 20; ++step) {
    simulation->step();
    for (std::size_t i = 0; i < solids.size(); ++i) {
      CHECK(solids.position[i] == start[i]);
      CHECK(solids.velocity[i] == Vec3::Zero());
      CHECK(solids.angular_velocity[i] == Vec3::Zero());
    }
  }
  // A run checkpointed while the grains are held and resumed holds them until T as well (the hold is a time).
  const auto directory = test::scratch_dir("hold_until_resume");
  const std::string path = (directory / "held.ckpt").string();
  write_checkpoint(path, simulation->checkpoint_data());
  for (int step = 20; step < 50; ++step) simulation->step();
  REQUIRE(simulation->world().step_status.ok());
  const double t = simulation->world().time, released = 0.02025, fall = t - released;
  const double rounding_bound = 4.0 * 200 * 2.2e-16 * 0.3 + 1e-15;
  for (std::size_t i = 0; i < solids.size(); ++i) {
    CHECK((solids.position[i] - (start[i] + 0.5 * fall * fall * Vec3(0.0, 0.0, -9.81))).norm() < rounding_bound);
    CHECK((solids.velocity[i] - fall * Vec3(0.0, 0.0, -9.81)).norm() < 10.0 * rounding_bound);
    CHECK(solids.angular_velocity[i] == Vec3::Zero());
  }
  auto resumed = Simulation::from_checkpoint(path);
  for (int step = 20; step < 50; ++step) resumed->step();
  CHECK(encode_checkpoint(resumed->checkpoint_data()) == encode_checkpoint(simulation->checkpoint_data()));

  // hold_until = 0: never held, the same bytes as no key (the default).
  auto unheld = Simulation::from_model(parse_scene(held_grains_scene(""), "free.toml"));
  auto zero = Simulation::from_model(parse_scene(held_grains_scene("hold_until = 0.0"), "free.toml"));
  for (int step = 0; step < 30; ++step) {
    unheld->step();
    zero->step();
  }
  for (std::size_t i = 0; i < 2; ++i) {
    CHECK(unheld->world().solids->position[i] == zero->world().solids->position[i]);
    CHECK(unheld->world().solids->velocity[i] == zero->world().solids->velocity[i]);
    CHECK(unheld->world().solids->angular_velocity[i] == zero->world().solids->angular_velocity[i]);
  }
  CHECK(unheld->world().solids->velocity[0].z() > 0.1);  // the initial 0.5 m/s upward, less 30 ms of gravity
}

namespace {
/// A rough floor in a 5 cm tank: a grain 0.1 mm above the floor fixed by `[solids] fixed_below` (centre 2.6 mm < 4 mm), a
/// free grain of the same size starting 0.1 mm above it on the same vertical, and a grain fixed by its own `fixed`
/// key in mid-air. Hertz-Mindlin grains of E = 1e7 Pa, nu = 0.3, 2650 kg/m^3, radius 2.5 mm; `motion` is appended
/// to [tank].
std::string rough_floor_scene(const std::string& motion) {
  return SceneBuilder().run({.end_time = 1.0, .dt = 1.0e-3})
      .material("grain", {.density = 2650.0, .young_modulus = 1.0e7, .poisson_ratio = 0.3})
      .tank({.size = {0.05, 0.05, 0.05}, .wall_material = "grain"}).verbatim(motion + "\n")
      .contact({.law = "hertz_mindlin", .restitution = 0.5, .friction = 0.4}).solids().set("fixed_below", 0.004)
      .sphere({.position = {0.025, 0.025, 0.0026}, .radius = 0.0025, .material = "grain"})
      .sphere({.position = {0.025, 0.025, 0.0077}, .radius = 0.0025, .material = "grain"})
      .sphere({.position = {0.01, 0.01, 0.03}, .radius = 0.0025, .material = "grain", .velocity = {0.0, 0.0, 0.5}})
      .set("fixed", true).toml();
}
}  // namespace

// [solids] fixed_below (a rough floor): a fixed grain does not respond to any force; it carries the weight of a grain
// resting on it. In a still tank the free grain comes to rest on the floor grain at Hertz's static overlap,
// delta = (3 m g / (4 E* sqrt(R*)))^(2/3) with E* = E / (2 (1 - nu^2)), R* = R/2, and the contact force on the fixed
// grain is that weight (Newton's third law); in a shaken tank the fixed grains ride with it exactly (to rounding),
// and a resume continues bit for bit.
TEST_CASE("fixed grains (a rough floor) hold still, carry a resting grain's weight, ride with the tank, and resume") {
  auto still = Simulation::from_model(parse_scene(rough_floor_scene(""), "floor.toml"));
  const Solids& grains = *still->world().solids;
  REQUIRE(grains.size() == 3);
  // The rebuilds reorder the grains (by slab and cell): grains are found by id (0: on the floor, fixed; 1: free;
  // 2: in mid-air, fixed; the scene's order).
  const auto slot_of = [](const Solids& solids, EntityId id) {
    return static_cast<std::size_t>(std::find(solids.id.begin(), solids.id.end(), id) - solids.id.begin());
  };
  std::vector<Vec3> start(3);
  for (const EntityId id : {EntityId{0}, EntityId{1}, EntityId{2}}) {
    REQUIRE(slot_of(grains, id) < 3);
    CHECK(grains.fixed[slot_of(grains, id)] == (id == 1 ? 0 : 1));
    start[id] = grains.position[slot_of(grains, id)];
  }
  for (int step = 0; step < 600; ++step) still->step();  // 0.6 s: the bounce damps out (restitution 0.5)
  REQUIRE(still->world().step_status.ok());
  const std::size_t floor = slot_of(grains, 0), free = slot_of(grains, 1), mid_air = slot_of(grains, 2);
  for (const EntityId id : {EntityId{0}, EntityId{2}}) {
    const std::size_t i = slot_of(grains, id);
    CHECK(grains.position[i] == start[id]);
    CHECK(grains.velocity[i] == Vec3::Zero());
    CHECK(grains.angular_velocity[i] == Vec3::Zero());
  }
  const double radius = 0.0025, mass = 2650.0 * 4.0 / 3.0 * 3.14159265358979323846 * radius * radius * radius;
  const double weight = mass * 9.81;
  const double effective_young = 1.0e7 / (2.0 * (1.0 - 0.3 * 0.3)), effective_radius = 0.5 * radius;
  const double overlap = std::pow(3.0 * weight / (4.0 * effective_young * std::sqrt(effective_radius)), 2.0 / 3.0);
  CHECK(grains.velocity[free].norm() < 1e-4);
  CHECK(grains.position[free].x() == start[1].x());  // on the vertical: no sideways force
  CHECK(2.0 * radius - (grains.position[free].z() - grains.position[floor].z()) == doctest::Approx(overlap).epsilon(0.01));
  CHECK(-grains.contact_force[floor].z() == doctest::Approx(weight).epsilon(1e-3));  // the floor grain carries it
  CHECK(grains.contact_force[mid_air] == Vec3::Zero());  // the one in mid-air touches nothing

  // Shaken (the seed's motion, ramped over 0.2 s): the fixed grains keep their place in the tank exactly.
  const std::string shaken_text = rough_floor_scene(SceneBuilder()
      .tank_motion({.amplitude = 0.01, .frequency = 1.7, .ramp_time = 0.2}).toml());
  const Model shaken_model = parse_scene(shaken_text, "shaken_floor.toml");
  auto shaken = Simulation::from_model(shaken_model);
  const Solids& riding = *shaken->world().solids;
  for (int step = 0; step < 400; ++step) shaken->step();
  REQUIRE(shaken->world().step_status.ok());
  const TankMotion tank = tank_kinematics(shaken_model.tank.motion, shaken->world().time);
  const TankMotion tank_start = tank_kinematics(shaken_model.tank.motion, 0.0);
  REQUIRE(std::abs(tank.displacement.x() - tank_start.displacement.x()) > 1e-3);  // it did move
  // A sum of the tank's displacement over every sub-step: rounding of order (sub-steps) x eps x |x|, as above.
  const double rounding_bound = 4.0 * 400 * static_cast<double>(shaken_model.solid_substeps) * 2.2e-16 * 0.05;
  for (const EntityId id : {EntityId{0}, EntityId{2}}) {
    const std::size_t i = slot_of(riding, id);
    REQUIRE(i < riding.size());
    CHECK((riding.position[i] - (start[id] + tank.displacement - tank_start.displacement)).norm() < rounding_bound);
    CHECK((riding.velocity[i] - tank.velocity).norm() < 1e-15);
    CHECK(riding.angular_velocity[i] == Vec3::Zero());
  }
  // Checkpointed and resumed: the flags travel, and the run continues bit for bit.
  const auto directory = test::scratch_dir("rough_floor_resume");
  const std::string path = (directory / "floor.ckpt").string();
  write_checkpoint(path, shaken->checkpoint_data());
  for (int step = 0; step < 100; ++step) shaken->step();
  auto resumed = Simulation::from_checkpoint(path);
  for (const EntityId id : {EntityId{0}, EntityId{1}, EntityId{2}})
    CHECK(resumed->world().solids->fixed[slot_of(*resumed->world().solids, id)] == (id == 1 ? 0 : 1));
  for (int step = 0; step < 100; ++step) resumed->step();
  CHECK(encode_checkpoint(resumed->checkpoint_data()) == encode_checkpoint(shaken->checkpoint_data()));
}
