#include "systems/mps/fluid_predict.hpp"

#include <cmath>

#include "systems/physics/fluid_pair_batch.hpp"
#include "systems/physics/mps_operators.hpp"

namespace riffle {

void FluidPredict::run(SystemContext& context) {
  ParticleState& particles = context.write<ParticleState>();
  ParticlePrediction& prediction = context.write<ParticlePrediction>();
  ParticleDragReaction& reaction = context.write<ParticleDragReaction>();
  const FluidNeighbours& neighbours = context.read<FluidNeighbours>();
  const std::size_t fluid_count = fluid_slot_count(particles);
  const WendlandKernel kernel = constants_.kernel;
  const double radius_squared = kernel.effective_radius * kernel.effective_radius;
  const double n0 = constants_.reference_density;
  // nu <lap u>_i = nu 2D / (lambda0 n0) sum_j (u_j - u_i) w_ij  (numerics 1.4, D = 3)
  const double viscous_factor =
      fluid_.kinematic_viscosity * 6.0 / (constants_.laplacian_lambda * constants_.reference_density);
  const bool error_compensation = fluid_.schemes.error_compensating_source;
  const Vec3 gravity = context.model.gravity;
  acceleration_.resize(fluid_count);
  for_each_particle(fluid_count, [&](std::size_t i) {
    Vec3 viscous = Vec3::Zero();
    double density = 0.0, rate = 0.0;
    if (viscous_factor > 0.0 || error_compensation) {
      const Vec3 position = particles.position[i];
      const Vec3 velocity = particles.velocity[i];
      FluidPairBatch batch;
      for_each_pair_within(
          neighbours_of(neighbours, i), radius_squared, kernel, batch,
          [&](std::uint32_t j) -> Vec3 { return particles.position[j] - position; },
          [&](const FluidPairBatch& pair, std::size_t k) {
            const std::uint32_t j = pair.slot[k];
            const double weight = pair.weight[k];
            const Vec3 relative_velocity = particles.velocity[j] - velocity;
            viscous += weight * relative_velocity;
            if (error_compensation) {
              density += weight;
              const double derivative_over_distance = kernel.derivative_over_distance(pair.distance[k]);
              rate += density_rate_term(particles.kind[j] == kFluidKind, derivative_over_distance, pair.offset(k),
                                        relative_velocity);
            }
          });
    }
    acceleration_[i] = viscous_factor * viscous + gravity;
    if (error_compensation) {
      const double error = (density - n0) / n0;
      prediction.density_rate[i] = std::abs(error) * rate + std::abs(rate) * error;
    }
  });
  const double dt = context.dt;
  const double inverse_density = 1.0 / fluid_.density;
  for_each_particle(fluid_count, [&](std::size_t i) {
    // The grains' drag from the last step comes back as an impulse per volume (fluid_drag_reaction).
    particles.velocity[i] += dt * acceleration_[i] + inverse_density * reaction.drag_reaction[i];
    reaction.drag_reaction[i] = Vec3::Zero();
    prediction.predicted_position[i] = particles.position[i] + dt * particles.velocity[i];
  });
  context.count_items(fluid_count);
}

}  // namespace riffle
