#pragma once
// The fluid's stability limits on the step length (numerics 1.5): the Courant number and the viscous diffusion
// number. The stepper is the one place that combines them with run.dt and the grains' sub-step.
#include "components/model.hpp"
#include "systems/physics/mps_common.hpp"

namespace riffle {

/// Largest step the fluid allows: min(max_dt, C_r l0 / |u|max, diffusion l0^2 / nu).
double fluid_time_step(const FluidModel& fluid, const ParticleState& particles, double max_dt);

}  // namespace riffle
