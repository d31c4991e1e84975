#pragma once
// How long an engine step is and how it is cut into the grains' sub-steps, as the World holds it: plain step data,
// decided by decide_step_lengths (systems/physics/time/time_step.hpp) and printed by the diagnostics.
#include <cstdint>

namespace riffle {

/// What set the step length.
enum class StepLimit : std::uint8_t {
  kRunDt,      ///< run.dt, the largest step
  kCourant,    ///< C_r l0 / max|u| of the fluid
  kDiffusion,  ///< diffusion_number l0^2 / nu of the fluid
  kDrag,       ///< coupling.drag_number / (the fastest rate at which the grains' drag relaxes the water)
  kHydrostatic,  ///< hydrostatic_number sqrt(l0 / |g|) l0 / H of the fluid, H its depth
};

const char* step_limit_name(StepLimit limit);

struct StepLengths {
  double dt = 0.0;             ///< [s] length of the engine step
  std::int64_t substeps = 0;   ///< grains' sub-steps in it, in [1, model.solid_substeps]
  double substep = 0.0;        ///< [s] length of each sub-step: dt / substeps
  StepLimit limit = StepLimit::kRunDt;
  double drag_rate = 0.0;      ///< [1/s] water_drag_rate as the step was decided (0 without grains in the water)
};

}  // namespace riffle
