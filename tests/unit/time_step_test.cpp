// decide_step_lengths: the one place that decides the step and its sub-steps (systems/physics/time_step.hpp).
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "systems/physics/time_step.hpp"

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
