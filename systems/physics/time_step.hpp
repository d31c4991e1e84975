#pragma once
// The one place that decides how long an engine step is and how it is cut into the grains' sub-steps: run.dt,
// shortened by the fluid's stability limits (numerics 1.5: the Courant number and the viscous diffusion number),
// then split into sub-steps no longer than the scene's solid_dt(). The stepper asks once per step and stores the
// answer in the World; the diagnostics print it.
#include <cstdint>

#include "components/model.hpp"
#include "systems/physics/mps_common.hpp"

namespace riffle {

/// What set the step length.
enum class StepLimit : std::uint8_t {
  kRunDt,      ///< run.dt, the largest step
  kCourant,    ///< C_r l0 / max|u| of the fluid
  kDiffusion,  ///< diffusion_number l0^2 / nu of the fluid
};

const char* step_limit_name(StepLimit limit);

struct StepLengths {
  double dt = 0.0;             ///< [s] length of the engine step
  std::int64_t substeps = 0;   ///< grains' sub-steps in it, in [1, model.solid_substeps]
  double substep = 0.0;        ///< [s] length of each sub-step: dt / substeps
  StepLimit limit = StepLimit::kRunDt;
};

/// The lengths of the next step. `fluid` is the scene's MPS particles (nullptr without a fluid): its largest speed
/// and the viscosity may shorten run.dt. A step below fluid.min_dt is returned as it is; the stepper stops on it.
StepLengths decide_step_lengths(const Model& model, const ParticleState* fluid);

}  // namespace riffle
