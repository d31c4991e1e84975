// Verification of the driven flows that need no periodic boundary (docs/FLUID.md, "Driven flows"):
//  - a body force f along x on water at rest in a closed box is a tilt of gravity: the water settles to the
//    hydrostatic field of rho (f, 0, -g), so the pressure gradient along x is rho f and along z -rho g;
//  - a lid sliding at U over a layer of depth h in a long closed box: away from the ends the steady flow is the
//    plane Couette flow with the return flow that a closed box forces (zero net flux through a cross-section):
//    u = U (3 s^2 - 2 s), s = z / h (the lid at s = 1), and the lid's traction on the water is 4 mu U / h.
// The Poiseuille / Couette / Stokes-second-problem sweeps run in a periodic channel: tools/riffle-tools driven-flow-study, and
// their coarsest cases in tests/verification/periodic_fluid_test.cpp.
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "engine/run/simulation.hpp"
#include "engine/scene/scene.hpp"
#include "tests/support/fluid_support.hpp"
#include "tests/support/scene_builder.hpp"

using riffle::test::SceneBuilder;

namespace riffle {
namespace {

using test::kG;

/// Least-squares plane p = c + a x + b z over the particles `use` selects: returns (a, b).
template <class Use>
Eigen::Vector2d pressure_plane(const FluidParticles& fluid, std::size_t count, Use&& use) {
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d right = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < count; ++i) {
    if (!use(i)) continue;
    const Eigen::Vector3d row(1.0, fluid.position[i].x(), fluid.position[i].z());
    normal += row * row.transpose();
    right += row * fluid.pressure[i];
  }
  const Eigen::Vector3d solution = normal.ldlt().solve(right);
  return {solution[1], solution[2]};
}

}  // namespace

// Sizes (CTest time): l0 = 10 mm, a 20 x 4 x 10 l0 block (800 particles) in a 0.2 x 0.04 x 0.15 m open box;
// f = 0.1 g, so the surface tilts by 0.1 (one l0 over the box from the middle to each end). The suddenly applied
// force starts the first sloshing mode (T = 0.53 s); nu = 5e-3 m^2/s damps it (2 nu k^2 = 2.5/s, and the walls'
// boundary layers more), and the plane is fitted to the time mean over t in [1.5, 2.5] s, about two periods, which
// averages what is left. The fit uses the particles at least 2 l0 below the surface and l0 from the walls, where the
// lattice's support is full. On the lattice the tilted hydrostatic field is an exact discrete solution (GC
// reproduces a linear field; the walls' pressure is extrapolated along rho (g + f e_x), fluid_correct), so what is
// left is the start-up oscillation: its amplitude in grad p starts at rho f (the force is switched on at once) and
// the free mode decays at least as exp(-2 nu k^2 t) = exp(-2.5 t), 2.4 % at t = 1.5 s before the time mean lowers it
// further: tolerance 2.5 % of rho f on dp/dx; dp/dz (rho g, ten times larger, the same oscillation) 0.5 %. The
// surface particles stand on a staircase under the tilted plane (p = 0 at their centres, numerics amendment 4), up
// to l0/2 off it with zero mean along x: that moves the fit's constant, not its slope, to first order. Measured
// (-s): dp/dx within 0.02 %, dp/dz within 0.001 %.
TEST_CASE("a body force along x on water at rest in a closed box gives the hydrostatic field of rho (f, 0, -g)") {
  const double l0 = 0.01, length = 0.2, width = 0.04, depth = 0.1;
  Model model = test::fluid_model(Vec3(length, width, 0.15), l0, {ParticleBoxModel{Vec3::Zero(), Vec3(length, width, depth)}});
  model.fluid.kinematic_viscosity = 5.0e-3;
  model.dt = 2.0e-3;
  const double f = 0.1 * kG;
  model.fluid.body_force.kind = BodyForceModel::Kind::kConstant;
  model.fluid.body_force.acceleration = f;
  test::FluidRun run(std::move(model));
  REQUIRE(run.fluid_count() == 800);
  REQUIRE_MESSAGE(run.run_until(1.5), run.diagnosis());
  const double rho = run.model.fluid.density;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  int samples = 0;
  while (run.world.time < 2.5 - 1e-12) {
    REQUIRE_MESSAGE(run.step(), run.diagnosis());
    const FluidParticles& fluid = *run.world.fluid;
    const std::size_t count = run.fluid_count();
    // The surface height above x: depth + (f/g)(x - L/2) (volume conserved, slope f/g).
    mean += pressure_plane(fluid, count, [&](std::size_t i) {
      const Vec3& r = fluid.position[i];
      const double surface = depth + f / kG * (r.x() - 0.5 * length);
      return r.z() < surface - 2.0 * l0 && r.x() > l0 && r.x() < length - l0 && r.z() > l0;
    });
    ++samples;
  }
  mean /= samples;
  MESSAGE("dp/dx = ", mean[0], " Pa/m (rho f = ", rho * f, "), dp/dz = ", mean[1], " Pa/m (-rho g = ", -rho * kG, ")");
  CHECK(std::abs(mean[0] - rho * f) < 0.025 * rho * f);
  CHECK(std::abs(mean[1] + rho * kG) < 0.005 * rho * kG);
  CHECK(run.world.fluid_summary->body_force == f);
}

// The water fills the box: with no free surface the pressure is relative, and the lid's suction at the upstream
// corner needs tension, so negative pressure is not clamped (clamped, a void opens there and its spurious free
// surface shakes the flow). The lids and the floor span the tank's width over the side boxes, so that the water's
// edge particles see the plane their whole support wide (as in a channel periodic in y); the traction is the middle
// lid's force over the area of water under it, 16 l0 by the water's 4 l0.
// The floor is a no-slip lid at rest and the top a no-slip lid at U: both extrapolate the water's velocity across
// their planes (Morris et al. 1997; docs/FLUID.md, "Moving lids"), which the tank's own walls do not do.
// Sizes: l0 = 10 mm, h = 8 l0, the water L = 48 l0 long and 4 l0 wide between free-slip side boxes 3 l0 thick
// (wider than r_e = 2.4 l0, so the tank's no-slip side walls behind them are out of every support: the flow is
// plane, not duct flow). The water's ends are wall boxes 3 l0 thick under the lid; the lid, a no-slip wall box 3 l0
// thick, spans the whole tank over them, so its seams (where its particles wrap, at the tank's end walls) are 3 l0
// from any water: at a seam next to a fixed wall the lid's row opens a gap or crowds (up to l0), which water in
// reach would see as a density hole (a spurious free surface) once per l0 of travel. The lid is cut into three along
// x at the middle third of the water's length: each part wraps within its own extent, all in phase (the parts' faces
// lie on the lattice), so together they are one sliding plane, and the middle part's force is the traction over
// the water's middle third, away from the corners. The no-slip planes lie half a spacing outside the outer particle
// centres (z = 0 and z = h). nu = 2e-3 m^2/s and U = 25 mm/s give Re = U h / nu = 1 (creeping: the closed-box
// profile holds); the start-up's slowest mode decays as exp(-pi^2 nu t / h^2), 1/e in 0.32 s: at t = 1.6 s what is
// left is e^-5 (0.7 %) of it. Measured over the middle third in x (16 l0 from each end of the water: the end
// disturbance decays like exp(-pi x / h), e^-6). Tolerances: the profile, RMS of (u - U (3 s^2 - 2 s)) over U below
// 3 % (the 0.7 % transient and the walls' first-order treatment; measured 0.9 %). The traction 4 mu U / h within
// 15 %: the lid's sum takes the shear at the plane from the linear extrapolation between the plane and fluid
// particles d_i = l0/2 .. r_e away, which reads the slope at about d_i / 2 below the plane; with the profile's
// curvature u'' = 6 U / h^2 that is low by u'' d_i / 2 over u' = 4 U / h, i.e. 0.75 d_i / h: 5 % at d_i = l0/2,
// 22 % at r_e, 9 % at the kernel-weighted mean d_i of about l0 (h = 8 l0). First order in l0: halving l0 halves it
// (tools/riffle-tools driven-flow-study closed_lid, docs/FLUID.md).
TEST_CASE("a lid over a layer in a long closed box: the Couette flow with return flow, and traction 4 mu U / h") {
  const std::string text = SceneBuilder(SceneBuilder::kSpaced)
      .run({.name = "lid", .end_time = 1.6, .dt = 5.0e-3, .gravity = {0.0, 0.0, 0.0}})
      .material("glass", {.density = 2500.0}).tank({.size = {0.54, 0.10, 0.14}, .wall_material = "glass"})
      .fluid({.spacing = 0.01, .kinematic_viscosity = 2.0e-3, .clamp_negative_pressure = false})
      .fluid_box({0.03, 0.03, 0.03}, {0.51, 0.07, 0.11})
      .wall_box({.low = {0.0, 0.0, 0.03}, .high = {0.54, 0.03, 0.11}, .lid = "free_slip"})
      .wall_box({.low = {0.0, 0.07, 0.03}, .high = {0.54, 0.10, 0.11}, .lid = "free_slip"})
      .wall_box({.low = {0.0, 0.03, 0.03}, .high = {0.03, 0.07, 0.11}})
      .wall_box({.low = {0.51, 0.03, 0.03}, .high = {0.54, 0.07, 0.11}})
      .wall_box({.low = {0.0, 0.0, 0.0}, .high = {0.54, 0.10, 0.03}, .lid = "no_slip"})
      .wall_box({.low = {0.0, 0.0, 0.11}, .high = {0.19, 0.10, 0.14}, .lid = "no_slip", .velocity = 0.025})
      .wall_box({.low = {0.19, 0.0, 0.11}, .high = {0.35, 0.10, 0.14}, .lid = "no_slip", .velocity = 0.025})
      .wall_box({.low = {0.35, 0.0, 0.11}, .high = {0.54, 0.10, 0.14}, .lid = "no_slip", .velocity = 0.025}).toml();
  // Gravity off: the layer is closed, gravity would only add a hydrostatic field.
  test::FluidRun run(parse_scene(text, "lid.toml"));
  REQUIRE(run.fluid_count() == 48 * 4 * 8);
  REQUIRE_MESSAGE(run.run_until(1.6), run.diagnosis());
  const double h = 0.08, x_low = 0.03, z_low = 0.03, length = 0.48, speed = 0.025, nu = 2.0e-3;
  const FluidParticles& fluid = *run.world.fluid;
  double squared = 0.0;
  std::size_t used = 0;
  for (std::size_t i = 0; i < run.fluid_count(); ++i) {
    const Vec3& r = fluid.position[i];
    if (std::abs(r.x() - x_low - 0.5 * length) > length / 6.0) continue;
    const double s = (r.z() - z_low) / h;
    const double error = fluid.velocity[i].x() / speed - (3.0 * s * s - 2.0 * s);
    squared += error * error;
    ++used;
  }
  const double rms = std::sqrt(squared / static_cast<double>(used));
  // Lids in scene order: the two free-slip side boxes (no viscous force: 0), the floor, the three thirds of the top.
  REQUIRE(run.world.fluid_summary->lid_force.size() == 6);
  CHECK(run.world.fluid_summary->lid_force[0].norm() == 0.0);
  const double area = 0.16 * 0.04;
  const double traction = run.world.fluid_summary->lid_force[4].x() / area;  // the middle third's lid
  const double expected = 4.0 * run.model.fluid.density * nu * speed / h;
  MESSAGE("profile rms error ", rms, " U over ", used, " particles; traction ", traction, " Pa against 4 mu U / h = ",
          expected, " Pa");
  CHECK(rms < 0.03);
  CHECK(std::abs(traction - expected) < 0.15 * expected);
  CHECK(run.count_outside_tank(0.0) == 0);
}

}  // namespace riffle

namespace riffle {
namespace {

/// A grain (held in place: fixed_to_tank, its forces still computed) 3 cm deep in the middle of water at rest under
/// a body force f = 0.1 g along x in a closed box; `grains` the [fluid.body_force] key.
std::string grain_under_body_force(const std::string& grains) {
  return SceneBuilder().run({.end_time = 1.5, .dt = 2.0e-3, .solid_substeps = 4})
      .material("grain", {.density = 1000.0}).material("glass", {.density = 2500.0})
      .tank({.size = {0.2, 0.04, 0.15}, .open_faces = {"z_max"}, .wall_material = "glass"})
      .solids().set("fixed_to_tank", true).sphere({.position = {0.1, 0.02, 0.05}, .radius = 0.005, .material = "grain"})
      .fluid({.spacing = 0.01, .kinematic_viscosity = 5.0e-3})
      .body_force("constant").set("acceleration", 0.981).set("grains", grains)
      .fluid_box({0.0, 0.0, 0.0}, {0.2, 0.04, 0.1}).toml();
}

}  // namespace

// The imposed gradient and buoyancy are not counted twice (docs/COUPLING.md, "Driven flows and the grains"): in a
// closed box the water at rest under f holds grad p_MPS = rho (f, 0, -g) (the walls' answer to f), so -V grad p_MPS
// gives the grain -V rho f along x, and the imposed mean gradient's +V rho f cancels it: a grain at rest in water
// at rest feels no horizontal pressure force ("pressure_gradient"), while "none" leaves -V rho f. Tolerance 3 % of
// V rho f: the grain samples the kernel mean of the particles' GC gradients, exact for the linear field on the
// lattice, so what is left is the start-up oscillation (2.4 % at 1.5 s, as in the test above). Measured: 0.04 % in
// both readings; the buoyancy within 0.01 %.
TEST_CASE("a grain at rest in water at rest under a body force: the imposed gradient cancels the walls' answer") {
  const double volume = std::numbers::pi / 6.0 * 1e-6, imposed = 1000.0 * 0.981 * volume;
  for (const std::string grains : {"pressure_gradient", "none"}) {
    CAPTURE(grains);
    auto simulation = Simulation::from_model(parse_scene(grain_under_body_force(grains), "grain_body_force.toml"));
    for (int step = 0; step < 750; ++step) simulation->step();
    REQUIRE(simulation->world().step_status.ok());
    const Vec3 force = simulation->world().solids->pressure_force[0];
    MESSAGE(grains, ": pressure force on the grain ", force.transpose(), " N; V rho f = ", imposed, " N");
    const double expected = grains == "none" ? -imposed : 0.0;
    CHECK(std::abs(force.x() - expected) < 0.03 * imposed);
    CHECK(force.z() == doctest::Approx(1000.0 * 9.81 * volume).epsilon(0.02));  // buoyancy, untouched
  }
  // [coupling] viscous_stress: water at rest has no viscous stress, so the grain's V rho <nu lap u> must vanish, to
  // the same start-up tolerance: the stored nu <lap u> must leave out gravity (10 V rho f) and the body force
  // (V rho f), which fluid_predict adds to the same acceleration.
  auto viscous = Simulation::from_model(parse_scene(
      grain_under_body_force("pressure_gradient") + "[coupling]\nviscous_stress = true\n", "grain_viscous.toml"));
  for (int step = 0; step < 750; ++step) viscous->step();
  REQUIRE(viscous->world().step_status.ok());
  const Vec3 viscous_force = viscous->world().solids->viscous_force[0];
  MESSAGE("viscous stress force on the grain in water at rest ", viscous_force.transpose(), " N");
  CHECK(viscous_force.norm() < 0.03 * imposed);
  CHECK(std::abs(viscous->world().solids->pressure_force[0].x()) < 0.03 * imposed);
}

}  // namespace riffle

namespace riffle {

// The controller's wiring in the engine (its law: tests/unit/driven_flow_test.cpp). A closed box has no bulk
// velocity to hold: in a box full of water (no free surface to tilt) the water cannot pass the end walls, its mean
// u_x stays near 0 (below 1e-3 U here: the density relaxation's compressions), and the controller sees the full
// error U at every step. The force
// reported must be exactly K_p (U - U_b) + K_i I with U_b the bulk velocity reported and I the rectangle-rule
// integral of U - U_b (rounding), and so within 3 % of K_p U + K_i U t_n.
TEST_CASE("the bulk-velocity controller in a closed box: the force K_p U + K_i U t, reported each step") {
  Model model = test::fluid_model(Vec3(0.1, 0.04, 0.05), 0.01, {ParticleBoxModel{Vec3::Zero(), Vec3(0.1, 0.04, 0.05)}});
  model.tank.open_faces.clear();
  model.fluid.clamp_negative_pressure = false;  // full box: relative pressure, the downstream end pulls
  model.dt = 2.0e-3;
  BodyForceModel& force = model.fluid.body_force;
  force.kind = BodyForceModel::Kind::kBulkVelocity;
  force.target_velocity = 0.01;
  force.proportional_gain = 2.0;
  force.integral_gain = 1.0;
  test::FluidRun run(std::move(model));
  double integral = 0.0;
  for (int n = 0; n < 25; ++n) {
    const double time = run.world.time;
    REQUIRE_MESSAGE(run.step(), run.diagnosis());
    const FluidSummary& summary = *run.world.fluid_summary;
    const double error = 0.01 - summary.bulk_velocity;
    CHECK(summary.body_force == doctest::Approx(2.0 * error + 1.0 * integral).epsilon(1e-12));
    integral += error * 2.0e-3;
    CHECK(summary.body_force == doctest::Approx(2.0 * 0.01 + 1.0 * 0.01 * time).epsilon(0.03));
    CHECK(std::abs(summary.bulk_velocity) < 1e-3 * 0.01);
  }
}

}  // namespace riffle
