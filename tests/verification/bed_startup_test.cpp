// Seed 003's start-up in embryo (docs/SCENES.md, "The start-up"): a bed settled dry, put under water and a lid at
// rest, held for a while and released, must not move: no grain faster than the seed's 0.01 m/s threshold of a
// "moving" grain (seed 003 Sec. 5, its Eq. 29) at any step after the release. This is issue 24's "a settled bed
// under a lid too slow to move it: no grain moves" with the lid at rest; the seed's large (2 mm) grains in the
// seed's own 2 cm x 2 cm plan (273 grains, a closed box), so it runs in seconds.
#include <doctest/doctest.h>

#include <algorithm>
#include <string>

#include "engine/output/checkpoint.hpp"
#include "engine/run/simulation.hpp"
#include "tests/test_support.hpp"

using namespace riffle;

namespace {
/// The sheared-bed scenes' materials, contact law and a 2 cm x 2 cm box 2.75 cm high.
const std::string kCommon = R"(
[materials.grain]
density = 2650.0
young_modulus = 1.0e7
poisson_ratio = 0.3
[contact]
law = "hertz_mindlin"
restitution = 0.5
friction = 0.5
rolling_friction = 0.05
max_impact_speed = 1.0
[tank]
size = [0.02, 0.02, 0.0275]
wall_material = "grain"
)";

double max_grain_speed(const Solids& grains) {
  double fastest = 0.0;
  for (const Vec3& velocity : grains.velocity) fastest = std::max(fastest, velocity.norm());
  return fastest;
}
}  // namespace

TEST_CASE("a bed settled dry, held under water and a lid at rest, then released: no grain moves") {
  const std::string dry = R"(
[run]
end_time = 0.3
dt = 5.0e-4
)" + kCommon + R"(
[solids]
[[solids.layered_beds]]
layers = 3
layer_thickness = 0.002
loose_factor = 2.0
seed = 1
[[solids.layered_beds.classes]]
diameter = 0.002
count = 273
material = "grain"
)";
  auto settle = Simulation::from_model(parse_scene(dry, "settle.toml"));
  while (settle->world().time < 0.3 - 1e-9) settle->step();
  REQUIRE(settle->world().step_status.ok());
  const double settled_speed = max_grain_speed(*settle->world().solids);
  CHECK(settled_speed < 0.01);  // at rest dry after 0.3 s (the scenes settle 0.5 s)
  const auto directory = test::scratch_dir("bed_startup");
  const std::string bed = (directory / "settled.ckpt").string();
  write_checkpoint(bed, settle->checkpoint_data());
  settle.reset();

  const std::string wet = R"(
[run]
end_time = 0.25
dt = 5.0e-4
)" + kCommon + R"(
[solids]
initial_state = ")" + bed + R"("
hold_until = 0.05
[fluid]
spacing = 0.0025
clamp_negative_pressure = false
turbulence = "sps"
smagorinsky_constant = 0.15
[[fluid.boxes]]
low = [0.0, 0.0, 0.0]
high = [0.02, 0.02, 0.02]
[[fluid.wall_boxes]]
low = [0.0, 0.0, 0.02]
high = [0.02, 0.02, 0.0275]
lid = "no_slip"
velocity = 0.0
[coupling]
fluid_velocity = "mixture"
)";
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
