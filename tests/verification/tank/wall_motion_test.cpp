// Prescribed tank motion against its closed form: seed 000 Eq. (1), x = -A sin(2 pi f t), after a C2 ramp.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "engine/setup/initial_state.hpp"
#include "engine/run/simulation.hpp"
#include "systems/physics/geometry/tank_kinematics.hpp"
#include "tests/support/test_support.hpp"

using namespace riffle;

namespace {

TankMotionModel seed_motion(double ramp_time) {
  TankMotionModel motion;
  motion.kind = TankMotionModel::Kind::kSinusoidal;
  motion.direction = Vec3::UnitX();
  motion.amplitude = 0.01;
  motion.frequency = 1.7;
  motion.ramp_time = ramp_time;
  return motion;
}
}  // namespace

TEST_CASE("after the ramp the tank follows x = -A sin(2 pi f t) exactly") {
  const TankMotionModel motion = seed_motion(0.5);
  const double omega = 2.0 * std::numbers::pi * motion.frequency;
  for (double t = 0.5; t < 5.0; t += 0.0137) {
    const TankMotion tank = tank_kinematics(motion, t);
    CHECK(tank.displacement[0] == doctest::Approx(-0.01 * std::sin(omega * t)).epsilon(1e-14));
    CHECK(tank.velocity[0] == doctest::Approx(-0.01 * omega * std::cos(omega * t)).epsilon(1e-14));
    CHECK(tank.acceleration[0] == doctest::Approx(0.01 * omega * omega * std::sin(omega * t)).epsilon(1e-14));
    CHECK(tank.displacement[1] == 0.0);
    CHECK(tank.displacement[2] == 0.0);
  }
  // The peak acceleration is 4 pi^2 f^2 A = 1.141 m/s^2 (numerics.md section 1.5).
  CHECK(4.0 * std::numbers::pi * std::numbers::pi * 1.7 * 1.7 * 0.01 == doctest::Approx(1.141).epsilon(1e-3));
}

TEST_CASE("velocity and acceleration are the exact derivatives, ramp included") {
  // Central differences have error h^2/6 |x'''| and h^2/12 |x''''|. Bound the derivatives by those of
  // A r sin(wt) with |r^(k)| <= 10 / T_r^k (quintic smoothstep): |x'''| <= A (w + 10/T_r)^3, etc.
  const TankMotionModel motion = seed_motion(0.6);
  const double omega = 2.0 * std::numbers::pi * motion.frequency;
  const double rate_bound = omega + 10.0 / motion.ramp_time;
  const double h = 1e-4;
  const double velocity_tolerance = h * h / 6.0 * 0.01 * std::pow(rate_bound, 3) + 1e-10;
  const double acceleration_tolerance = h * h / 12.0 * 0.01 * std::pow(rate_bound, 4) + 1e-6;
  for (double t = h; t < 1.2; t += 0.0093) {
    const double minus = tank_kinematics(motion, t - h).displacement[0];
    const double plus = tank_kinematics(motion, t + h).displacement[0];
    const TankMotion tank = tank_kinematics(motion, t);
    CHECK(std::abs((plus - minus) / (2 * h) - tank.velocity[0]) < velocity_tolerance);
    const double velocity_minus = tank_kinematics(motion, t - h).velocity[0];
    const double velocity_plus = tank_kinematics(motion, t + h).velocity[0];
    CHECK(std::abs((velocity_plus - velocity_minus) / (2 * h) - tank.acceleration[0]) < acceleration_tolerance);
  }
}

TEST_CASE("the start-up ramp is C2: zero motion at t = 0, smooth hand-over at the end") {
  const double ramp_time = 0.5;
  const Ramp start = start_up_ramp(0.0, ramp_time);
  CHECK(start.value == 0.0);
  CHECK(start.rate == 0.0);
  CHECK(start.curvature == 0.0);
  const Ramp end = start_up_ramp(ramp_time * (1.0 - 1e-9), ramp_time);
  CHECK(end.value == doctest::Approx(1.0).epsilon(1e-12));
  CHECK(std::abs(end.rate) < 1e-12);
  CHECK(std::abs(end.curvature) < 1e-6);
  const Ramp middle = start_up_ramp(0.5 * ramp_time, ramp_time);
  CHECK(middle.value == doctest::Approx(0.5));
  CHECK(middle.rate == doctest::Approx(30.0 / 16.0 / ramp_time));
  // The tank starts at rest: no jump in velocity or acceleration when the table switches on.
  const TankMotion tank = tank_kinematics(seed_motion(ramp_time), 0.0);
  CHECK(tank.velocity.norm() == 0.0);
  CHECK(tank.acceleration.norm() == 0.0);
}

TEST_CASE("walls that follow the tank are where the motion says after a run") {
  auto simulation = Simulation::from_model(test::small_model());
  for (int step = 0; step < 37; ++step) simulation->step();
  const World& world = simulation->world();
  const TankMotion expected = tank_kinematics(simulation->model().tank.motion, world.time);
  CHECK(world.tank_motion->displacement[0] == doctest::Approx(expected.displacement[0]).epsilon(1e-12));
  const Walls& walls = *world.walls;
  const Walls rest = tank_walls(simulation->model().tank);
  for (std::size_t wall = 0; wall < walls.size(); ++wall) {
    CHECK((walls.point[wall] - (rest.point[wall] + expected.displacement)).norm() < 1e-15);
    CHECK((walls.velocity[wall] - expected.velocity).norm() < 1e-15);
  }
}

TEST_CASE("a bed fixed to the tank moves rigidly with it, whatever the forces on it") {
  // [solids] fixed_to_tank: every grain takes the tank's displacement over each sub-step and its velocity, exactly
  // (the tank's motion is analytic), and does not fall under gravity or respond to contacts.
  std::string scene = test::small_scene_text();
  scene.replace(scene.find("[solids]"), 8, "[solids]\nfixed_to_tank = true");
  auto simulation = Simulation::from_model(parse_scene(scene, "fixed.toml"));
  const std::vector<Vec3> start = simulation->world().solids->position;
  const std::vector<EntityId> ids = simulation->world().solids->id;
  REQUIRE(start.size() > 1);
  for (int step = 0; step < 37; ++step) simulation->step();
  const World& world = simulation->world();
  REQUIRE(world.step_status.ok());
  const TankMotion expected = tank_kinematics(simulation->model().tank.motion, world.time);
  REQUIRE(expected.displacement.norm() > 1e-4);  // the tank has moved: the check means something
  const Solids& solids = *world.solids;
  for (std::size_t i = 0; i < solids.size(); ++i) {
    CHECK(solids.id[i] == ids[i]);
    // Sums of sub-step displacements: rounding only.
    CHECK((solids.position[i] - (start[i] + expected.displacement)).norm() < 1e-12);
    CHECK((solids.velocity[i] - expected.velocity).norm() < 1e-15);
    CHECK(solids.angular_velocity[i].norm() == 0.0);
  }
}
