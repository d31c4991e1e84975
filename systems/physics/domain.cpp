#include "systems/physics/domain.hpp"

#include "systems/physics/tank_kinematics.hpp"

namespace riffle {

DomainBox domain_box(const Model& model) {
  const TankModel& tank = model.tank;
  const Vec3 sweep = tank_motion_sweep(tank.motion);
  const Vec3 margin = Vec3::Constant(tank.domain_margin) + sweep;
  return {tank.origin - margin, tank.origin + tank.size + margin};
}

}  // namespace riffle
