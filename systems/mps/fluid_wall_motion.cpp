#include "systems/mps/fluid_wall_motion.hpp"

#include <algorithm>

#include "systems/physics/mps/driven_flow.hpp"
#include "systems/physics/geometry/tank_kinematics.hpp"

namespace riffle {

void FluidWallMotion::run(SystemContext& context) {
  ParticleState& particles = context.write<ParticleState>();
  ParticlePrediction& prediction = context.write<ParticlePrediction>();
  const std::size_t first_wall = fluid_slot_count(particles);
  const double time = context.time + context.dt;
  const TankMotion tank = tank_kinematics(context.model.tank.motion, time);
  for_each_particle(particles.size() - first_wall, [&](std::size_t k) {
    const std::size_t i = first_wall + k;
    particles.position[i] = particles.rest_position[i] + tank.displacement;
    prediction.predicted_position[i] = particles.position[i];
    particles.velocity[i] = tank.velocity;
  });
  // Moving lids (docs/FLUID.md, "Driven flows"): a lid box's particles slide along x at the lid's velocity and wrap
  // within the box's x extent, an infinite plane that never leaves the tank; set from the time, so no drift builds.
  const std::vector<ParticleBoxModel>& boxes = context.model.fluid.wall_boxes;
  if (context.model.fluid.has_lids()) {
    const double tolerance = 1e-9 * std::max(1.0, context.model.tank.size.maxCoeff());
    for_each_particle(particles.size() - first_wall, [&](std::size_t k) {
      const std::size_t i = first_wall + k;
      const Vec3& rest = particles.rest_position[i];
      for (const ParticleBoxModel& box : boxes) {
        if (!box.lid || box.lid_velocity == 0.0) continue;
        if (!(rest.array() >= box.low.array() - tolerance).all() || !(rest.array() <= box.high.array() + tolerance).all())
          continue;
        particles.position[i].x() =
            lid_particle_x(rest.x(), box.lid_start_x, box.lid_period, box.lid_velocity, time) + tank.displacement.x();
        prediction.predicted_position[i] = particles.position[i];
        particles.velocity[i].x() += box.lid_velocity;
        break;
      }
    });
  }
  context.count_items(particles.size() - first_wall);
}

}  // namespace riffle
