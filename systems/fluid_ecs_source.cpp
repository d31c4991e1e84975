#include "systems/fluid_ecs_source.hpp"

#include <cmath>

namespace riffle {

void FluidEcsSource::run(SystemContext& context) {
  FluidParticles& particles = context.write<FluidParticles>();
  const FluidNeighbours& neighbours = context.read<FluidNeighbours>();
  const std::size_t fluid_count = fluid_slot_count(particles);
  const WendlandKernel kernel = constants_.kernel;
  const double radius_squared = kernel.effective_radius * kernel.effective_radius;
  const double n0 = constants_.reference_density;
  for_each_particle(fluid_count, [&](std::size_t i) {
    const Vec3 position = particles.position[i];
    const Vec3 velocity = particles.velocity[i];
    double density = 0.0, rate = 0.0;
    for (const std::uint32_t j : neighbours_of(neighbours, i)) {
      const Vec3 offset = particles.position[j] - position;
      const double distance_squared = offset.squaredNorm();
      if (distance_squared >= radius_squared) continue;
      const double distance = std::sqrt(distance_squared);
      density += kernel.weight(distance);
      const double pair_share = particles.kind[j] == kFluidKind ? 1.0 : 2.0;
      rate += pair_share * kernel.derivative_over_distance(distance) * offset.dot(particles.velocity[j] - velocity);
    }
    const double error = (density - n0) / n0;
    particles.density_rate[i] = std::abs(error) * rate + std::abs(rate) * error;
  });
  context.count_items(fluid_count);
}

}  // namespace riffle
