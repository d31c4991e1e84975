#pragma once
// Wall motion: the single owner of the tank's state in the world. Moves every wall that follows the tank to the end
// of the (sub)step and gives it the exact velocity (systems/physics/geometry/tank_kinematics.hpp).
#include "systems/system.hpp"

namespace riffle {

class WallMotion final : public System {
 public:
  std::string_view name() const override { return "wall_motion"; }
  Access access() const override { return {{}, component_ids<TankMotion, Walls>()}; }
  void run(SystemContext& context) override;
};

}  // namespace riffle
