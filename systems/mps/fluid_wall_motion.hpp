#pragma once
// Wall and dummy MPS particles follow the tank to t^{k+1}, set analytically from tank_kinematics (the one owner of
// the prescribed motion, systems/physics/geometry/tank_kinematics.hpp) so no drift builds up (numerics 3.3).
#include <vector>

#include "systems/system.hpp"
#include "systems/physics/mps/mps_common.hpp"

namespace riffle {

class FluidWallMotion final : public System {
 public:
  std::string_view name() const override { return "fluid_wall_motion"; }
  Access access() const override { return {{}, component_ids<ParticleState, ParticlePrediction>()}; }
  void run(SystemContext& context) override;
};

}  // namespace riffle
