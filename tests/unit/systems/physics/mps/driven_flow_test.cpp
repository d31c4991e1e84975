// Driven flows and the SPS closure (systems/physics/mps/driven_flow.hpp; docs/FLUID.md, "Driven flows", "Turbulence"):
// the body force's laws, the PI controller against a first-order plant with a closed-form answer, the lid's wrap,
// the Smagorinsky viscosity of a linear shear (exact) from the formula and from the engine's MPS gradient on a
// lattice, and the scene keys with their validation.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "engine/scene/scene.hpp"
#include "engine/setup/fluid_layout.hpp"
#include "systems/mps/fluid_neighbours.hpp"
#include "systems/physics/math/counter_random.hpp"
#include "systems/physics/mps/driven_flow.hpp"
#include "tests/support/test_support.hpp"
#include "tests/support/scene_builder.hpp"

using namespace riffle;
using riffle::test::SceneBuilder;

namespace {

bool drive_mentions(const std::vector<std::string>& problems, const std::string& a, const std::string& b) {
  for (const std::string& line : problems)
    if (line.find(a) != std::string::npos && line.find(b) != std::string::npos) return true;
  return false;
}

}  // namespace

TEST_CASE("body force: constant and sinusoidal laws") {
  BodyForceModel model;
  CHECK(prescribed_body_force(model, 1.0) == 0.0);
  model.kind = BodyForceModel::Kind::kConstant;
  model.acceleration = 0.3;
  CHECK(prescribed_body_force(model, 7.0) == 0.3);
  model.kind = BodyForceModel::Kind::kSinusoidal;
  model.acceleration = 2.0;
  model.period = 4.0;
  model.phase = std::numbers::pi / 2.0;
  CHECK(prescribed_body_force(model, 0.0) == doctest::Approx(2.0).epsilon(1e-15));
  CHECK(prescribed_body_force(model, 1.0) == doctest::Approx(0.0).epsilon(1e-15));  // sin(pi) = 0
  CHECK(prescribed_body_force(model, 2.0) == doctest::Approx(-2.0).epsilon(1e-15));
  model.kind = BodyForceModel::Kind::kBulkVelocity;
  CHECK_THROWS(prescribed_body_force(model, 0.0));
}

TEST_CASE("PI gains: the closed loop s^2 + (K_p + 1/tau) s + K_i has the asked omega and zeta") {
  const PiGains gains = pi_gains(2.0, 0.25, 0.7);
  CHECK(gains.integral == doctest::Approx(16.0));
  CHECK(gains.proportional + 0.5 == doctest::Approx(2.0 * 0.7 * 4.0));
  const PiGains inertial = pi_gains(std::numeric_limits<double>::infinity(), 0.5, 1.0);
  CHECK(inertial.proportional == doctest::Approx(4.0));
  CHECK(inertial.integral == doctest::Approx(4.0));
  CHECK(pi_gains(0.01, 1.0, 1.0).proportional == 0.0);  // the plant's own damping exceeds the ask: K_p not below 0
  CHECK_THROWS(pi_gains(1.0, 0.0, 1.0));
}

// The plant dU/dt = f - U / tau, started at rest, with the controller of pi_gains at zeta = 1: the error obeys
// e'' + 2 omega e' + omega^2 e = 0, e(0) = U*, e'(0) = -K_p U*, so e(t) = (U* + B t) exp(-omega t) with
// B = U* (omega - K_p). The discrete loop (the plant by explicit Euler, the controller's rectangle rule) is a
// first-order scheme: at dt = 1e-4 of the response time its error is below 1e-3 U*.
TEST_CASE("PI controller: a first-order plant follows the critically damped answer and holds the target") {
  const double tau = 0.8, response = 0.2, target = 0.5;
  BodyForceModel model;
  model.kind = BodyForceModel::Kind::kBulkVelocity;
  model.target_velocity = target;
  const PiGains gains = pi_gains(tau, response, 1.0);
  model.proportional_gain = gains.proportional;
  model.integral_gain = gains.integral;
  const double omega = 1.0 / response, b = target * (omega - gains.proportional);
  BulkVelocityController controller;
  double velocity = 0.0, worst = 0.0;
  const double dt = 1e-4 * response;
  const auto steps = static_cast<int>(std::lround(3.0 / dt));
  for (int n = 0; n < steps; ++n) {
    const double force = controller.step(model, velocity, dt);
    velocity += dt * (force - velocity / tau);
    const double t = (n + 1) * dt;
    const double error = (target + b * t) * std::exp(-omega * t);
    worst = std::max(worst, std::abs((target - velocity) - error));
  }
  CHECK(worst < 1e-3 * target);
  // Held: at 15 response times the bulk velocity is the target and the force balances the plant's drag U*/tau.
  CHECK(velocity == doctest::Approx(target).epsilon(1e-5));
  CHECK(controller.force == doctest::Approx(target / tau).epsilon(1e-5));
}

TEST_CASE("PI controller: integral action removes the steady error under an unknown constant drag") {
  BodyForceModel model;
  model.kind = BodyForceModel::Kind::kBulkVelocity;
  model.target_velocity = 0.2;
  const PiGains gains = pi_gains(std::numeric_limits<double>::infinity(), 0.1, 1.0);
  model.proportional_gain = gains.proportional;
  model.integral_gain = gains.integral;
  BulkVelocityController controller;
  double velocity = 0.0;
  const double dt = 1e-3, drag = 0.7;  // dU/dt = f - 0.7 (a constant loss the gains do not know)
  for (int n = 0; n < 5000; ++n) velocity += dt * (controller.step(model, velocity, dt) - drag);
  CHECK(velocity == doctest::Approx(0.2).epsilon(1e-9));
  CHECK(controller.force == doctest::Approx(drag).epsilon(1e-9));
}

TEST_CASE("lid particles wrap within their extent: continuous modulo the period, never outside") {
  const double start = 0.1, period = 0.05, velocity = 0.37;
  CHECK(lid_particle_x(0.1025, start, period, velocity, 0.0) == doctest::Approx(0.1025));
  for (int n = 0; n < 1000; ++n) {
    const double t = 0.0137 * n;
    const double x = lid_particle_x(0.1025, start, period, velocity, t);
    CHECK(x >= start);
    CHECK(x < start + period);
    const double unwrapped = 0.1025 + velocity * t;
    const double cycles = (unwrapped - x) / period;
    CHECK(std::abs(cycles - std::round(cycles)) < 1e-9);
  }
  CHECK(lid_particle_x(0.1025, start, period, -velocity, 1.0) >= start);  // backwards too
}

TEST_CASE("Smagorinsky viscosity: a linear shear gives (C_s l0)^2 |a|, a rotation nothing") {
  Eigen::Matrix3d shear = Eigen::Matrix3d::Zero();
  shear(0, 2) = -3.0;  // u = (a z, 0, 0): d u_x / d z = a
  CHECK(strain_rate_magnitude(shear) == doctest::Approx(3.0).epsilon(1e-15));
  CHECK(smagorinsky_viscosity(0.12, 0.002, shear) == doctest::Approx(0.12 * 0.12 * 0.002 * 0.002 * 3.0).epsilon(1e-15));
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Zero();
  rotation(0, 1) = 2.0;
  rotation(1, 0) = -2.0;
  CHECK(strain_rate_magnitude(rotation) == 0.0);
  Eigen::Matrix3d stretch = Eigen::Matrix3d::Zero();  // u = (e x, -e y, 0): 2 S:S = 4 e^2
  stretch(0, 0) = 0.5;
  stretch(1, 1) = -0.5;
  CHECK(strain_rate_magnitude(stretch) == doctest::Approx(1.0).epsilon(1e-15));
}

// The engine's gradient (sps_eddy_viscosity, what fluid_predict runs) on a cubic lattice with u = (a z, 0, 0):
// every particle whose support is full of lattice points reads nu_t = (C_s l0)^2 |a| (the GC gradient is exact for
// a linear field; rounding only).
TEST_CASE("SPS eddy viscosity from the MPS gradient: exact on a lattice in linear shear") {
  const double l0 = 0.002, a = 5.0, constant = 0.12;
  FluidModel fluid;
  fluid.spacing = l0;
  fill_mps_constants(fluid);
  const MpsConstants& constants = mps_constants(fluid);
  ParticleState particles;
  const int n = 11;
  FluidParticles group;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const Vec3 r(i * l0, j * l0, k * l0);
        group.add(r, Vec3(a * r.z(), 0.0, 0.0), FluidKind::kFluid);
      }
  FluidNeighbours neighbours;
  build_fluid_neighbours(group.position, fluid.effective_radius(), neighbours);
  std::vector<double> viscosity;
  particle_eddy_viscosity(group, neighbours, group.size(), constants, {.smagorinsky = constant, .scatter = 0.0},
                          viscosity);
  REQUIRE(viscosity.size() == group.size());
  const double expected = (constant * l0) * (constant * l0) * a;
  const double reach = std::ceil(fluid.effective_radius() / l0) * l0;
  std::size_t interior = 0;
  for (std::size_t i = 0; i < group.size(); ++i) {
    const Vec3& r = group.position[i];
    const bool inside = (r.array() >= reach - 1e-12).all() && (r.array() <= (n - 1) * l0 - reach + 1e-12).all();
    if (!inside) continue;
    ++interior;
    CHECK(viscosity[i] == doctest::Approx(expected).epsilon(1e-10));
  }
  CHECK(interior == 125);  // the 5^3 particles at least 3 l0 inside
}

// The particle-scale viscosity nu_p = C_p l0 s (particle_eddy_viscosity's scatter part): s is the particle's distance
// from the linear field its neighbours and the GC gradient describe. A linear field gives s = 0 on any arrangement
// (the GC gradient is exact for it and sum_j w (L r_ij) - L sum_j w r_ij = 0); on the lattice a lone particle
// kicked by delta reads s = |delta| exactly (its neighbourhood's symmetry leaves its gradient the field's and its
// first moment zero), and the ceiling caps it.
TEST_CASE("particle-scale viscosity: zero for a linear field on a disordered arrangement, C_p l0 |delta| for a kick") {
  const double l0 = 0.002, cp = 2.0;
  FluidModel fluid;
  fluid.spacing = l0;
  fill_mps_constants(fluid);
  const MpsConstants& constants = mps_constants(fluid);
  const Eigen::Matrix3d field = (Eigen::Matrix3d() << 1.0, 2.0, -3.0, 0.5, -1.0, 4.0, 2.0, 0.0, 1.5).finished();
  const int n = 11;
  const double reach = std::ceil(fluid.effective_radius() / l0) * l0;
  const auto interior = [&](const Vec3& site) {
    return (site.array() >= reach - 1e-12).all() && (site.array() <= (n - 1) * l0 - reach + 1e-12).all();
  };
  std::uint64_t draw = 0;
  const auto jitter = [&]() {  // a uniform offset in (-0.2, 0.2) l0
    return (counter_uniform(12345, draw++, 0, 0) - 0.5) * 0.4 * l0;
  };
  FluidParticles disordered, lattice;
  std::vector<Vec3> sites;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const Vec3 site(i * l0, j * l0, k * l0);
        const Vec3 moved = site + Vec3(jitter(), jitter(), jitter());
        disordered.add(moved, field * moved, FluidKind::kFluid);
        lattice.add(site, field * site, FluidKind::kFluid);
        sites.push_back(site);
      }
  const EddyViscosityConstants closures{.smagorinsky = 0.0, .scatter = cp};
  FluidNeighbours neighbours;
  build_fluid_neighbours(disordered.position, fluid.effective_radius(), neighbours);
  std::vector<double> viscosity;
  particle_eddy_viscosity(disordered, neighbours, disordered.size(), constants, closures, viscosity);
  std::size_t checked = 0;
  for (std::size_t i = 0; i < disordered.size(); ++i) {
    if (!interior(sites[i])) continue;
    ++checked;
    CHECK(viscosity[i] < 1e-12 * cp * l0 * field.norm() * l0);  // rounding of a velocity ~ |L| l0
  }
  CHECK(checked == 125);

  // One interior particle of the lattice kicked by delta.
  const std::size_t kicked = (5 * n + 5) * n + 5;
  const Vec3 delta(0.03, -0.01, 0.02);
  lattice.velocity[kicked] += delta;
  build_fluid_neighbours(lattice.position, fluid.effective_radius(), neighbours);
  particle_eddy_viscosity(lattice, neighbours, lattice.size(), constants, closures, viscosity);
  CHECK(viscosity[kicked] == doctest::Approx(cp * l0 * delta.norm()).epsilon(1e-10));
  const std::size_t far = (3 * n + 3) * n + 3;  // 2 sqrt(3) l0 > r_e away from the kick
  CHECK(viscosity[far] < 1e-12 * cp * l0 * field.norm() * l0);
  EddyViscosityConstants capped = closures;
  capped.scatter_ceiling = 0.5 * cp * l0 * delta.norm();
  particle_eddy_viscosity(lattice, neighbours, lattice.size(), constants, capped, viscosity);
  CHECK(viscosity[kicked] == doctest::Approx(capped.scatter_ceiling).epsilon(1e-12));
}

TEST_CASE("scene keys: body force, turbulence and lids read with their defaults") {
  const Model plain = test::fluid_model();
  CHECK(plain.fluid.body_force.kind == BodyForceModel::Kind::kNone);
  CHECK(plain.fluid.turbulence == FluidModel::Turbulence::kNone);
  CHECK_FALSE(plain.fluid.has_lids());
  CHECK_FALSE(plain.fluid.reports_driving());

  std::string text = test::fluid_scene_text(SceneBuilder(SceneBuilder::kSpaced).within("fluid")
      .body_force("sinusoidal").set("amplitude", 0.5).set("period", 2.0).set("phase", 90.0)
      .set("grains", "frame")
      .wall_box({.low = {0.1, -0.01, 0.02}, .high = {0.14, 0.01, 0.03}, .lid = "no_slip", .velocity = 0.25}).toml());
  text.replace(text.find("spacing = 0.005"), 15, "spacing = 0.005\nturbulence = \"sps\"\nsmagorinsky_constant = 0.15");
  const Model model = parse_scene(text, "driven.toml");
  CHECK(model.fluid.body_force.kind == BodyForceModel::Kind::kSinusoidal);
  CHECK(model.fluid.body_force.acceleration == 0.5);
  CHECK(model.fluid.body_force.period == 2.0);
  CHECK(model.fluid.body_force.phase == doctest::Approx(std::numbers::pi / 2.0));
  CHECK(model.fluid.body_force.grains == BodyForceModel::Grains::kFrame);
  CHECK(model.fluid.turbulence == FluidModel::Turbulence::kSps);
  CHECK(model.fluid.smagorinsky_constant == 0.15);
  const ParticleBoxModel& lid = model.fluid.wall_boxes.back();
  CHECK(lid.lid);
  CHECK_FALSE(lid.lid_free_slip);
  CHECK(lid.lid_velocity == 0.25);
  CHECK(lid.lid_period == doctest::Approx(0.04));  // 8 particles along x, l0 apart
  CHECK(lid.lid_start_x == doctest::Approx(0.1));
  CHECK(lid.lid_area == doctest::Approx(0.04 * 0.02));
  CHECK(model.fluid.reports_driving());

  // The controller holds the lab-frame mean velocity: the tank may move, but not along x.
  std::string bulk_text = test::fluid_scene_text(SceneBuilder().within("fluid")
      .body_force("bulk_velocity").set("target_velocity", 0.3).set("response_time", 0.5)
      .set("viscous_time", 2.0)
      .toml());
  CHECK(drive_mentions(test::problems_of(bulk_text), "fluid.body_force.kind", "does not move along x"));
  bulk_text.replace(bulk_text.find("[tank.motion]\n"), 14, "[tank.motion]\ndirection = [0.0, 0.0, 1.0]\n");
  const Model bulk = parse_scene(bulk_text, "bulk.toml");
  CHECK(bulk.fluid.body_force.integral_gain == doctest::Approx(4.0));
  CHECK(bulk.fluid.body_force.proportional_gain == doctest::Approx(4.0 - 0.5));
  CHECK(bulk.fluid.body_force.grains == BodyForceModel::Grains::kPressureGradient);
}

TEST_CASE("scene keys: bad driven-flow input is refused naming the key") {
  auto problems = [](const std::string& extra) { return test::problems_of(test::fluid_scene_text(extra)); };
  CHECK(drive_mentions(problems("\n[fluid.body_force]\nkind = \"pump\"\n"), "fluid.body_force.kind", "pump"));
  CHECK(drive_mentions(problems("\n[fluid.body_force]\nkind = \"constant\"\n"), "fluid.body_force.acceleration", "missing"));
  CHECK(drive_mentions(problems("\n[fluid.body_force]\nkind = \"sinusoidal\"\namplitude = 1.0\nperiod = 0.0\n"),
                 "fluid.body_force.period", ""));
  CHECK(drive_mentions(problems("\n[fluid.body_force]\nkind = \"constant\"\nacceleration = 1e6\n"),
                 "fluid.body_force.acceleration", ""));
  CHECK(drive_mentions(problems("\n[fluid.body_force]\nkind = \"bulk_velocity\"\ntarget_velocity = 0.1\n"
                          "integral_gain = 1.0\nproportional_gain = 1.0\nresponse_time = 1.0\n"),
                 "fluid.body_force.response_time", "not both"));
  CHECK(drive_mentions(problems("\n[fluid.body_force]\nkind = \"constant\"\nacceleration = 1.0\nperiod = 2.0\n"),
                 "fluid.body_force.period", ""));
  CHECK(drive_mentions(problems("\n[[fluid.wall_boxes]]\nlow = [0.1, -0.01, 0.02]\nhigh = [0.14, 0.01, 0.03]\n"
                          "lid = \"free_slip\"\nvelocity = 0.1\n"),
                 "velocity", "free-slip"));
  CHECK(drive_mentions(problems("\n[[fluid.wall_boxes]]\nlow = [0.1, -0.01, 0.02]\nhigh = [0.14, 0.01, 0.03]\n"
                          "lid = \"sticky\"\n"),
                 "lid", "sticky"));
  CHECK(drive_mentions(problems("\n[[fluid.wall_boxes]]\nlow = [0.1, -0.01, 0.02]\nhigh = [0.14, 0.01, 0.03]\n"
                          "velocity = 0.1\n"),
                 "velocity", ""));  // velocity without lid: an unknown key
  std::string text = test::fluid_scene_text();
  text.replace(text.find("spacing = 0.005"), 15, "spacing = 0.005\nsmagorinsky_constant = 0.1");
  CHECK(drive_mentions(test::problems_of(text), "fluid.smagorinsky_constant", "sps"));
  text = test::fluid_scene_text();
  text.replace(text.find("spacing = 0.005"), 15, "spacing = 0.005\nturbulence = \"les\"");
  CHECK(drive_mentions(test::problems_of(text), "fluid.turbulence", "les"));
}
