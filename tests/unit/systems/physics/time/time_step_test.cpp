// decide_step_lengths: the one place that decides the step and its sub-steps (systems/physics/time/time_step.hpp).
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "systems/physics/time/time_step.hpp"

using namespace riffle;

namespace {

/// run.dt = 1 ms in 40 sub-steps; water at l0 = 1 cm, C_r = 0.2, diffusion number 0.2, nu = 1e-6 (20 s: never binds).
Model step_model() {
  Model model;
  model.dt = 1.0e-3;
  model.solid_substeps = 40;
  model.fluid.enabled = true;
  model.fluid.spacing = 0.01;
  model.fluid.courant = 0.2;
  model.fluid.diffusion_number = 0.2;
  model.fluid.kinematic_viscosity = 1.0e-6;
  return model;
}

/// Two fluid particles (speeds `fast` and 0.1 m/s) and a wall particle faster than both: walls never limit.
FluidParticles water(double fast) {
  FluidParticles particles;
  particles.kind = {0, 0, 1};
  particles.velocity = {Vec3(0.0, fast, 0.0), Vec3(0.1, 0.0, 0.0), Vec3(0.0, 0.0, 1.0e3)};
  // One layer of water (depth l0: the hydrostatic limit, 2 sqrt(l0 / g) = 64 ms, never binds) above a deep wall.
  particles.position = {Vec3(0.0, 0.0, 0.5), Vec3(0.1, 0.0, 0.5), Vec3(0.0, 0.0, -10.0)};
  return particles;
}

}  // namespace

TEST_CASE("without a fluid the step is run.dt in solid_substeps sub-steps") {
  const Model model = step_model();
  const StepLengths lengths = decide_step_lengths(model, nullptr);
  CHECK(lengths.dt == model.dt);
  CHECK(lengths.substeps == 40);
  CHECK(lengths.substep == model.solid_dt());
  CHECK(lengths.limit == StepLimit::kRunDt);
  CHECK(std::string(step_limit_name(lengths.limit)) == "run.dt");
}

TEST_CASE("slow water leaves run.dt") {
  const Model model = step_model();
  const FluidParticles particles = water(1.0);  // C_r l0 / |u| = 2 ms > 1 ms
  const StepLengths lengths = decide_step_lengths(model, &particles);
  CHECK(lengths.dt == model.dt);
  CHECK(lengths.substeps == 40);
  CHECK(lengths.limit == StepLimit::kRunDt);
}

TEST_CASE("fast water limits the step by its Courant number, and the sub-steps stay no longer than solid_dt") {
  const Model model = step_model();
  const FluidParticles particles = water(4.0);  // C_r l0 / |u| = 0.2 * 0.01 / 4 = 0.5 ms
  const StepLengths lengths = decide_step_lengths(model, &particles);
  CHECK(lengths.dt == 0.2 * 0.01 / 4.0);
  CHECK(lengths.limit == StepLimit::kCourant);
  CHECK(lengths.substeps == 20);  // 0.5 ms / 25 us
  CHECK(lengths.substep == lengths.dt / 20.0);
  CHECK(lengths.substep <= model.solid_dt());
}

TEST_CASE("viscous water limits the step by its diffusion number") {
  Model model = step_model();
  model.fluid.kinematic_viscosity = 0.1;  // 0.2 l0^2 / nu = 0.2 ms
  const FluidParticles particles = water(1.0);
  const StepLengths lengths = decide_step_lengths(model, &particles);
  CHECK(lengths.dt == 0.2 * 0.01 * 0.01 / 0.1);
  CHECK(lengths.limit == StepLimit::kDiffusion);
  CHECK(lengths.substeps == 8);  // ceil(0.2 ms / 25 us)
  SUBCASE("the shorter limit wins") {
    const FluidParticles faster = water(20.0);  // Courant: 0.1 ms
    const StepLengths both = decide_step_lengths(model, &faster);
    CHECK(both.dt == 0.2 * 0.01 / 20.0);
    CHECK(both.limit == StepLimit::kCourant);
  }
}

TEST_CASE("deep water limits the step by its hydrostatic number, its depth along gravity from its particles") {
  Model model = step_model();
  model.gravity = Vec3(0.0, 0.0, -9.81);
  // A column 0.99 m tall (centres) of particles l0 = 1 cm apart: H = 1 m, 2 sqrt(l0 / g) l0 / H = 0.639 ms.
  FluidParticles particles = water(1.0);
  particles.position[1] = Vec3(0.1, 0.0, 1.49);
  const double expected = 2.0 * std::sqrt(0.01 / 9.81) * 0.01 / 1.0;
  const StepLengths lengths = decide_step_lengths(model, &particles);
  CHECK(lengths.dt == doctest::Approx(expected).epsilon(1e-12));
  CHECK(lengths.limit == StepLimit::kHydrostatic);
  CHECK(std::string(step_limit_name(lengths.limit)) == "hydrostatic");
  // The wall particle 10 m down is not water; the extent is along gravity, whichever way it points.
  const WaterExtent extent = water_extent(particles, model.gravity);
  CHECK(extent.high - extent.low == doctest::Approx(0.99).epsilon(1e-12));
  CHECK(water_extent(particles, Vec3(9.81, 0.0, 0.0)).high - water_extent(particles, Vec3(9.81, 0.0, 0.0)).low ==
        doctest::Approx(0.1).epsilon(1e-12));
  SUBCASE("without gravity, or without water, no depth and no limit") {
    model.gravity = Vec3::Zero();
    CHECK(decide_step_lengths(model, &particles).limit == StepLimit::kRunDt);
    CHECK(water_depth(water_extent(particles, model.gravity), 0.01) == 0.0);
    CHECK(water_depth(water_extent(FluidParticles{}, Vec3(0.0, 0.0, -9.81)), 0.01) == 0.0);
  }
  SUBCASE("the key scales it") {
    model.fluid.hydrostatic_number = 5.0;  // 1.6 ms > run.dt
    CHECK(decide_step_lengths(model, &particles).limit == StepLimit::kRunDt);
  }
}

TEST_CASE("the sub-step count is clamped to [1, solid_substeps]") {
  const Model model = step_model();
  SUBCASE("a step just below run.dt keeps solid_substeps sub-steps") {
    const FluidParticles particles = water(2.0 * 1.0001);  // dt = 0.9999 ms: ceil(39.996) = 40
    const StepLengths lengths = decide_step_lengths(model, &particles);
    CHECK(lengths.dt < model.dt);
    CHECK(lengths.substeps == 40);
  }
  SUBCASE("a step shorter than one sub-step is one sub-step") {
    const FluidParticles particles = water(1.0e3);  // dt = 2 us < 25 us
    const StepLengths lengths = decide_step_lengths(model, &particles);
    CHECK(lengths.substeps == 1);
    CHECK(lengths.substep == lengths.dt);
  }
  SUBCASE("an infinite speed gives a zero step, still one sub-step (the stepper stops on fluid.min_dt)") {
    const FluidParticles particles = water(std::numeric_limits<double>::infinity());
    const StepLengths lengths = decide_step_lengths(model, &particles);
    CHECK(lengths.dt == 0.0);
    CHECK(lengths.substeps == 1);
  }
  SUBCASE("a multiple of solid_dt is cut exactly, not into one more sub-step") {
    const FluidParticles particles = water(8.0);  // dt = 0.25 ms = 10 sub-steps of 25 us
    const StepLengths lengths = decide_step_lengths(model, &particles);
    CHECK(lengths.substeps == 10);
  }
}

namespace {

/// Two grains of 2 mm at voidage 0.4 in water of nu = 1e-4 m^2/s, both at rest in water at rest (slip 0: Ergun's
/// viscous term alone); the second is dry (no fluid sampled), so it cannot set the rate whatever its voidage.
Solids two_grains() {
  Solids grains;
  resize_fields(grains, 2);
  grains.radius = {1.0e-3, 1.0e-4};
  grains.voidage = {0.4, 0.3};
  grains.fluid_weight = {1.0, 0.0};
  return grains;
}

Model drag_model(bool mixture) {
  Model model = step_model();
  model.fluid.density = 1000.0;
  model.fluid.kinematic_viscosity = 1.0e-4;
  model.coupling.enabled = true;
  model.coupling.fluid_velocity = mixture ? CouplingModel::FluidVelocity::kMixture : CouplingModel::FluidVelocity::kPore;
  return model;
}

}  // namespace

TEST_CASE("the grains' drag limits the step by the water's relaxation rate under it") {
  // Ergun at slip 0: beta = 150 (1 - eps)^2 mu / (eps d^2), the drag per grain volume k = beta / (1 - eps). Per
  // volume of water (1 - eps) / V grains each pull with dF/du = k V / s, and the water takes it over s_w: the rate is
  // k (1 - eps) / (rho s s_w) = 150 (1 - eps)^2 nu / (eps d^2 s s_w), s = s_w = eps in the mixture reading, 1 in the pore.
  const double eps = 0.4, d = 2.0e-3, nu = 1.0e-4;
  const double pore_rate = 150.0 * (1.0 - eps) * (1.0 - eps) * nu / (eps * d * d);  // 3375 1/s
  const Solids grains = two_grains();
  SUBCASE("the pore reading") {
    const Model model = drag_model(false);
    CHECK(water_drag_rate(model, grains, grains, grains, grains) == doctest::Approx(pore_rate).epsilon(1e-12));
  }
  SUBCASE("the mixture reading: the slip and the water's share both over eps") {
    Model model = drag_model(true);
    const double rate = water_drag_rate(model, grains, grains, grains, grains);
    CHECK(rate == doctest::Approx(pore_rate / (eps * eps)).epsilon(1e-12));  // 21,094 1/s
    const FluidParticles slow = water(0.1);
    const StepLengths lengths = decide_step_lengths(model, &slow, rate);
    CHECK(lengths.dt == doctest::Approx(0.5 / rate).epsilon(1e-15));  // drag_number 0.5: 24 us, below run.dt's 1 ms
    CHECK(lengths.limit == StepLimit::kDrag);
    CHECK(std::string(step_limit_name(lengths.limit)) == "drag");
    CHECK(lengths.substeps == 1);  // 24 us < 25 us
    model.coupling.drag_number = 0.0;  // no limit
    CHECK(decide_step_lengths(model, &slow, rate).limit == StepLimit::kRunDt);
  }
  SUBCASE("a slip adds Ergun's inertial term: the rate grows") {
    Solids sliding = two_grains();
    sliding.fluid_velocity[0] = Vec3(0.01, 0.0, 0.0);
    const Model model = drag_model(true);
    CHECK(water_drag_rate(model, sliding, sliding, sliding, sliding) >
          water_drag_rate(model, grains, grains, grains, grains) * 1.001);
  }
  SUBCASE("without the drag, no limit") {
    Model model = drag_model(true);
    model.coupling.drag = false;
    CHECK(water_drag_rate(model, grains, grains, grains, grains) == 0.0);
  }
}
