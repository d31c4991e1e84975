// The grains' decomposition over MPI ranks (systems/physics/ranks/grain_ranks.hpp), on the one rank of a process
// started without mpirun: the split, the rebuild with carried springs, and the gathered world that a run over ranks
// writes its outputs and checkpoints from. Several ranks are tested under mpiexec (tests/mpi/); these cases run in
// every build, with MPI or without.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "engine/run/simulation.hpp"
#include "engine/scene/scene.hpp"

using namespace riffle;

namespace {

/// tests/data/shaken_bed.toml: 520 grains of 4 and 6 mm dropped into a tank shaken sideways, falling, colliding and
/// sliding along the floor, with springs on grain pairs and walls.
Model shaken_bed() { return load_scene_file(RIFFLE_SOURCE_DIR "/tests/data/shaken_bed.toml"); }

/// slot of each id
std::map<EntityId, std::size_t> slots_by_id(const Solids& solids) {
  std::map<EntityId, std::size_t> slots;
  for (std::size_t i = 0; i < solids.size(); ++i) slots[solids.id[i]] = i;
  return slots;
}

/// Largest distance between the same grain in two tables.
double largest_position_difference(const Solids& a, const Solids& b) {
  const auto in_b = slots_by_id(b);
  double largest = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) largest = std::max(largest, (a.position[i] - b.position[in_b.at(a.id[i])]).norm());
  return largest;
}

/// The touching pairs' springs by (lower id, higher id), oriented for the lower id.
std::map<std::pair<EntityId, EntityId>, Vec3> touching_springs(const Solids& solids, const Contacts& contacts) {
  std::map<std::pair<EntityId, EntityId>, Vec3> springs;
  for (std::size_t i = 0; i < solids.size(); ++i)
    for (std::uint32_t k = contacts.pair_offsets[i]; k < contacts.pair_offsets[i + 1]; ++k) {
      if (contacts.pair_overlap[k] <= 0.0) continue;
      const EntityId first = solids.id[i], second = solids.id[contacts.pair_second[k]];
      springs[{std::min(first, second), std::max(first, second)}] =
          first < second ? contacts.pair_spring[k] : Vec3(-contacts.pair_spring[k]);
    }
  return springs;
}

}  // namespace

TEST_CASE("a bed split over the one rank of a process runs as the bed unsplit, to rounding") {
  // The split drops the neighbour list and carries the springs by id to the first rebuild; with one rank nothing
  // migrates and no ghost comes, so every force is the same but for the order of a grain's sum (that rebuild, a step
  // earlier than the unsplit run's, reorders the slots): rounding, which the colliding bed amplifies about tenfold
  // every 10 steps (tests/mpi/grain_ranks.cpp), 2e-15 m after 20 steps here; 1e-12 m allows that growth and catches
  // any lost spring or contact (a spring's force on these grains moves them by more than 1e-9 m in a step).
  auto whole = Simulation::from_model(shaken_bed());
  auto split = Simulation::from_model(shaken_bed());
  for (int step = 0; step < 100; ++step) {  // falling, then the first collisions: springs on pairs and walls
    whole->step();
    split->step();
  }
  REQUIRE(touching_springs(*split->world().solids, *split->world().contacts).size() > 50);
  split->split_over_ranks();
  CHECK(split->over_ranks());
  CHECK(split->world().solids->size() == whole->world().solids->size());
  for (int step = 0; step < 20; ++step) {
    whole->step();
    split->step();
  }
  MESSAGE("largest position difference after 20 steps: ",
          largest_position_difference(*whole->world().solids, *split->world().solids), " m");
  CHECK(largest_position_difference(*whole->world().solids, *split->world().solids) < 1e-12);
  CHECK(split->world().solid_summary->translational_energy ==
        doctest::Approx(whole->world().solid_summary->translational_energy).epsilon(1e-9));
}

TEST_CASE("the gathered world holds every grain and touching spring, and its checkpoint resumes the run") {
  auto run = Simulation::from_model(shaken_bed());
  for (int step = 0; step < 80; ++step) run->step();
  run->split_over_ranks();
  for (int step = 0; step < 40; ++step) run->step();
  const World whole = run->gathered_world();
  REQUIRE(whole.solids);
  REQUIRE(whole.contacts);
  const Solids& grains = *run->world().solids;
  CHECK(whole.solids->size() == grains.size());
  CHECK(std::is_sorted(whole.solids->id.begin(), whole.solids->id.end()));
  CHECK(largest_position_difference(*whole.solids, grains) == 0.0);
  // Every touching pair's spring is in the gathered list, by id (the list over the whole bed is the checkpoint's).
  const auto running = touching_springs(grains, *run->world().contacts);
  const auto gathered = touching_springs(*whole.solids, *whole.contacts);
  REQUIRE(running.size() > 50);
  CHECK(gathered.size() == running.size());
  std::size_t same = 0;
  for (const auto& [pair, spring] : running) {
    const auto found = gathered.find(pair);
    if (found != gathered.end() && found->second == spring) ++same;
  }
  CHECK(same == running.size());
  // The wall contacts' forces as the run had them (the wall probes read them).
  Vec3 wall_force = Vec3::Zero(), gathered_wall_force = Vec3::Zero();
  for (const Vec3& force : run->world().contacts->wall_pair_force) wall_force += force;
  for (const Vec3& force : whole.contacts->wall_pair_force) gathered_wall_force += force;
  CHECK((wall_force - gathered_wall_force).norm() <= 1e-12 * wall_force.norm());
  CHECK(wall_force.norm() > 0.0);
  // Resumed from the gathered checkpoint, the bed goes on as the run does: to rounding (the resumed list is built at
  // other times, so its slots, hence its sums' order, differ), grown where a contact starts or a spring slips, over
  // the next 10 steps of colliding grains (1e-15 m after 9 steps, 8e-12 m after 10). A contact missed or a spring
  // lost would move a grain by the order of the contacts' overlaps (a few 1e-6 m for these E = 1e7 grains).
  auto resumed = Simulation::from_checkpoint_data(run->checkpoint_data_of(whole), "gathered");
  CHECK_FALSE(resumed->over_ranks());
  for (int step = 0; step < 10; ++step) {
    run->step();
    resumed->step();
  }
  MESSAGE("largest position difference after 10 steps: ",
          largest_position_difference(*run->world().solids, *resumed->world().solids), " m");
  CHECK(largest_position_difference(*run->world().solids, *resumed->world().solids) < 1e-9);
}
