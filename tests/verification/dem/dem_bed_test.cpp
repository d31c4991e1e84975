// Settled beds and hard cases for the DEM: force balance at rest, and runs that must neither explode nor lose grains.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "engine/scene/scene.hpp"
#include "engine/run/simulation.hpp"
#include "tests/support/scene_builder.hpp"

using namespace riffle;
using riffle::test::SceneBuilder;

namespace {

/// A small closed tank with contacts; `solids` and `extra` are appended verbatim.
std::string dem_scene(const std::string& solids, double end_time = 0.3, const std::string& motion = "",
                      const std::string& contact = "restitution = 0.5\nfriction = 0.4\n") {
  return SceneBuilder(SceneBuilder::kSpaced).run({.end_time = end_time, .dt = 1.0e-3})
             .material("grain", {.density = 1318.0, .young_modulus = 1.0e8, .poisson_ratio = 0.3})
             .material("heavy", {.density = 7800.0, .young_modulus = 1.0e8, .poisson_ratio = 0.3})
             .material("glass", {.density = 2500.0, .young_modulus = 1.0e8, .poisson_ratio = 0.3})
             .table("contact").verbatim(contact).tank({.size = {0.04, 0.04, 0.08}, .wall_material = "glass"})
             .verbatim(motion).solids().toml() +
         solids;
}

double total_weight(const Solids& solids, const Vec3& gravity) {
  double mass = 0.0;
  for (double m : solids.mass) mass += m;
  return mass * gravity.norm();
}

/// Runs until t_end or the first problem; returns the number of steps taken.
int run_steps(Simulation& simulation, int steps) {
  int taken = 0;
  while (taken < steps && simulation.world().step_status.ok()) {
    simulation.step();
    ++taken;
  }
  return taken;
}

double largest_dimensionless_overlap(const Solids& solids, const Contacts& contacts) {
  double largest = 0.0;
  for (std::size_t i = 0; i < solids.size(); ++i)
    for (std::uint32_t k = contacts.pair_offsets[i]; k < contacts.pair_offsets[i + 1]; ++k) {
      const std::uint32_t j = contacts.pair_second[k];
      largest = std::max(largest, contacts.pair_overlap[k] / (solids.radius[i] + solids.radius[j]));
    }
  return largest;
}

const std::string kLooseBlock = SceneBuilder().within("solids")
    .block({.min = {0.004, 0.004, 0.004}, .max = {0.036, 0.036, 0.03}, .spacing = 0.0065, .radius = 0.0025,
            .material = "grain", .velocity = {0.05, -0.03, 0.0}})
    .toml();

}  // namespace

TEST_CASE("a settled bed: the walls carry the whole weight and the grains come to rest") {
  // Rolling friction makes the bed come to rest in a few tenths of a second (without it, grains keep rolling in
  // their pockets for much longer, which is physical but slow to test).
  const std::string contact = "restitution = 0.5\nfriction = 0.4\nrolling_friction = 0.02\n";
  auto simulation = Simulation::from_model(parse_scene(dem_scene(kLooseBlock, 0.4, "", contact), "settle.toml"));
  int steps = 0;
  double peak_energy = 0.0;
  for (int k = 0; k < 8; ++k) {
    steps += run_steps(*simulation, 50);
    peak_energy = std::max(peak_energy, simulation->world().solid_summary->translational_energy);
  }
  REQUIRE(simulation->world().step_status.ok());
  CHECK(steps == 400);
  const Solids& solids = *simulation->world().solids;
  const Contacts& contacts = *simulation->world().contacts;
  Vec3 wall_reaction = Vec3::Zero();  // force the grains exert on the walls = minus the walls' force on grains
  for (const Vec3& force : contacts.wall_pair_force) wall_reaction -= force;
  const Vec3 gravity = simulation->model().gravity;
  const double weight = total_weight(solids, gravity);
  // At rest, Newton: sum of wall forces on the grains = -(total weight); the residual is the grains' total
  // m dv/dt, bounded by the kinetic energy still left. Require 1 % of the weight.
  INFO("wall reaction " << wall_reaction.transpose() << " N, weight " << weight << " N");
  CHECK(wall_reaction.z() == doctest::Approx(-weight).epsilon(0.01));
  CHECK(std::abs(wall_reaction.x()) < 0.01 * weight);
  CHECK(std::abs(wall_reaction.y()) < 0.01 * weight);
  const SolidSummary& summary = *simulation->world().solid_summary;
  // Coming to rest: the kinetic energy has fallen by two orders of magnitude from its peak during the fall.
  CHECK(summary.translational_energy < 1e-2 * peak_energy);
  CHECK(summary.rotational_energy < 1e-2 * peak_energy);
  // Overlaps stay small: E = 1e8 Pa under a few grain weights gives d/d_ij of order 1e-4.
  CHECK(largest_dimensionless_overlap(solids, contacts) < 0.005);
}

TEST_CASE("hard case: a high-speed impact at 10 times the design speed neither explodes nor tunnels") {
  const std::string solids = SceneBuilder().within("solids")
      .sphere({.position = {0.02, 0.02, 0.02}, .radius = 0.0025, .material = "grain", .velocity = {0.0, 0.0, -10.0}})
      .toml();
  auto simulation = Simulation::from_model(parse_scene(dem_scene(solids, 0.02), "impact.toml"));
  // It reaches the floor after 1.75 ms; the Hertz contact at 10 m/s lasts about 0.1 ms.
  run_steps(*simulation, 3);
  REQUIRE(simulation->world().step_status.ok());
  const Solids& grains = *simulation->world().solids;
  // The sub-step was chosen for 1 m/s impacts (16 steps per collision); at 10 m/s a collision still spans
  // 16 / 10^0.2 = 10 sub-steps, so the calibrated restitution 0.5 holds to the O((dt/t_c)^2) ~ 1e-2 level.
  CHECK(grains.velocity[0].z() == doctest::Approx(0.5 * 10.0).epsilon(0.05));
  CHECK(grains.position[0].z() > grains.radius[0]);
}

TEST_CASE("hard case: a heavy sphere dropped on a dense packing") {
  std::string solids = SceneBuilder(SceneBuilder::kSpaced).within("solids")
      .block({.min = {0.0026, 0.0026, 0.0026}, .max = {0.0374, 0.0374, 0.018}, .spacing = 0.0051, .radius = 0.0025,
              .material = "grain"})
      .sphere({.position = {0.02, 0.02, 0.05}, .radius = 0.0075, .material = "heavy", .velocity = {0.0, 0.0, -1.0}})
      .toml();
  auto simulation = Simulation::from_model(parse_scene(dem_scene(solids, 0.2), "heavy.toml"));
  const std::size_t grains = simulation->world().solids->size();
  run_steps(*simulation, 200);
  INFO("status: " << static_cast<int>(simulation->world().step_status.problem));
  REQUIRE(simulation->world().step_status.ok());
  const Solids& solids_after = *simulation->world().solids;
  CHECK(solids_after.size() == grains);
  // No grain pushed through the floor or out of the tank.
  for (std::size_t i = 0; i < solids_after.size(); ++i) {
    CHECK(solids_after.position[i].z() > 0.5 * solids_after.radius[i]);
    CHECK(solids_after.position[i].x() > 0.0);
    CHECK(solids_after.position[i].x() < 0.04);
  }
  CHECK(largest_dimensionless_overlap(solids_after, *simulation->world().contacts) < 0.02);
}

TEST_CASE("hard case: grains wedged in the corners of a violently shaken tank stay in it") {
  std::string solids;
  for (double x : {0.0026, 0.0374})
    for (double y : {0.0026, 0.0374})
      for (double z : {0.0026, 0.0077}) {
        char sphere[256];
        std::snprintf(sphere, sizeof sphere,
                      "[[solids.spheres]]\nposition = [%g, %g, %g]\nradius = 0.0025\nmaterial = \"grain\"\n", x, y, z);
        solids += sphere;
      }
  // 2 cm at 5 Hz: 20 m/s^2 peak, twice gravity, with no ramp: an abrupt start.
  const std::string motion = "[tank.motion]\nkind = \"sinusoidal\"\namplitude = 0.02\nfrequency = 5.0\n";
  auto simulation = Simulation::from_model(parse_scene(dem_scene(solids, 0.4, motion), "corners.toml"));
  const int steps = run_steps(*simulation, 400);
  CHECK(steps == 400);
  CHECK(simulation->world().step_status.ok());
  const Solids& grains = *simulation->world().solids;
  const Vec3 tank_offset = simulation->world().tank_motion->displacement;
  for (std::size_t i = 0; i < grains.size(); ++i) {
    const Vec3 local = grains.position[i] - tank_offset;  // position in the tank's frame
    // Inside the tank up to a small overlap with a wall.
    CHECK(local.x() > 0.8 * grains.radius[i]);
    CHECK(local.x() < 0.04 - 0.8 * grains.radius[i]);
    CHECK(local.z() > 0.8 * grains.radius[i]);
  }
}

TEST_CASE("hard case: a large sphere on a layer of small ones neither tunnels nor is thrown out") {
  const std::string solids = SceneBuilder(SceneBuilder::kSpaced).within("solids")
      .block({.min = {0.0026, 0.0026, 0.0026}, .max = {0.0374, 0.0374, 0.0026}, .spacing = 0.0051, .radius = 0.0025,
              .material = "grain"})
      .sphere({.position = {0.02, 0.02, 0.0135}, .radius = 0.0075, .material = "grain"}).toml();
  const std::string contact = "restitution = 0.5\nfriction = 0.4\nrolling_friction = 0.02\n";
  auto simulation = Simulation::from_model(parse_scene(dem_scene(solids, 0.3, "", contact), "large_on_small.toml"));
  const EntityId large = 0;  // explicit spheres get the first ids (slots may already be reordered by cell)
  run_steps(*simulation, 300);
  REQUIRE(simulation->world().step_status.ok());
  const Solids& grains = *simulation->world().solids;
  const std::size_t slot = static_cast<std::size_t>(
      std::find(grains.id.begin(), grains.id.end(), large) - grains.id.begin());
  // It wedges the small grains apart on the frictional floor and sinks slowly (physical), but it can neither pass
  // through them to the floor nor be thrown up: its centre stays between its own radius (touching the floor) and
  // its start, and every grain stays in the tank.
  CHECK(grains.position[slot].z() > 0.0075);
  CHECK(grains.position[slot].z() < 0.0135);
  for (std::size_t i = 0; i < grains.size(); ++i) {
    CHECK(grains.position[i].z() > 0.9 * grains.radius[i]);
    CHECK(std::abs(grains.position[i].x() - 0.02) < 0.02);
    CHECK(std::abs(grains.position[i].y() - 0.02) < 0.02);
  }
  // Energy stays bounded by what gravity can release (the sphere's fall of at most 6 mm plus the small grains').
  CHECK(simulation->world().solid_summary->translational_energy < 2.3e-3 * 9.81 * 0.006);
}
