#pragma once
// Problems found during a step. Kernels never throw or log: checks write here and the stepper applies the policy
// (stop with a diagnosis, keep the last good checkpoint).
#include <cstdint>
#include <string>

#include "components/component_id.hpp"
#include "components/vec.hpp"

namespace riffle {

enum class StepProblem : std::uint8_t {
  kNone,
  kNonFinite,   ///< a NaN or infinity in a particle's state
  kLeftDomain,  ///< a particle's centre left the domain box
  kSolverFailed,       ///< the pressure solve produced a non-finite residual
  kTimeStepCollapse,   ///< the Courant limit fell below the scene's minimum step (the flow blew up)
  kTooManyEscaped,     ///< more fluid particles removed as escaped than fluid.escape_fraction_limit allows
  kSurfaceWithConservativeGradient,  ///< a free-surface particle under [fluid.schemes] conservative_gradient
};

struct StepStatus {
  static constexpr ComponentId kId = component_id<StepStatus>;
  static constexpr std::string_view kName = "step_status";
  static constexpr bool kPersistent = false;

  StepProblem problem = StepProblem::kNone;
  std::string phase;                ///< "solids", ...
  EntityId entity = 0;              ///< id of the first offending particle (lowest slot, so deterministic)
  Vec3 position = Vec3::Zero();     ///< [m] its position when found
  Vec3 velocity = Vec3::Zero();     ///< [m/s] its velocity when found

  bool ok() const { return problem == StepProblem::kNone; }
  void clear() { *this = StepStatus{}; }
};

}  // namespace riffle
