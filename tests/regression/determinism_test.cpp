// Determinism: identical checkpoint bytes for any thread count and for resumed versus uninterrupted runs.
#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <map>
#include <optional>
#include <utility>

#include "engine/output/checkpoint.hpp"
#include "engine/setup/initial_state.hpp"
#include "systems/physics/mps/mps_common.hpp"
#include "systems/dem/solid_neighbours.hpp"
#include "engine/run/simulation.hpp"
#include "tests/support/test_support.hpp"
#include "tests/support/scene_builder.hpp"

using namespace riffle;
using riffle::test::SceneBuilder;

namespace {
/// A scene large enough that parallel loops really split (several thousand grains).
std::string busy_scene() {
  std::string text = test::small_scene_text(SceneBuilder().within("solids")
      .block({.min = {0.01, 0.01, 0.01}, .max = {0.23, 0.15, 0.08}, .spacing = 0.006, .radius = 0.0025,
              .material = "grain", .velocity = {0.3, 0.1, 1.0}})
      .toml());
  return text;
}

/// Checkpoint bytes after `steps` steps of `scene_text` on `threads` threads.
std::string checkpoint_bytes_after(const std::string& scene_text, const std::string& file, int threads, int steps) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  auto simulation = Simulation::from_model(parse_scene(scene_text, file));
  for (int step = 0; step < steps; ++step) simulation->step();
  REQUIRE(simulation->world().step_status.ok());
  return encode_checkpoint(simulation->checkpoint_data());
}

/// Checkpoint bytes after `steps` steps of `scene_text`, written to a checkpoint after `split` and resumed from it.
std::string resumed_checkpoint_bytes(const std::string& scene_text, const std::string& file, int split, int steps) {
  const auto directory = test::scratch_dir("determinism_" + file);
  auto first_part = Simulation::from_model(parse_scene(scene_text, file));
  for (int step = 0; step < split; ++step) first_part->step();
  REQUIRE(first_part->world().step_status.ok());
  const std::string path = (directory / "part.ckpt").string();
  write_checkpoint(path, first_part->checkpoint_data());
  first_part.reset();
  auto resumed = Simulation::from_checkpoint(path);
  REQUIRE(resumed->world().step == static_cast<std::uint64_t>(split));
  for (int step = split; step < steps; ++step) resumed->step();
  REQUIRE(resumed->world().step_status.ok());
  return encode_checkpoint(resumed->checkpoint_data());
}
}  // namespace

TEST_CASE("one and two threads give byte-identical checkpoints") {
  const std::string one = checkpoint_bytes_after(busy_scene(), "busy.toml", 1, 40);
  const std::string two = checkpoint_bytes_after(busy_scene(), "busy.toml", 2, 40);
  CHECK(one.size() == two.size());
  CHECK(one == two);
}

TEST_CASE("resuming from a checkpoint equals the uninterrupted run byte for byte") {
  // 23 is not a multiple of sort_every = 7
  CHECK(resumed_checkpoint_bytes(busy_scene(), "busy.toml", 23, 60) ==
        checkpoint_bytes_after(busy_scene(), "busy.toml", 2, 60));
}

TEST_CASE("the grain count and summary are unchanged by reordering") {
  auto simulation = Simulation::from_model(parse_scene(busy_scene(), "busy.toml"));
  const std::size_t grains = simulation->world().solids->size();
  for (int step = 0; step < 14; ++step) simulation->step();  // two cell sorts
  CHECK(simulation->world().solids->size() == grains);
  CHECK_NOTHROW(check_field_sizes(*simulation->world().solids, "solids"));
  std::vector<EntityId> ids = simulation->world().solids->id;
  std::sort(ids.begin(), ids.end());
  for (std::size_t k = 0; k < ids.size(); ++k) CHECK(ids[k] == k);
}

namespace {
/// Grains falling into a pile with contacts: rebuilds, reordering by cell (every rebuild) and sliding contacts, so
/// tangential springs must be carried across reorders and checkpoints.
/// `rolling_law`: [contact] rolling_law ("elastic_plastic": rolling springs too).
std::string contact_scene(const std::string& rolling_law = "constant_torque") {
  return SceneBuilder().run({.end_time = 1.0, .dt = 1.0e-3})
      .material("grain", {.density = 1318.0, .young_modulus = 1.0e8, .poisson_ratio = 0.3})
      .contact({.restitution = 0.5, .friction = 0.4, .rolling_friction = 0.01}).set("sort_every_rebuild", 1)
      .set("rolling_law", rolling_law)
      .tank({.size = {0.04, 0.04, 0.1}, .wall_material = "grain"}).tank_motion({.amplitude = 0.01, .frequency = 3.0})
      .block({.min = {0.004, 0.004, 0.004}, .max = {0.036, 0.036, 0.03}, .spacing = 0.0062, .radius = 0.0025,
              .material = "grain", .velocity = {0.2, -0.1, 0.0}})
      .toml();
}
}  // namespace

TEST_CASE("with contacts: one and two threads, and resumed runs, give byte-identical checkpoints") {
  for (const std::string rolling_law : {"constant_torque", "elastic_plastic"}) {
    INFO("rolling_law " << rolling_law);
    const std::string one = checkpoint_bytes_after(contact_scene(rolling_law), "pile.toml", 1, 60);
    const std::string two = checkpoint_bytes_after(contact_scene(rolling_law), "pile.toml", 2, 60);
    CHECK(one == two);

    const auto directory = test::scratch_dir("determinism_contacts");
    auto first_part = Simulation::from_model(parse_scene(contact_scene(rolling_law), "pile.toml"));
    for (int step = 0; step < 37; ++step) first_part->step();
    // The list was rebuilt (and the grains reordered) and springs are loaded: the checkpoint must carry both.
    const Contacts& contacts = *first_part->world().contacts;
    CHECK(contacts.rebuilds > 1);
    bool loaded_spring = false, loaded_rolling_spring = false;
    for (const Vec3& spring : contacts.pair_spring) loaded_spring = loaded_spring || spring.norm() > 0.0;
    for (const Vec3& spring : contacts.pair_rolling_spring)
      loaded_rolling_spring = loaded_rolling_spring || spring.norm() > 0.0;
    CHECK(loaded_spring);
    CHECK(loaded_rolling_spring == (rolling_law == "elastic_plastic"));
    const std::string path = (directory / "part.ckpt").string();
    write_checkpoint(path, first_part->checkpoint_data());
    first_part.reset();
    auto resumed = Simulation::from_checkpoint(path);
    for (int step = 37; step < 60; ++step) resumed->step();
    CHECK(encode_checkpoint(resumed->checkpoint_data()) == two);
  }
}

namespace {
/// Tangential springs of touching pairs keyed by (lower id, higher id), oriented for the lower id.
std::map<std::pair<EntityId, EntityId>, Vec3> springs_by_id(const Solids& solids, const Contacts& contacts) {
  std::map<std::pair<EntityId, EntityId>, Vec3> springs;
  for (std::size_t i = 0; i < solids.size(); ++i)
    for (std::uint32_t k = contacts.pair_offsets[i]; k < contacts.pair_offsets[i + 1]; ++k) {
      // Touching by geometry: the list may just have been rebuilt, before the force system refreshed its overlaps.
      const std::uint32_t j = contacts.pair_second[k];
      if ((solids.position[j] - solids.position[i]).norm() >= solids.radius[i] + solids.radius[j]) continue;
      const EntityId first = solids.id[i], second = solids.id[j];
      const Vec3& spring = contacts.pair_spring[k];
      springs[{std::min(first, second), std::max(first, second)}] = first < second ? spring : Vec3(-spring);
    }
  return springs;
}
}  // namespace

TEST_CASE("a neighbour-list rebuild that reorders the grains keeps every tangential spring with its pair") {
  auto simulation = Simulation::from_model(parse_scene(contact_scene(), "pile.toml"));
  for (int step = 0; step < 40; ++step) simulation->step();
  // From step 40 on, the first state where a reordering rebuild moves grains (they moved across a slab or a cell
  // since the last sort), rebuilt in a copy of the world.
  std::optional<World> rebuilt;
  std::map<std::pair<EntityId, EntityId>, Vec3> before;
  for (int step = 40; step < 400 && !rebuilt; ++step) {
    simulation->step();
    World world = simulation->world();
    before = springs_by_id(*world.solids, *world.contacts);
    const std::vector<EntityId> ids_before = world.solids->id;
    rebuild_neighbour_list(*world.solids, *world.contacts, *world.walls, *world.tank_motion, simulation->model(), true);
    if (world.solids->id != ids_before) rebuilt = std::move(world);
  }
  REQUIRE(rebuilt.has_value());
  REQUIRE(before.size() > 10);
  const World& world = *rebuilt;
  const auto after = springs_by_id(*world.solids, *world.contacts);
  REQUIRE(after.size() == before.size());
  for (const auto& [pair, spring] : before) {
    REQUIRE(after.count(pair) == 1);
    CHECK(after.at(pair) == spring);  // carried over by id, bit for bit
  }
}

TEST_CASE("a pair apart at a rebuild's positions keeps no spring: its next touch starts afresh") {
  // Between the last force evaluation and a rebuild a touching pair can come apart. The new list starts every pair at
  // zero overlap, so the contact pass would not see it separate: a spring carried to it would outlive the contact.
  auto simulation = Simulation::from_model(parse_scene(contact_scene(), "pile.toml"));
  for (int step = 0; step < 40; ++step) simulation->step();
  World& world = simulation->world();
  Solids& solids = *world.solids;
  const auto before = springs_by_id(solids, *world.contacts);
  REQUIRE(before.size() > 10);
  // Pull the first spring-loaded pair's higher-id grain off along their centre line, a micrometre past touching.
  const auto& [ids, spring] = *before.begin();
  std::size_t lower = 0, higher = 0;
  for (std::size_t i = 0; i < solids.size(); ++i) {
    if (solids.id[i] == ids.first) lower = i;
    if (solids.id[i] == ids.second) higher = i;
  }
  REQUIRE(spring.norm() > 0.0);
  const Vec3 line = solids.position[higher] - solids.position[lower];
  const double apart = solids.radius[lower] + solids.radius[higher] + 1.0e-6;
  solids.position[higher] = solids.position[lower] + apart * line.normalized();
  rebuild_neighbour_list(solids, *world.contacts, *world.walls, *world.tank_motion, simulation->model(), false);
  const Contacts& contacts = *world.contacts;
  std::size_t apart_pairs = 0;
  bool separated_pair_listed = false;
  for (std::size_t i = 0; i < solids.size(); ++i)
    for (std::uint32_t k = contacts.pair_offsets[i]; k < contacts.pair_offsets[i + 1]; ++k) {
      const std::uint32_t j = contacts.pair_second[k];
      if ((solids.position[j] - solids.position[i]).norm() < solids.radius[i] + solids.radius[j]) continue;
      ++apart_pairs;
      CHECK(contacts.pair_spring[k] == Vec3::Zero());
      separated_pair_listed = separated_pair_listed || (solids.id[i] == ids.first && solids.id[j] == ids.second) ||
                              (solids.id[i] == ids.second && solids.id[j] == ids.first);
    }
  CHECK(apart_pairs > 0);
  CHECK(separated_pair_listed);  // still a candidate (within the skin), now without its spring
  // Every other pair still touching keeps its spring, bit for bit.
  const auto after = springs_by_id(solids, contacts);
  for (const auto& [pair, kept] : after)
    if (before.count(pair) == 1) CHECK(kept == before.at(pair));
}

namespace {
/// A dam break in the shaken seed tank: the fluid moves fast (Courant-limited steps, neighbour rebuilds, surface
/// particles come and go) and the PPE warm start carries state between steps.
std::string fluid_scene() {
  return SceneBuilder().run({.end_time = 1.0, .dt = 1.0e-3}).material("glass", {.density = 2500.0})
      .tank({.size = {0.12, 0.04, 0.08}, .open_faces = {"z_max"}, .wall_material = "glass"})
      .tank_motion({.amplitude = 0.01, .frequency = 1.7}).fluid({.spacing = 0.005})
      .fluid_box({0.0, 0.0, 0.0}, {0.04, 0.04, 0.06}, {0.2, 0.0, 0.0}).toml();
}
}  // namespace

TEST_CASE("a fluid run gives byte-identical checkpoints on one and two threads") {
  CHECK(checkpoint_bytes_after(fluid_scene(), "fluid.toml", 1, 60) ==
        checkpoint_bytes_after(fluid_scene(), "fluid.toml", 2, 60));
}

TEST_CASE("a resumed fluid run equals the uninterrupted one byte for byte") {
  CHECK(resumed_checkpoint_bytes(fluid_scene(), "fluid.toml", 27, 60) ==
        checkpoint_bytes_after(fluid_scene(), "fluid.toml", 2, 60));
}

TEST_CASE("reordering the fluid by cell moves slots, not particles: results agree by id to rounding") {
  const auto run = [](std::int64_t sort_every, std::int64_t sort_every_fast) {
    std::string scene = fluid_scene();
    scene.replace(scene.find("spacing = 0.005"), 15,
                  "spacing = 0.005\nsort_every = " + std::to_string(sort_every) +
                      "\nsort_every_fast = " + std::to_string(sort_every_fast));
    auto simulation = Simulation::from_model(parse_scene(scene, "fluid.toml"));
    for (int step = 0; step < 60; ++step) simulation->step();
    REQUIRE(simulation->world().step_status.ok());
    return *simulation->world().fluid;
  };
  const FluidParticles unsorted = run(0, 0);
  // Every 7 steps whatever the flow, and every 3 steps only while it is fast (the splashing column is).
  for (const std::pair<int, int>& setting : {std::pair{7, 0}, std::pair{0, 3}}) {
    const int every = setting.first, every_fast = setting.second;  // named: clang 14 cannot capture a binding
    CAPTURE(every);
    const FluidParticles sorted = run(every, every_fast);
    REQUIRE(sorted.size() == unsorted.size());
    CHECK(sorted.id != unsorted.id);  // the sort moved particles to other slots
    const std::size_t fluid = fluid_slot_count(sorted);
    CHECK(fluid == fluid_slot_count(unsorted));
    for (std::size_t i = fluid; i < sorted.size(); ++i) CHECK(sorted.kind[i] != kFluidKind);
    std::vector<std::size_t> slot_of(sorted.size());
    for (std::size_t i = 0; i < sorted.size(); ++i) slot_of[sorted.id[i]] = i;
    // Only the order of the terms in the neighbour sums changes, so the states differ by rounding, amplified over
    // 60 steps of a splashing flow: far below the 5 mm spacing and the 10 Pa pressures.
    double position_difference = 0.0, pressure_difference = 0.0;
    for (std::size_t i = 0; i < unsorted.size(); ++i) {
      const std::size_t k = slot_of[unsorted.id[i]];
      position_difference = std::max(position_difference, (sorted.position[k] - unsorted.position[i]).norm());
      pressure_difference = std::max(pressure_difference, std::abs(sorted.pressure[k] - unsorted.pressure[i]));
    }
    MESSAGE("largest difference by id: position " << position_difference << " m, pressure " << pressure_difference
                                                  << " Pa");
    CHECK(position_difference < 1.0e-9);
    CHECK(pressure_difference < 1.0e-3);
  }
}

TEST_CASE("the neighbour skin, fixed or narrowed in fast flow, changes no result") {
  // The lists are cut at r_e by every operator and kept ascending, so the skin only decides how often they are
  // rebuilt and how long they are: the states must be identical to the last bit (the checkpoints differ only by
  // the scene text they carry).
  const auto run = [](const std::string& skins, double* narrowest_radius, std::uint64_t* builds) {
    std::string scene = fluid_scene();
    scene.replace(scene.find("spacing = 0.005"), 15, "spacing = 0.005\n" + skins);
    auto simulation = Simulation::from_model(parse_scene(scene, "fluid.toml"));
    double narrowest = 1.0;
    for (int step = 0; step < 60; ++step) {
      simulation->step();
      narrowest = std::min(narrowest, simulation->world().fluid_neighbours->radius);
    }
    REQUIRE(simulation->world().step_status.ok());
    if (narrowest_radius) *narrowest_radius = narrowest;
    if (builds) *builds = simulation->world().fluid_neighbours->builds;
    return *simulation->world().fluid;
  };
  double narrowest = 0.0;
  std::uint64_t adaptive_builds = 0, wide_builds = 0;
  const FluidParticles adaptive =
      run("neighbour_skin = 0.3\nneighbour_skin_narrow = 0.1", &narrowest, &adaptive_builds);
  const FluidParticles wide = run("neighbour_skin = 0.3\nneighbour_skin_narrow = 0.3", nullptr, &wide_builds);
  // Without a skin the cell sort's cells change too, and with them the order of the terms: compare unsorted runs.
  const FluidParticles adaptive_unsorted =
      run("neighbour_skin = 0.3\nneighbour_skin_narrow = 0.1\nsort_every = 0\nsort_every_fast = 0", nullptr, nullptr);
  const FluidParticles none_unsorted = run("neighbour_skin = 0.0\nsort_every = 0\nsort_every_fast = 0", nullptr, nullptr);
  for (const auto& compared : {std::pair{&adaptive, &wide}, std::pair{&adaptive_unsorted, &none_unsorted}}) {
    const FluidParticles* one = compared.first;  // named: clang 14 cannot capture a structured binding
    const FluidParticles* other = compared.second;
    CAPTURE(other == &wide);
    CHECK(one->position == other->position);
    CHECK(one->velocity == other->velocity);
    CHECK(one->pressure == other->pressure);
    CHECK(one->number_density == other->number_density);
  }
  // The splashing column uses up the wide skin within a step at times, so the narrow lists were built and used.
  MESSAGE("builds in 60 steps: adaptive " << adaptive_builds << ", wide " << wide_builds);
  CHECK(narrowest == doctest::Approx(2.4 * 0.005 + 0.1 * 0.005).epsilon(1e-12));
  CHECK(adaptive_builds > wide_builds);
}

namespace {
/// Grains in shaken water, contacts and drag on: the two branches of a step run side by side, the grains sample the
/// step-start copy of the water, and the drag goes back to the water at the end of the step (docs/COUPLING.md).
std::string coupled_scene() {
  return SceneBuilder().run({.end_time = 1.0, .dt = 1.0e-3, .solid_substeps = 50})
      .material("grain", {.density = 1318.0, .young_modulus = 1.0e7, .poisson_ratio = 0.3})
      .material("glass", {.density = 2500.0, .young_modulus = 1.0e8, .poisson_ratio = 0.3})
      .contact({.law = "hertz_mindlin", .restitution = 0.5, .friction = 0.4})
      .tank({.size = {0.08, 0.04, 0.08}, .open_faces = {"z_max"}, .wall_material = "glass"})
      .tank_motion({.amplitude = 0.01, .frequency = 1.7})
      .block({.min = {0.005, 0.005, 0.005}, .max = {0.075, 0.035, 0.03}, .spacing = 0.0055, .radius = 0.0025,
              .material = "grain", .velocity = {0.05, 0.0, -0.1}})
      .fluid({.spacing = 0.005}).fluid_box({0.0, 0.0, 0.0}, {0.08, 0.04, 0.05})
      .coupling().set("fluid_velocity", "mixture").toml();
}
}  // namespace

TEST_CASE("grains in water: one and two threads, and a resumed run, give byte-identical checkpoints") {
  REQUIRE(initial_world(parse_scene(coupled_scene(), "coupled.toml")).solids->size() > 100);
  const std::string uninterrupted = checkpoint_bytes_after(coupled_scene(), "coupled.toml", 2, 30);
  CHECK(checkpoint_bytes_after(coupled_scene(), "coupled.toml", 1, 30) == uninterrupted);
  // The grains sample a copy of the water taken at each step start: the resumed run takes it from the restored water.
  CHECK(resumed_checkpoint_bytes(coupled_scene(), "coupled.toml", 13, 30) == uninterrupted);
}

TEST_CASE("grains in water with added mass and the history force: threads and a resumed run give the same bytes") {
  // The history force's state lives in grain fields (GrainAddedMass), so a checkpoint carries it; the water's
  // acceleration is sampled afresh at each step start.
  const std::string scene = coupled_scene() + "added_mass = true\nhistory_force = true\nhistory_window = 0.02\n";
  const std::string uninterrupted = checkpoint_bytes_after(scene, "coupled.toml", 2, 30);
  CHECK(checkpoint_bytes_after(scene, "coupled.toml", 1, 30) == uninterrupted);
  CHECK(resumed_checkpoint_bytes(scene, "coupled.toml", 13, 30) == uninterrupted);
  CHECK(uninterrupted != checkpoint_bytes_after(coupled_scene(), "coupled.toml", 2, 30));  // the forces act
}

TEST_CASE("dilute grains in water with every added coupling force on: threads and a resumed run give the same bytes") {
  // The self-induced correction's build-up (GrainDrag's self_induced_* fields) acts on dilute grains only (voidage
  // above 0.8): a sparse block, so that it does; its state, like the history's, is in grain fields.
  std::string scene = coupled_scene();
  const std::string dense = "spacing = 0.0055";
  REQUIRE(scene.find(dense) != std::string::npos);
  scene.replace(scene.find(dense), dense.size(), "spacing = 0.012");
  const std::string forces = "self_induced_velocity = true\nadded_mass = true\nhistory_force = true\n"
                             "history_window = 0.02\nlubrication = true\n";
  const std::string all_on = scene + forces;
  const World start = initial_world(parse_scene(all_on, "dilute.toml"));
  REQUIRE(start.solids->size() >= 10);
  const std::string uninterrupted = checkpoint_bytes_after(all_on, "dilute.toml", 2, 30);
  CHECK(checkpoint_bytes_after(all_on, "dilute.toml", 1, 30) == uninterrupted);
  CHECK(resumed_checkpoint_bytes(all_on, "dilute.toml", 13, 30) == uninterrupted);
  CHECK(uninterrupted != checkpoint_bytes_after(scene, "dilute.toml", 2, 30));  // the forces act
  // ... and the self-induced correction is among them.
  CHECK(uninterrupted != checkpoint_bytes_after(scene + "added_mass = true\nhistory_force = true\n"
                                                "history_window = 0.02\nlubrication = true\n",
                                                "dilute.toml", 2, 30));
}

namespace {
std::string splash_scene() { return read_scene_text(RIFFLE_SOURCE_DIR "/tests/data/splash_escape.toml"); }

std::size_t removed_after(const std::string& scene_text, int steps) {
  auto simulation = Simulation::from_model(parse_scene(scene_text, "splash.toml"));
  for (int step = 0; step < steps; ++step) simulation->step();
  REQUIRE(simulation->world().step_status.ok());
  return simulation->world().fluid_summary->removed_count();
}
}  // namespace

TEST_CASE("escaped fluid particles removed: one and two threads and a resumed run give byte-identical checkpoints") {
  // tests/data/splash_escape.toml removes droplets from step ~60 on; split the run between removals, so the resumed
  // run starts from a compacted table and removes more after the split.
  constexpr int kSplit = 110, kSteps = 200;
  const std::size_t at_split = removed_after(splash_scene(), kSplit);
  const std::size_t at_end = removed_after(splash_scene(), kSteps);
  MESSAGE("removed: " << at_split << " by step " << kSplit << ", " << at_end << " by step " << kSteps);
  REQUIRE(at_split > 0);
  REQUIRE(at_end > at_split);
  const std::string one = checkpoint_bytes_after(splash_scene(), "splash.toml", 1, kSteps);
  const std::string two = checkpoint_bytes_after(splash_scene(), "splash.toml", 2, kSteps);
  CHECK(one == two);
  CHECK(resumed_checkpoint_bytes(splash_scene(), "splash.toml", kSplit, kSteps) == two);
  // The resumed run has the same particles and the same removed count (derived from the scene's count).
  const auto directory = test::scratch_dir("determinism_splash_count");
  auto first = Simulation::from_model(parse_scene(splash_scene(), "splash.toml"));
  for (int step = 0; step < kSplit; ++step) first->step();
  const std::string path = (directory / "part.ckpt").string();
  write_checkpoint(path, first->checkpoint_data());
  auto resumed = Simulation::from_checkpoint(path);
  CHECK(resumed->world().fluid_summary->removed_count() == first->world().fluid_summary->removed_count());
  CHECK(resumed->world().fluid_summary->initial_fluid_count == first->world().fluid_summary->initial_fluid_count);
  CHECK(resumed->world().fluid->id == first->world().fluid->id);
}
