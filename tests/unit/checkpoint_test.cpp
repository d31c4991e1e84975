// Checkpoint format: round trip, and refusal of truncated, corrupted, foreign and wrong-version files.
#include <doctest/doctest.h>

#include <cstring>
#include <fstream>

#include "engine/checkpoint.hpp"
#include "engine/simulation.hpp"
#include "tests/test_support.hpp"

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
