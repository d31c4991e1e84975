#include "systems/physics/domain.hpp"

namespace riffle {

DomainBox domain_box(const Model& model) {
  const TankModel& tank = model.tank;
  const Vec3 sweep = tank.motion.kind == TankMotionModel::Kind::kNone
                         ? Vec3::Zero()
                         : Vec3(tank.motion.amplitude * tank.motion.direction.cwiseAbs());
  const Vec3 margin = Vec3::Constant(tank.domain_margin) + sweep;
  return {tank.origin - margin, tank.origin + tank.size + margin};
}

}  // namespace riffle
