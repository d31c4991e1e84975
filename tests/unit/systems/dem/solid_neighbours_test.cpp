// The grains' Verlet list (systems/dem/solid_neighbours.cpp): when it must be rebuilt, and that between rebuilds it
// misses no contact, in a shaken tank where the list is judged in the tank's frame.
#include <doctest/doctest.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/run/simulation.hpp"
#include "engine/scene/scene.hpp"
#include "systems/dem/solid_neighbours.hpp"
#include "tests/support/scene_builder.hpp"

using namespace riffle;
using riffle::test::SceneBuilder;

namespace {

/// A pile of grains dropped into a tank shaken at 1 cm and 3 Hz (up to 0.19 m/s, so the tank moves past the skin,
/// half the smallest radius, within a few steps): the pile comes to ride with the tank.
std::string shaken_pile_scene() {
  return SceneBuilder().run({.end_time = 1.0, .dt = 1.0e-3})
      .material("grain", {.density = 1318.0, .young_modulus = 1.0e7, .poisson_ratio = 0.3})
      .contact({.restitution = 0.5, .friction = 0.4, .rolling_friction = 0.1, .max_impact_speed = 0.5})
      .tank({.size = {0.04, 0.04, 0.1}, .wall_material = "grain"}).tank_motion({.amplitude = 0.01, .frequency = 3.0})
      .block({.min = {0.004, 0.004, 0.004}, .max = {0.036, 0.036, 0.02}, .spacing = 0.0052, .radius = 0.0025,
              .material = "grain"})
      .toml();
}

/// Pairs of grains that touch (centre distance below the radii's sum) and are not in the list, and grains that touch
/// a wall plane and are not in that wall's list: both must be zero whenever the list is used.
struct Missed {
  std::size_t pairs = 0, walls = 0, touching_pairs = 0, touching_walls = 0;
};
Missed missed_contacts(const World& world) {
  const Solids& solids = *world.solids;
  const Contacts& contacts = *world.contacts;
  const Walls& walls = *world.walls;
  Missed missed;
  const std::size_t count = solids.size();
  std::vector<std::vector<std::uint32_t>> listed(count);
  for (std::size_t i = 0; i < count; ++i)
    for (std::uint32_t k = contacts.pair_offsets[i]; k < contacts.pair_offsets[i + 1]; ++k) {
      listed[i].push_back(contacts.pair_second[k]);
      listed[contacts.pair_second[k]].push_back(static_cast<std::uint32_t>(i));
    }
  for (std::size_t i = 0; i < count; ++i)
    for (std::size_t j = i + 1; j < count; ++j) {
      if ((solids.position[j] - solids.position[i]).norm() >= solids.radius[i] + solids.radius[j]) continue;
      ++missed.touching_pairs;
      bool found = false;
      for (const std::uint32_t other : listed[i]) found = found || other == j;
      missed.pairs += found ? 0 : 1;
    }
  for (std::size_t i = 0; i < count; ++i)
    for (std::size_t wall = 0; wall < walls.size(); ++wall) {
      if ((solids.position[i] - walls.point[wall]).dot(walls.normal[wall]) >= solids.radius[i]) continue;
      ++missed.touching_walls;
      bool found = false;
      for (std::uint32_t k = contacts.wall_pair_offsets[i]; k < contacts.wall_pair_offsets[i + 1]; ++k)
        found = found || contacts.wall_pair_wall[k] == wall;
      missed.walls += found ? 0 : 1;
    }
  return missed;
}

}  // namespace

TEST_CASE("a list judged in the shaken tank's frame misses no contact, and outlives the tank's own travel") {
  auto simulation = Simulation::from_model(parse_scene(shaken_pile_scene(), "pile.toml"));
  // One sub-step per check would be ideal; the engine step's end is where a missed pair would still be (a pair that
  // closed within a step stays closed at its end at these speeds: the overlaps last many sub-steps).
  Missed total;
  std::size_t lab_stale_steps = 0, checked_steps = 0;
  for (int step = 0; step < 600; ++step) {
    simulation->step();
    const World& world = simulation->world();
    const Missed missed = missed_contacts(world);
    total.pairs += missed.pairs;
    total.walls += missed.walls;
    total.touching_pairs += missed.touching_pairs;
    total.touching_walls += missed.touching_walls;
    // The lab frame's rule (each grain within skin / 2 of its build position, and its move plus the walls' within the
    // skin) would have rebuilt at every step where it says stale; the tank frame's list is still in use there.
    if (step >= 300) {
      ++checked_steps;
      if (neighbour_list_stale(*world.solids, *world.contacts, *world.tank_motion, false)) ++lab_stale_steps;
      CHECK_FALSE(neighbour_list_stale(*world.solids, *world.contacts, *world.tank_motion, true));
    }
  }
  CHECK(total.touching_pairs > 6000);  // about 30 grains in contact for 600 steps
  CHECK(total.touching_walls > 6000);
  CHECK(total.pairs == 0);
  CHECK(total.walls == 0);
  // Once the pile rides with the tank (the last 300 steps, the tank 1 cm either way at 3 Hz), the lab frame's rule
  // would have found its list stale at most of those steps; the tank frame's keeps it.
  CHECK(lab_stale_steps > checked_steps / 2);
  CHECK(simulation->world().contacts->rebuilds < 300);
}

TEST_CASE("the tank frame's rule: a bed carried with the tank keeps its list, a grain moved against it does not") {
  auto simulation = Simulation::from_model(parse_scene(shaken_pile_scene(), "pile.toml"));
  for (int step = 0; step < 5; ++step) simulation->step();
  World world = simulation->world();
  Contacts& contacts = *world.contacts;
  Solids& solids = *world.solids;
  TankMotion& tank = *world.tank_motion;
  // Put the state at the build: every grain where the list was built, the tank where it was.
  for (std::size_t i = 0; i < solids.size(); ++i) solids.position[i] = contacts.build_position[i];
  tank.displacement = contacts.build_tank_displacement;
  CHECK_FALSE(neighbour_list_stale(solids, contacts, tank, true));
  CHECK_FALSE(neighbour_list_stale(solids, contacts, tank, false));
  // The bed and the tank moved together by three skins: no gap changed.
  const Vec3 carried(3.0 * contacts.skin, -1.0 * contacts.skin, 0.5 * contacts.skin);
  for (std::size_t i = 0; i < solids.size(); ++i) solids.position[i] += carried;
  tank.displacement += carried;
  CHECK_FALSE(neighbour_list_stale(solids, contacts, tank, true));
  CHECK(neighbour_list_stale(solids, contacts, tank, false));  // the lab frame cannot tell
  // One grain moves against the tank by just under the skin (its gaps to the others and to the walls close by at most
  // that), then a second by so much that the two moves add up to just under and just over the skin.
  solids.position[0] += Vec3(0.99 * contacts.skin, 0.0, 0.0);
  CHECK_FALSE(neighbour_list_stale(solids, contacts, tank, true));
  solids.position[0] -= Vec3(0.50 * contacts.skin, 0.0, 0.0);
  solids.position[1] += Vec3(0.0, 0.0, 0.50 * contacts.skin);
  CHECK_FALSE(neighbour_list_stale(solids, contacts, tank, true));
  solids.position[1] += Vec3(0.0, 0.0, 0.02 * contacts.skin);
  CHECK(neighbour_list_stale(solids, contacts, tank, true));
  solids.position[1] -= Vec3(0.0, 0.0, 0.52 * contacts.skin);
  solids.position[0] += Vec3(0.52 * contacts.skin, 0.0, 0.0);  // one grain past the skin alone
  CHECK(neighbour_list_stale(solids, contacts, tank, true));
}
