// Checkpoint format: round trip, and refusal of truncated, corrupted, foreign and wrong-version files.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstring>
#include <iterator>
#include <limits>
#include <type_traits>
#include <filesystem>
#include <fstream>

#include "engine/output/checkpoint.hpp"
#include "engine/run/simulation.hpp"
#include "tests/support/test_support.hpp"

using namespace riffle;

namespace {
CheckpointData sample_checkpoint() {
  auto simulation = Simulation::from_model(test::small_model());
  for (int step = 0; step < 5; ++step) simulation->step();
  CheckpointData data = simulation->checkpoint_data();
  data.output.frame_times = {0.0, 0.01};
  data.output.checkpoints_due = 2;
  data.output.kept_steps = {3, 5};
  return data;
}

/// Every field of the read table `a` equal to the written `b`'s (fields are matched by their place in
/// for_each_field), except a field not checkpointed (FieldInfo::checkpointed), which the read sets to its default.
template <class Component>
void check_same_fields(const Component& a, const Component& b) {
  std::size_t index = 0, compared = 0;
  Component::for_each_field(a, [&](const FieldInfo& info, const auto& field) {
    std::size_t other_index = 0;
    Component::for_each_field(b, [&](const FieldInfo&, const auto& other) {
      if constexpr (std::is_same_v<decltype(field), decltype(other)>)
        if (other_index == index) {
          if (info.checkpointed) {
            CHECK_MESSAGE(field == other, info.name);
          } else {
            using Value = typename std::decay_t<decltype(field)>::value_type;
            CHECK_MESSAGE(field.size() == other.size(), info.name);
            CHECK_MESSAGE(std::count(field.begin(), field.end(), field_default<Value>(info)) ==
                              static_cast<std::ptrdiff_t>(field.size()),
                          info.name);
          }
          ++compared;
        }
      ++other_index;
    });
    ++index;
  });
  CHECK(compared == index);
}
}  // namespace

TEST_CASE("fnv1a64 matches the published test vectors") {
  CHECK(fnv1a64("") == 0xcbf29ce484222325ull);
  CHECK(fnv1a64("a") == 0xaf63dc4c8601ec8cull);
  CHECK(fnv1a64("foobar") == 0x85944171f73967e8ull);
}

TEST_CASE("a checkpoint round trip restores every field") {
  const CheckpointData original = sample_checkpoint();
  const std::string bytes = encode_checkpoint(original);
  const CheckpointData restored = decode_checkpoint(bytes, "memory");
  CHECK(restored.scene_file == original.scene_file);
  CHECK(restored.scene_text == original.scene_text);
  CHECK(restored.world.time == original.world.time);
  CHECK(restored.world.step == original.world.step);
  REQUIRE(restored.world.solids.has_value());
  const Solids& a = *original.world.solids;
  const Solids& b = *restored.world.solids;
  CHECK(b.next_id == a.next_id);
  CHECK(b.id == a.id);
  CHECK(b.position == a.position);
  CHECK(b.velocity == a.velocity);
  CHECK(b.angular_velocity == a.angular_velocity);
  CHECK(b.radius == a.radius);
  CHECK(b.mass == a.mass);
  CHECK(b.force == a.force);
  CHECK(b.size_class == a.size_class);
  REQUIRE(restored.world.walls.has_value());
  CHECK(restored.world.walls->name == original.world.walls->name);
  CHECK(restored.world.walls->point == original.world.walls->point);
  CHECK(restored.world.tank_motion->displacement == original.world.tank_motion->displacement);
  CHECK(restored.output.frame_times == original.output.frame_times);
  CHECK(restored.output.kept_steps == original.output.kept_steps);
  // Encoding is a pure function of the data: the same state gives the same bytes.
  CHECK(encode_checkpoint(restored) == bytes);
}

TEST_CASE("damaged or foreign checkpoints are refused with a clear message") {
  const std::string bytes = encode_checkpoint(sample_checkpoint());
  SUBCASE("truncated") {
    CHECK_THROWS_WITH_AS(decode_checkpoint(bytes.substr(0, bytes.size() - 100), "x.ckpt"),
                         doctest::Contains("x.ckpt: checkpoint is truncated"), CheckpointError);
    CHECK_THROWS_AS(decode_checkpoint(bytes.substr(0, 10), "x.ckpt"), CheckpointError);
  }
  SUBCASE("one bit flipped anywhere in the payload") {
    for (std::size_t offset : {std::size_t{40}, bytes.size() / 2, bytes.size() - 1}) {
      std::string damaged = bytes;
      damaged[offset] = static_cast<char>(damaged[offset] ^ 0x10);
      CHECK_THROWS_WITH_AS(decode_checkpoint(damaged, "x.ckpt"), doctest::Contains("corrupted"), CheckpointError);
    }
  }
  SUBCASE("not a checkpoint") {
    CHECK_THROWS_WITH_AS(decode_checkpoint("[run]\nend_time = 1.0\n", "scene.toml"),
                         doctest::Contains("not a riffle checkpoint"), CheckpointError);
  }
  SUBCASE("another format version") {
    std::string other = bytes;
    const std::uint32_t version = kCheckpointVersion + 1;
    std::memcpy(other.data() + 8, &version, sizeof version);
    const std::string expected = "format version " + std::to_string(kCheckpointVersion + 1);
    CHECK_THROWS_WITH_AS(decode_checkpoint(other, "x.ckpt"), doctest::Contains(expected.c_str()), CheckpointError);
  }
}

TEST_CASE("write_checkpoint writes atomically and read_checkpoint reads it back") {
  const auto directory = test::scratch_dir("checkpoint_io");
  const std::string path = (directory / "a.ckpt").string();
  const CheckpointData data = sample_checkpoint();
  write_checkpoint(path, data);
  CHECK_FALSE(std::filesystem::exists(path + ".tmp"));
  CHECK(encode_checkpoint(read_checkpoint(path)) == encode_checkpoint(data));
  CHECK_THROWS_WITH_AS(read_checkpoint((directory / "missing.ckpt").string()), doctest::Contains("cannot open"),
                       CheckpointError);
  CHECK_THROWS_AS(write_checkpoint((directory / "no_such_dir" / "b.ckpt").string(), data), CheckpointError);
}

TEST_CASE("a checkpoint with a fluid round trips bit for bit and resumes into the same fluid") {
  auto simulation = Simulation::from_model(test::fluid_model());
  for (int step = 0; step < 3; ++step) simulation->step();
  // Give every field values that no default would reproduce, so a field left out of the archive shows.
  FluidParticles& fluid = *simulation->world().fluid;
  for (std::size_t i = 0; i < fluid.size(); ++i) {
    const double x = 1.0 / (3.0 + static_cast<double>(i));
    fluid.position[i] += 1e-3 * Vec3(x, -x, 0.5 * x);  // small: a resumed particle must lie inside the domain
    fluid.velocity[i] = Vec3(x, 2.0 * x, -x);
    fluid.predicted_position[i] = fluid.position[i] + Vec3(1e-3 * x, 0.0, 0.0);
    fluid.density_rate[i] = -x;
    fluid.pressure[i] = 1e3 * x;
    fluid.number_density[i] = 7.0 + x;
    fluid.free_surface[i] = static_cast<std::int32_t>(i % 2);
    fluid.applied_pressure_gradient[i] = Vec3(x, x, x);  // not checkpointed: read back at its default
  }
  FluidSummary& summary = *simulation->world().fluid_summary;
  summary.surface_count = 17;
  summary.kinetic_energy = 1.0 / 3.0;
  summary.solver_iterations = 42;
  summary.solver_residual = 1.0 / 7.0;
  summary.solver_converged = false;
  summary.courant = 1.0 / 9.0;  // after solver_converged, where format 4 stored last_dt

  const CheckpointData original = simulation->checkpoint_data();
  const std::string bytes = encode_checkpoint(original);
  const CheckpointData restored = decode_checkpoint(bytes, "memory");
  REQUIRE(restored.world.fluid.has_value());
  REQUIRE(restored.world.fluid_summary.has_value());
  CHECK_FALSE(restored.world.fluid_neighbours.has_value());  // rebuilt, never stored
  CHECK(restored.world.fluid->next_id == fluid.next_id);
  check_same_fields(*restored.world.fluid, static_cast<const FluidParticles&>(fluid));
  CHECK(restored.world.fluid_summary->fluid_count == summary.fluid_count);
  CHECK(restored.world.fluid_summary->surface_count == 17);
  CHECK(restored.world.fluid_summary->kinetic_energy == 1.0 / 3.0);
  CHECK(restored.world.fluid_summary->solver_residual == 1.0 / 7.0);
  CHECK_FALSE(restored.world.fluid_summary->solver_converged);
  CHECK(restored.world.fluid_summary->courant == 1.0 / 9.0);
  CHECK(encode_checkpoint(restored) == bytes);

  // Resuming puts the stored fluid back and an empty neighbour list beside it.
  const auto directory = test::scratch_dir("checkpoint_fluid");
  const std::string path = (directory / "fluid.ckpt").string();
  write_checkpoint(path, original);
  auto resumed = Simulation::from_checkpoint(path);
  REQUIRE(resumed->world().fluid.has_value());
  CHECK(resumed->world().fluid->position == fluid.position);
  CHECK(resumed->world().fluid->pressure == fluid.pressure);
  CHECK(resumed->world().fluid_summary->solver_iterations == 42);
  REQUIRE(resumed->world().fluid_neighbours.has_value());
  CHECK(resumed->world().fluid_neighbours->particle_count() == 0);
  CHECK(encode_checkpoint(resumed->checkpoint_data()) == bytes);
}

TEST_CASE("a fluid checkpoint whose field lengths disagree is refused, not padded") {
  // FluidParticles::serialize sizes only the fields the file does not hold (applied_pressure_gradient); a stored
  // field shorter than the ids must reach the reader's size check.
  auto simulation = Simulation::from_model(test::fluid_model());
  simulation->step();
  CheckpointData data = simulation->checkpoint_data();
  data.world.fluid->pressure.pop_back();
  const std::string bytes = encode_checkpoint(data);
  CHECK_THROWS_WITH_AS(decode_checkpoint(bytes, "short.ckpt"), doctest::Contains("pressure holds"), CheckpointError);
}

TEST_CASE("checkpoints of a format before 4 or after 15 are refused") {
  CHECK(kCheckpointVersion == 15);
  CHECK(kOldestCheckpointVersionRead == 4);
  for (const std::uint32_t version : {3u, 16u}) {
    std::string bytes = encode_checkpoint(sample_checkpoint());
    std::memcpy(bytes.data() + 8, &version, sizeof version);
    const std::string expected = "x.ckpt: checkpoint format version " + std::to_string(version) +
                                 ", but this riffle reads version 15 (and 4)";
    CHECK_THROWS_WITH_AS(decode_checkpoint(bytes, "x.ckpt"), doctest::Contains(expected.c_str()), CheckpointError);
  }
}

namespace {
std::string file_bytes(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
}

/// A checkpoint's bytes with a new payload: the header's size and checksum made right again.
std::string with_payload(const std::string& bytes, const std::string& payload) {
  std::string out = bytes.substr(0, 32) + payload;
  const std::uint64_t size = payload.size(), checksum = fnv1a64(payload);
  std::memcpy(out.data() + 16, &size, sizeof size);
  std::memcpy(out.data() + 24, &checksum, sizeof checksum);
  return out;
}
}  // namespace

TEST_CASE("a format-4 checkpoint with a fluid loads without its last_dt, resumes, and is written in the current format") {
  // Written by riffle before format 5 (tests/fuzz/make_checkpoint_corpus.sh): FluidSummary held last_dt there.
  const std::string path = RIFFLE_SOURCE_DIR "/tests/fuzz/corpus/checkpoint/v4_tiny_fluid.ckpt";
  const std::string v4 = file_bytes(path);
  std::uint32_t version = 0;
  std::memcpy(&version, v4.data() + 8, sizeof version);
  REQUIRE(version == 4);
  const CheckpointData data = read_checkpoint(path);
  REQUIRE(data.world.fluid_summary.has_value());
  CHECK(data.world.fluid_summary->fluid_count > 0);
  CHECK(data.world.fluid_summary->courant > 0.0);  // read from its own slot, after the skipped one
  const std::string v5 = encode_checkpoint(data);
  std::memcpy(&version, v5.data() + 8, sizeof version);
  CHECK(version == kCheckpointVersion);

  // Everything but the 8 bytes of last_dt is the same: the format-5 payload is the format-4 one without them, and
  // the current one adds the fluid's viscous_acceleration (format 7: a cereal vector of zeros, count and values)
  // at the end of the fluid's table, before the summary.
  const std::size_t added = 8 + data.world.fluid->size() * sizeof(Vec3);
  std::size_t block = 32;
  while (block < v5.size() && v5[block] == v4[block]) ++block;
  REQUIRE(block + added <= v5.size());
  std::uint64_t count = 0;
  std::memcpy(&count, v5.data() + block, sizeof count);
  CHECK(count == data.world.fluid->size());
  CHECK(v5.substr(block + 8, added - 8) == std::string(added - 8, '\0'));
  std::string v5_without = v5.substr(0, block) + v5.substr(block + added);
  // Format 9's mean-flow column, absent: cereal's one-byte flag of an empty optional, between the world's parts and
  // the output state (a vector of frame times, the checkpoints due, a vector of kept steps).
  const std::size_t output_bytes = 8 + 8 * data.output.frame_times.size() + 8 + 8 + 8 * data.output.kept_steps.size();
  const std::size_t flag = v5_without.size() - output_bytes - 1;
  CHECK(v5_without[flag] == 1);
  v5_without.erase(flag, 1);
  // Format 12's removals by reason and the controller's integral: 24 bytes of zeros after the summary's courant,
  // which follows last_dt in the format-4 file. Taken out where the two first differ after that slot.
  std::size_t dt_slot = 32;
  while (dt_slot < v5_without.size() && v5_without[dt_slot] == v4[dt_slot]) ++dt_slot;
  const std::string v4_without_dt = v4.substr(0, dt_slot) + v4.substr(dt_slot + 8);
  std::size_t reasons = dt_slot;
  while (reasons < v5_without.size() && v5_without[reasons] == v4_without_dt[reasons]) ++reasons;
  REQUIRE(reasons + 24 <= v5_without.size());
  v5_without.erase(reasons, 24);
  REQUIRE(v5_without.size() + 8 == v4.size());
  std::size_t slot = 32;
  while (slot < v5_without.size() && v5_without[slot] == v4[slot]) ++slot;
  CHECK(v4.substr(32, slot - 32) + v4.substr(slot + 8) == v5_without.substr(32));
  double skipped = 0.0;  // the riffle that wrote the fixture still stored the step there: the scene's dt
  std::memcpy(&skipped, v4.data() + slot, sizeof skipped);
  REQUIRE(skipped == 1e-3);

  // The skipped slot must still hold a finite number: the bounded reader refuses a malformed file.
  for (const double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    std::string payload = v4.substr(32);
    std::memcpy(payload.data() + (slot - 32), &bad, sizeof bad);
    CHECK_THROWS_WITH_AS(decode_checkpoint(with_payload(v4, payload), "old.ckpt"),
                         doctest::Contains("old.ckpt: checkpoint payload cannot be read: fluid_summary.last_dt"),
                         CheckpointError);
  }
  // A finite value there is any old run's step length: it loads, and is not kept.
  std::string payload = v4.substr(32);
  const double old_dt = 1e-3 / 3.0;
  std::memcpy(payload.data() + (slot - 32), &old_dt, sizeof old_dt);
  CHECK(encode_checkpoint(decode_checkpoint(with_payload(v4, payload), "old.ckpt")) == v5);
  // A format-5 file is not read with the slot (that would shift every later field): the same bytes as format 5 are
  // 8 bytes short of what format 4 needs.
  std::string as_v5 = v4;
  version = 5;
  std::memcpy(as_v5.data() + 8, &version, sizeof version);
  CHECK_THROWS_AS(decode_checkpoint(as_v5, "x.ckpt"), CheckpointError);

  // Resuming from it gives the world it stored, and the next checkpoint is in the current format, its scene's path
  // made absolute.
  auto resumed = Simulation::from_checkpoint(path);
  CHECK(resumed->world().fluid->position == data.world.fluid->position);
  CheckpointData rewritten = resumed->checkpoint_data();
  CHECK(std::filesystem::path(rewritten.scene_file).is_absolute());
  rewritten.scene_file = data.scene_file;
  CHECK(encode_checkpoint(rewritten) == v5);
}

TEST_CASE("a run whose scene names a settled bed relative to itself resumes from another working directory") {
  const std::filesystem::path directory = test::scratch_dir("resume_elsewhere");
  std::filesystem::create_directories(directory / "scenes");
  std::filesystem::create_directories(directory / "elsewhere");
  write_checkpoint((directory / "scenes" / "bed.ckpt").string(), sample_checkpoint());
  {
    std::ofstream scene(directory / "scenes" / "continued.toml");
    scene << SceneBuilder(SceneBuilder::kSpaced)
                 .run({.name = "continued", .end_time = 0.05, .dt = 1.0e-3, .solid_substeps = 4})
                 .material("grain", {.density = 1318.0}).tank({.size = {0.24, 0.16, 0.20}, .wall_material = "grain"})
                 .solids().set("initial_state", "bed.ckpt").toml();
  }
  const std::filesystem::path started_in = std::filesystem::current_path();
  // The run starts in `directory` with the scene's path relative to it, as `riffle run scenes/continued.toml` would.
  std::filesystem::current_path(directory);
  auto run = Simulation::from_scene_file("scenes/continued.toml");
  const std::size_t grains = run->world().solids->size();
  REQUIRE(grains > 0);
  run->step();
  const std::string checkpoint = (directory / "continued.ckpt").string();
  write_checkpoint(checkpoint, run->checkpoint_data());
  run.reset();
  // The resume runs from elsewhere: the checkpoint's scene path must still lead to bed.ckpt.
  std::filesystem::current_path(directory / "elsewhere");
  std::unique_ptr<Simulation> resumed;
  CHECK_NOTHROW(resumed = Simulation::from_checkpoint(checkpoint));
  std::filesystem::current_path(started_in);
  REQUIRE(resumed);
  CHECK(std::filesystem::path(resumed->model().scene_file).is_absolute());
  CHECK(resumed->world().solids->size() == grains);
  resumed->step();
  CHECK(resumed->world().step_status.ok());
}
