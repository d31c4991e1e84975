// Grains in free flight against the analytic trajectory x(t) = x0 + v0 t + g t^2 / 2.
// Velocity Verlet integrates a constant acceleration exactly, so the only error is floating-point rounding:
// about (number of sub-steps) x (machine epsilon) x |x|, i.e. 1000 x 2.2e-16 x 0.2 m = 5e-14 m here.
#include <doctest/doctest.h>

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "engine/output/checkpoint.hpp"
#include "engine/run/simulation.hpp"
#include "tests/test_support.hpp"

using namespace riffle;

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
  const std::string scene = test::small_scene_text(R"(
[[solids.spheres]]
position = [0.2, 0.08, 0.1]
velocity = [5.0, 0.0, 0.0]
radius = 0.005
material = "grain"
)");
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
  return R"(
[run]
end_time = 0.05
dt = 1.0e-3
solid_substeps = 4
[materials.grain]
density = 1318.0
[tank]
size = [0.24, 0.16, 0.20]
wall_material = "grain"
[solids]
)" + hold + R"(
[[solids.spheres]]
position = [0.1, 0.08, 0.15]
velocity = [0.0, 0.0, 0.5]
radius = 0.0025
material = "grain"
[[solids.spheres]]
position = [0.15, 0.08, 0.12]
angular_velocity = [0.0, 3.0, 0.0]
radius = 0.003
material = "grain"
)";
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
