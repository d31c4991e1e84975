// Determinism: identical checkpoint bytes for any thread count and for resumed versus uninterrupted runs.
#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include "engine/checkpoint.hpp"
#include "engine/simulation.hpp"
#include "tests/test_support.hpp"

using namespace riffle;

namespace {
/// A scene large enough that parallel loops really split (several thousand grains).
std::string busy_scene() {
  std::string text = test::small_scene_text(R"(
[[solids.blocks]]
min = [0.01, 0.01, 0.01]
max = [0.23, 0.15, 0.08]
spacing = 0.006
radius = 0.0025
material = "grain"
velocity = [0.3, 0.1, 1.0]
)");
  return text;
}

std::string run_to_bytes(int threads, int steps) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  auto simulation = Simulation::from_model(parse_scene(busy_scene(), "busy.toml"));
  for (int step = 0; step < steps; ++step) simulation->step();
  REQUIRE(simulation->world().step_status.ok());
  return encode_checkpoint(simulation->checkpoint_data());
}
}  // namespace

TEST_CASE("one and two threads give byte-identical checkpoints") {
  const std::string one = run_to_bytes(1, 40);
  const std::string two = run_to_bytes(2, 40);
  CHECK(one.size() == two.size());
  CHECK(one == two);
}

TEST_CASE("resuming from a checkpoint equals the uninterrupted run byte for byte") {
  const auto directory = test::scratch_dir("determinism_resume");
  const std::string uninterrupted = run_to_bytes(2, 60);

  auto first_half = Simulation::from_model(parse_scene(busy_scene(), "busy.toml"));
  for (int step = 0; step < 23; ++step) first_half->step();  // not a multiple of sort_every = 7
  const std::string path = (directory / "half.ckpt").string();
  write_checkpoint(path, first_half->checkpoint_data());
  first_half.reset();

  auto resumed = Simulation::from_checkpoint(path);
  CHECK(resumed->world().step == 23);
  for (int step = 23; step < 60; ++step) resumed->step();
  CHECK(encode_checkpoint(resumed->checkpoint_data()) == uninterrupted);
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
