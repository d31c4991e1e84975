// Tank motions beyond the seed's sinusoid, run through the engine: a tabulated sinusoid against the analytic one in a
// sloshing tank, a cosine start from rest against its closed form at the walls and the wall particles, and a dam
// break against an obstacle placed off the particle lattice.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "engine/run/simulation.hpp"
#include "engine/scene/motion_table.hpp"
#include "engine/setup/initial_state.hpp"
#include "systems/physics/geometry/tank_kinematics.hpp"
#include "tests/support/fluid_support.hpp"
#include "tests/support/test_support.hpp"

using namespace riffle;

namespace {


/// The sloshing tank of both runs: L = 0.2 m, 6 cm of water at l0 = 1 cm (first mode at 1.70 Hz, linear theory),
/// shaken near resonance by x = -A r(t) sin(2 pi f t), A = 5 mm, f = 1.6 Hz, a one-period ramp.
Model sloshing_model() {
  const double l0 = 0.01;
  Model model = test::fluid_model(Vec3(0.2, 2 * l0, 0.12), l0, {ParticleBoxModel{Vec3::Zero(), Vec3(0.2, 2 * l0, 0.06)}});
  model.tank.motion.kind = TankMotionModel::Kind::kSinusoidal;
  model.tank.motion.amplitude = 0.005;
  model.tank.motion.frequency = 1.6;
  model.tank.motion.ramp_time = 1.0 / 1.6;
  return model;
}

struct Series {
  std::vector<double> time, slosh;  ///< the water's centre of mass along x in the tank frame, from its start
  double work = 0.0;                ///< [J/kg per particle] sum over steps of a_tank . (mean fluid displacement)
};

Series run_sloshing(const Model& model, double until) {
  test::FluidRun run(model);
  Series series;
  auto centre = [&] {
    double sum = 0.0;
    for (std::size_t i = 0; i < run.fluid_count(); ++i) sum += run.world.fluid->position[i].x();
    return sum / static_cast<double>(run.fluid_count()) - run.world.tank_motion->displacement.x();
  };
  const double start = centre();
  double previous_mean = start + run.world.tank_motion->displacement.x();
  while (run.world.time < until - 1e-12) {
    REQUIRE_MESSAGE(run.step(), run.diagnosis());
    series.time.push_back(run.world.time);
    series.slosh.push_back(centre() - start);
    // The tank's forcing work on the water (per unit mass): the wall acceleration times the water's displacement.
    const double mean = series.slosh.back() + start + run.world.tank_motion->displacement.x();
    series.work += run.world.tank_motion->acceleration.x() * (mean - previous_mean);
    previous_mean = mean;
  }
  return series;
}

/// `series` at time t, linearly interpolated.
double at(const Series& series, double t) {
  const auto above = std::lower_bound(series.time.begin(), series.time.end(), t);
  if (above == series.time.begin()) return series.slosh.front();
  if (above == series.time.end()) return series.slosh.back();
  const std::size_t k = static_cast<std::size_t>(above - series.time.begin());
  const double u = (t - series.time[k - 1]) / (series.time[k] - series.time[k - 1]);
  return (1.0 - u) * series.slosh[k - 1] + u * series.slosh[k];
}

}  // namespace

TEST_CASE("a table of the sinusoid at 200 points per period sloshes the water as the analytic motion does") {
  const Model analytic = sloshing_model();
  const TankMotionModel& motion = analytic.tank.motion;
  // The analytic motion (ramp included) sampled at h = T/200 over [0, 1.3 s].
  const double h = 1.0 / (200.0 * motion.frequency), until = 1.25;
  std::string csv = "t,x\n";
  char line[96];
  for (double t = 0.0; t <= until + 4 * h; t += h) {
    std::snprintf(line, sizeof line, "%.17g,%.17g\n", t, tank_kinematics(motion, t).displacement.x());
    csv += line;
  }
  Model tabulated = analytic;
  tabulated.tank.motion = TankMotionModel{};
  tabulated.tank.motion.kind = TankMotionModel::Kind::kTable;
  REQUIRE(parse_motion_table(csv, "sine.csv", tabulated.tank.motion.table) == "");
  // The tables' kinematics: the spline's error bounds (tests/unit/tank_motion_test.cpp) with the ramp's derivatives
  // (|r^(k)| <= 10 / T_r^k): |x''''| <= A (w + 10/T_r)^4 = 5.5e3 m/s^4, so |dx| <= 5/384 h^4 5.5e3 = 7e-9 m and
  // |da| <= 3/8 h^2 5.5e3 = 2.0e-3 m/s^2, against a peak acceleration A w^2 = 0.505 m/s^2.
  const double f4 = motion.amplitude * std::pow(2.0 * std::numbers::pi * motion.frequency + 10.0 / motion.ramp_time, 4);
  double worst_x = 0.0, worst_a = 0.0;
  for (double t = 0.0; t <= until; t += h / 7.0) {
    const TankMotion exact = tank_kinematics(motion, t), table = tank_kinematics(tabulated.tank.motion, t);
    worst_x = std::max(worst_x, std::abs(exact.displacement.x() - table.displacement.x()));
    worst_a = std::max(worst_a, std::abs(exact.acceleration.x() - table.acceleration.x()));
  }
  CHECK(worst_x <= 5.0 / 384.0 * std::pow(h, 4) * f4);
  CHECK(worst_a <= 3.0 / 8.0 * h * h * f4);

  const Series exact = run_sloshing(analytic, until);
  const Series table = run_sloshing(tabulated, until);
  double peak = 0.0, difference = 0.0;
  for (std::size_t k = 0; k < exact.time.size(); ++k) {
    peak = std::max(peak, std::abs(exact.slosh[k]));
    difference = std::max(difference, std::abs(exact.slosh[k] - at(table, exact.time[k])));
  }
  MESSAGE("table vs analytic: kinematics |dx| " << worst_x << " m, |da| " << worst_a << " m/s^2; slosh peak " << peak
                                                << " m, largest difference " << difference << " m; forcing work "
                                                << exact.work << " vs " << table.work);
  REQUIRE(peak > 1e-3);  // the water has sloshed: the comparison means something
  // The forcing differs by |da| / (A w^2) = 4e-3 at most (mostly 1e-4); the response of the water, a linear
  // oscillator near resonance to first order, by as much relative to its peak; 1 % allows the rest (steps of a
  // Courant-limited length that follow the flow and round differently). Measured: 3e-4 of the peak.
  CHECK(difference <= 0.01 * peak);
  CHECK(table.work == doctest::Approx(exact.work).epsilon(0.01));
}

TEST_CASE("a cosine start from rest: walls and wall particles follow x = A cos(w t) exactly") {
  std::string scene = test::fluid_scene_text();
  scene.replace(scene.find("frequency = 1.7"), 15, "frequency = 1.7\nphase = -90");
  auto simulation = Simulation::from_model(parse_scene(scene, "cosine.toml"));
  const Model& model = simulation->model();
  const double a = 0.01, w = 2.0 * std::numbers::pi * 1.7;
  const Walls rest = tank_walls(model.tank);
  const World initial = initial_world(model);
  for (int step = 0; step <= 40; ++step) {
    if (step > 0) simulation->step();
    const World& world = simulation->world();
    REQUIRE(world.step_status.ok());
    const double t = world.time;
    const Vec3 x(a * std::cos(w * t), 0.0, 0.0);
    CHECK((world.tank_motion->displacement - x).norm() < 1e-15);
    CHECK(world.tank_motion->velocity.x() == doctest::Approx(-a * w * std::sin(w * t)).epsilon(1e-12).scale(a * w));
    CHECK(world.tank_motion->acceleration.x() ==
          doctest::Approx(-a * w * w * std::cos(w * t)).epsilon(1e-12).scale(a * w * w));
    for (std::size_t wall = 0; wall < world.walls->size(); ++wall)
      CHECK((world.walls->point[wall] - (rest.point[wall] + x)).norm() < 1e-15);
    const FluidParticles& particles = *world.fluid;
    double worst = 0.0;
    for (std::size_t i = fluid_slot_count(particles); i < particles.size(); ++i)
      worst = std::max(worst, (particles.position[i] - (particles.rest_position[i] + x)).norm());
    CHECK(worst < 1e-15);
    if (step == 0) {  // the water starts in the displaced tank, at rest
      for (std::size_t i = 0; i < fluid_slot_count(particles); ++i)
        CHECK((particles.position[i] - initial.fluid->position[i]).norm() == 0.0);
      CHECK(initial.fluid->position[0].x() - 0.1 == doctest::Approx(0.0025 + a));
    }
  }
}

TEST_CASE("a dam break runs into an obstacle placed off the lattice, which keeps its given extent") {
  // Tank 0.6 x 0.03 x 0.6 m (tall: the jet off the obstacle rises above 0.35 m) at l0 = 1 cm, a 0.12 x 0.24 m column, and a wall box [0.355, 0.395] x [0, 0.045]: its x
  // faces half a spacing off the lattice. Fitted to its extent (4 x 3 x 5 particles, x centred, z on the floor), the
  // particles' cells span exactly [0.355, 0.395] in x; snapped they would span [0.36, 0.39].
  const double l0 = 0.01;
  Model model = test::fluid_model(Vec3(0.6, 3 * l0, 0.6), l0, {ParticleBoxModel{Vec3::Zero(), Vec3(0.12, 3 * l0, 0.24)}});
  ParticleBoxModel obstacle{Vec3(0.355, 0.0, 0.0), Vec3(0.395, 3 * l0, 0.045)};
  obstacle.fit_extent = true;
  model.fluid.wall_boxes.push_back(obstacle);
  test::FluidRun run(model);
  const FluidParticles& particles = *run.world.fluid;
  double low = 1e300, high = -1e300;
  std::size_t obstacle_particles = 0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const Vec3& r = particles.rest_position[i];
    if (particles.kind[i] == static_cast<std::int32_t>(FluidKind::kFluid) || r.z() < 0.0 || r.x() < 0.3 ||
        r.x() > 0.45 || r.y() < 0.0 || r.y() > 3 * l0)
      continue;
    ++obstacle_particles;
    low = std::min(low, r.x() - 0.5 * l0);
    high = std::max(high, r.x() + 0.5 * l0);
  }
  CHECK(obstacle_particles == 4 * 3 * 5);
  CHECK(low == doctest::Approx(0.355).epsilon(1e-12));
  CHECK(high == doctest::Approx(0.395).epsilon(1e-12));

  const std::size_t count = run.fluid_count();
  REQUIRE_MESSAGE(run.run_until(0.35), run.diagnosis());
  CHECK(run.fluid_count() == count);
  CHECK(run.count_outside_tank(0.5 * l0) == 0);
  // The front has reached the obstacle (at x = 0.355 m, 0.24 m from the column: at the shallow-water front speed
  // 2 sqrt(g H) = 3.1 m/s about 0.1 s after release; measured fronts run at about 2/3 of it) and no water sits
  // inside it.
  double front = 0.0;
  std::size_t inside = 0;
  for (std::size_t i = 0; i < run.fluid_count(); ++i) {
    const Vec3& r = particles.position[i];
    front = std::max(front, r.x());
    if (r.x() > 0.355 + 0.5 * l0 && r.x() < 0.395 - 0.5 * l0 && r.z() < 0.045 - 0.5 * l0) ++inside;
  }
  MESSAGE("dam break with an off-lattice obstacle: front at " << front << " m at t = 0.35 s");
  CHECK(front > 0.4);
  CHECK(inside == 0);
}
