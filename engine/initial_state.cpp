#include "engine/initial_state.hpp"

#include <algorithm>

#include "systems/wall_motion.hpp"

namespace riffle {

Walls tank_walls(const TankModel& tank) {
  Walls walls;
  const Vec3 centre = tank.origin + 0.5 * tank.size;
  const Vec3 half = 0.5 * tank.size;
  const char* names[3][2] = {{"x_min", "x_max"}, {"y_min", "y_max"}, {"z_min", "z_max"}};
  for (int axis = 0; axis < 3; ++axis) {
    const int u_axis = (axis + 1) % 3;
    const int v_axis = (axis + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      const std::string name = names[axis][side];
      if (std::find(tank.open_faces.begin(), tank.open_faces.end(), name) != tank.open_faces.end()) continue;
      const double sign = side == 0 ? -1.0 : 1.0;
      Vec3 face_centre = centre;
      face_centre[axis] += sign * half[axis];
      const Vec3 inward = -sign * Vec3::Unit(axis);
      walls.add(name, face_centre, inward, half[u_axis] * Vec3::Unit(u_axis), half[v_axis] * Vec3::Unit(v_axis), true,
                tank.wall_material);
    }
  }
  return walls;
}

World initial_world(const Model& model) {
  World world;
  world.tank_motion = tank_kinematics(model.tank.motion, 0.0);
  world.walls = tank_walls(model.tank);
  apply_tank_motion(*world.tank_motion, *world.walls);
  if (model.solids.enabled) {
    world.solids.emplace();
    world.solid_summary.emplace();
    if (model.contact.enabled) world.contacts.emplace();
    for (const SphereSpec& sphere : model.solids.spheres) {
      const std::size_t slot = world.solids->add(sphere.position, sphere.velocity, sphere.radius,
                                                 model.materials[static_cast<std::size_t>(sphere.material)].density,
                                                 sphere.material, sphere.size_class);
      world.solids->angular_velocity[slot] = sphere.angular_velocity;
    }
  }
  return world;
}

}  // namespace riffle
