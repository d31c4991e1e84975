#include "systems/dem/wall_motion.hpp"

#include "systems/physics/geometry/tank_kinematics.hpp"


namespace riffle {

void WallMotion::run(SystemContext& context) {
  TankMotion& tank = context.write<TankMotion>();
  Walls& walls = context.write<Walls>();
  tank = tank_kinematics(context.model.tank.motion, context.time + context.dt);
  apply_tank_motion(tank, walls);
  context.count_items(walls.size());
}

}  // namespace riffle
