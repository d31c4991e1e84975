#include "systems/mps/fluid_wall_motion.hpp"

#include "systems/physics/tank_kinematics.hpp"

namespace riffle {

void FluidWallMotion::run(SystemContext& context) {
  ParticleState& particles = context.write<ParticleState>();
  ParticlePrediction& prediction = context.write<ParticlePrediction>();
  const std::size_t first_wall = fluid_slot_count(particles);
  const TankMotion tank = tank_kinematics(context.model.tank.motion, context.time + context.dt);
  for_each_particle(particles.size() - first_wall, [&](std::size_t k) {
    const std::size_t i = first_wall + k;
    particles.position[i] = particles.rest_position[i] + tank.displacement;
    prediction.predicted_position[i] = particles.position[i];
    particles.velocity[i] = tank.velocity;
  });
  context.count_items(particles.size() - first_wall);
}

}  // namespace riffle
