// Verification: pressure transducers (engine/output/probes.*, kind "pressure_transducer") on the walls of a tank of
// still water run by the engine, at rest and shaken vertically. Theory: the fluid at rest in the tank's frame has
// p = rho (g - a) . (x - x_s), x_s on the free surface; a disc's mean of a linear field is its value at the centre,
// and a disc across the water line reads the mean of rho g max(0, h) over the disc (half_submerged_mean).
// The discrete scheme puts p = 0 at the centres of the surface particles, l0/2 below the real surface
// (fluid_hydrostatic_test), so its exact answer is the offset line, depth h' = h - l0/2; against it the tolerance is
// rho |g - a| 0.1 l0, the bound numerics 6.2 sets on still water (a particle 0.1 l0 off its lattice site carries
// that much pressure), and against the continuum rho g h it is that plus rho g l0/2.
//
// On an obstacle (a named [[fluid.wall_boxes]] block on the floor, transducers put on its faces by the scene), the
// same theory and tolerance: the block's faces are walls like the tank's, with the water on their outside.
//
// Sizes (CTest time): l0 = 10 mm, a 6 x 4 x 10 block (240 particles), dt = 2 ms, 150 and 375 steps; the obstacle
// case 10 x 4 x 10 less a 3 x 4 x 4 block (352 particles), 150 steps.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "engine/output/probes.hpp"
#include "engine/scene/scene.hpp"
#include "tests/support/fluid_support.hpp"
#include "tests/support/test_support.hpp"

namespace riffle {
namespace {

using test::kG;
using test::kRho;
constexpr double kTransducerSpacing = 0.01;
constexpr double kDepth = 0.10;  // [m] H

using test::half_submerged_mean;

Model still_water_model() {
  Model model = test::fluid_model(Vec3(0.06, 0.04, 0.14), kTransducerSpacing,
                                  {ParticleBoxModel{Vec3::Zero(), Vec3(0.06, 0.04, kDepth)}});
  model.dt = 2.0e-3;
  return model;
}

struct Disc {
  std::string where;
  Vec3 point;        // [m] tank frame, on a wall's inner face
  Vec3 normal;       // out of the water
  double diameter;   // [m]
  double expected;   // [Pa] offset-line theory at rest (per rho |g - a| for the shaken tank: a depth)
};

}  // namespace

TEST_CASE("a transducer in still water reads rho g h, the wetted-area mean across the water line, 0 in air") {
  test::FluidRun run(still_water_model());
  const FluidProbeSettings settings = fluid_probe_settings(run.model);
  const double line = kDepth - 0.5 * kTransducerSpacing;  // the discrete water line (p = 0 at the surface particles)
  const double rho_g = kRho * kG;
  const std::vector<Disc> discs = {
      {"x_min wall, 5 cm deep", Vec3(0.0, 0.02, 0.05), -Vec3::UnitX(), 0.01, rho_g * (line - 0.05)},
      {"y_max wall, 8 cm deep, 2 cm across", Vec3(0.03, 0.04, 0.02), Vec3::UnitY(), 0.02, rho_g * (line - 0.02)},
      {"floor", Vec3(0.03, 0.02, 0.0), -Vec3::UnitZ(), 0.02, rho_g * line},
      {"x_max wall, centred on the water line", Vec3(0.06, 0.02, line), Vec3::UnitX(), 0.02,
       rho_g * half_submerged_mean(0.0, 0.01)},
      {"x_max wall, 4 mm below the water line", Vec3(0.06, 0.02, line - 0.004), Vec3::UnitX(), 0.02,
       rho_g * half_submerged_mean(0.004, 0.01)},
      {"x_min wall, in air", Vec3(0.0, 0.02, 0.125), -Vec3::UnitX(), 0.01, 0.0},
  };
  const TankMotion at_rest = run.world.tank_motion.value_or(TankMotion{});
  // 0.2 s to settle, then every step of the next 0.1 s.
  REQUIRE_MESSAGE(run.run_until(0.2), run.diagnosis());
  std::vector<double> worst(discs.size(), 0.0);
  while (run.world.time < 0.3 - 1e-12) {
    REQUIRE_MESSAGE(run.step(), run.diagnosis());
    for (std::size_t k = 0; k < discs.size(); ++k) {
      const double reading = pressure_transducer_reading(*run.world.fluid, settings, at_rest, discs[k].point,
                                                         discs[k].normal, discs[k].diameter);
      if (discs[k].expected == 0.0) CHECK(reading == 0.0);  // in air: exactly 0, never NaN or negative
      worst[k] = std::max(worst[k], std::abs(reading - discs[k].expected));
    }
  }
  for (std::size_t k = 0; k < discs.size(); ++k) {
    CAPTURE(discs[k].where);
    MESSAGE(discs[k].where << ": expected " << discs[k].expected << " Pa, largest deviation " << worst[k] << " Pa ("
                           << worst[k] / (rho_g * kTransducerSpacing) << " rho g l0)");
    // Offset-line theory within rho g 0.1 l0; across the line also the quadrature's 0.25 % of rho g R.
    CHECK(worst[k] <= rho_g * (0.1 * kTransducerSpacing + 0.0025 * 0.5 * discs[k].diameter));
  }
  // Against the continuum rho g h (h from the real surface, H): the offset line's l0/2 more.
  const double reading = pressure_transducer_reading(*run.world.fluid, settings, at_rest, discs[0].point,
                                                     discs[0].normal, discs[0].diameter);
  CHECK(std::abs(reading - rho_g * (kDepth - 0.05)) <= rho_g * 0.6 * kTransducerSpacing);
}

TEST_CASE("transducers on an obstacle's faces, placed by the scene, read the still water's rho g h") {
  // A block 3 l0 long and 4 l0 high across the tank under 10 cm of water; discs on its upstream and downstream faces
  // and on its top, each face found by the scene from the point.
  const std::string scene = R"(
[run]
name = "obstacle_transducers"
end_time = 0.3
dt = 2.0e-3

[materials.glass]
density = 2500.0

[tank]
size = [0.1, 0.04, 0.14]
open_faces = ["z_max"]
wall_material = "glass"

[fluid]
spacing = 0.01

[[fluid.boxes]]
low = [0.0, 0.0, 0.0]
high = [0.04, 0.04, 0.1]

[[fluid.boxes]]
low = [0.07, 0.0, 0.0]
high = [0.1, 0.04, 0.1]

[[fluid.boxes]]
low = [0.04, 0.0, 0.04]
high = [0.07, 0.04, 0.1]

[[fluid.wall_boxes]]
name = "block"
low = [0.04, 0.0, 0.0]
high = [0.07, 0.04, 0.04]

[output]
vtk_interval = 0.0

[[output.probes]]
kind = "pressure_transducer"
wall_box = "block"
points = [[0.04, 0.02, 0.02], [0.07, 0.02, 0.015], [0.055, 0.02, 0.04]]
diameter = 0.01
)";
  Model model = parse_scene(scene, "obstacle_transducers.toml");
  REQUIRE(model.output.probes.size() == 1);
  const ProbeModel probe = model.output.probes[0];
  REQUIRE(probe.points.size() == 3);
  // Out of the water, into the block.
  CHECK(probe.normals == std::vector<Vec3>{Vec3::UnitX(), -Vec3::UnitX(), -Vec3::UnitZ()});
  test::FluidRun run(std::move(model));
  const FluidProbeSettings settings = fluid_probe_settings(run.model);
  const double line = kDepth - 0.5 * kTransducerSpacing;
  const double rho_g = kRho * kG;
  const std::vector<double> expected = {rho_g * (line - 0.02), rho_g * (line - 0.015), rho_g * (line - 0.04)};
  const std::vector<std::string> where = {"upstream face, 8 cm deep", "downstream face, 8.5 cm deep",
                                          "top, 6 cm deep"};
  const TankMotion at_rest = run.world.tank_motion.value_or(TankMotion{});
  REQUIRE_MESSAGE(run.run_until(0.2), run.diagnosis());
  std::vector<double> worst(expected.size(), 0.0);
  while (run.world.time < 0.3 - 1e-12) {
    REQUIRE_MESSAGE(run.step(), run.diagnosis());
    for (std::size_t k = 0; k < expected.size(); ++k) {
      const double reading = pressure_transducer_reading(*run.world.fluid, settings, at_rest, probe.points[k],
                                                         probe.normals[k], probe.diameter);
      worst[k] = std::max(worst[k], std::abs(reading - expected[k]));
    }
  }
  for (std::size_t k = 0; k < expected.size(); ++k) {
    CAPTURE(where[k]);
    MESSAGE(where[k] << ": expected " << expected[k] << " Pa, largest deviation " << worst[k] << " Pa ("
                     << worst[k] / (rho_g * kTransducerSpacing) << " rho g l0)");
    // Offset-line theory within rho g 0.1 l0, as on the tank's walls.
    CHECK(worst[k] <= rho_g * 0.1 * kTransducerSpacing);
  }
}

TEST_CASE("a transducer in a vertically shaken tank moves with it and reads rho (g - a) h") {
  // x_z = -A sin(2 pi f t) after a C2 ramp of half a period: |a| up to A (2 pi f)^2 = 0.3 g, so the readings swing
  // by 30 %; the tank moves by up to A = 18.6 mm, so a disc that stayed behind would be off by up to rho g A = 183 Pa.
  // The fluid's pressures lag the tank's acceleration by one step (the pressure solved in a step realises the
  // velocity change the walls made in the step before: against a(t - dt) the deviations below fall from 0.06-0.11
  // to 0.03 rho |g - a| l0), a scheme error of rho h' |da/dt| dt, |da/dt| <= A (2 pi f)^3, added to the tolerance.
  Model model = still_water_model();
  const double frequency = 2.0;
  model.tank.motion.kind = TankMotionModel::Kind::kSinusoidal;
  model.tank.motion.direction = Vec3::UnitZ();
  model.tank.motion.frequency = frequency;
  model.tank.motion.amplitude = 0.3 * kG / std::pow(2.0 * std::numbers::pi * frequency, 2);
  model.tank.motion.ramp_time = 0.5 / frequency;
  test::FluidRun run(std::move(model));
  const FluidProbeSettings settings = fluid_probe_settings(run.model);
  const double line = kDepth - 0.5 * kTransducerSpacing;
  const std::vector<Disc> discs = {
      {"x_min wall, 5 cm deep", Vec3(0.0, 0.02, 0.05), -Vec3::UnitX(), 0.01, line - 0.05},
      {"y_min wall, 8 cm deep", Vec3(0.03, 0.0, 0.02), -Vec3::UnitY(), 0.01, line - 0.02},
      {"floor", Vec3(0.03, 0.02, 0.0), -Vec3::UnitZ(), 0.02, line},
      {"x_min wall, in air", Vec3(0.0, 0.02, 0.125), -Vec3::UnitX(), 0.01, 0.0},
  };
  const double jerk = run.model.tank.motion.amplitude * std::pow(2.0 * std::numbers::pi * frequency, 3);  // [m/s^3] max |da/dt|
  std::vector<double> worst(discs.size(), 0.0);
  double largest_acceleration = 0.0, largest_displacement = 0.0;
  while (run.world.time < 0.25 + 1.0 / frequency - 1e-12) {
    REQUIRE_MESSAGE(run.step(), run.diagnosis());
    REQUIRE(run.world.tank_motion);
    const TankMotion& tank = *run.world.tank_motion;
    const double body = kG + tank.acceleration.z();  // |g - a| for a vertical a (up positive)
    if (run.world.time < 0.25) continue;             // the ramp and the first quarter period: settle
    largest_acceleration = std::max(largest_acceleration, std::abs(tank.acceleration.z()));
    largest_displacement = std::max(largest_displacement, std::abs(tank.displacement.z()));
    for (std::size_t k = 0; k < discs.size(); ++k) {
      const double reading = pressure_transducer_reading(*run.world.fluid, settings, tank, discs[k].point,
                                                         discs[k].normal, discs[k].diameter);
      if (discs[k].expected == 0.0) CHECK(reading == 0.0);
      // Relative to the tolerance: rho |g - a| 0.1 l0 (still water) + rho h' |da/dt| dt (the one-step lag).
      const double tolerance = kRho * (body * 0.1 * kTransducerSpacing + discs[k].expected * jerk * run.model.dt);
      worst[k] = std::max(worst[k], std::abs(reading - kRho * body * discs[k].expected) / tolerance);
    }
  }
  MESSAGE("largest tank acceleration " << largest_acceleration / kG << " g, displacement " << largest_displacement
                                       << " m");
  CHECK(largest_acceleration > 0.29 * kG);
  for (std::size_t k = 0; k < discs.size(); ++k) {
    CAPTURE(discs[k].where);
    MESSAGE(discs[k].where << ": largest deviation from rho (g - a) h' " << worst[k] << " of the tolerance");
    CHECK(worst[k] <= 1.0);
  }
}

}  // namespace riffle
