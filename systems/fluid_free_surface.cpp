#include "systems/fluid_free_surface.hpp"

#include <cmath>

namespace riffle {

void FluidFreeSurface::run(SystemContext& context) {
  FluidParticles& particles = context.write<FluidParticles>();
  const FluidNeighbours& neighbours = context.read<FluidNeighbours>();
  const std::size_t fluid_count = fluid_slot_count(particles);
  const WendlandKernel kernel = constants_.kernel;
  const double radius_squared = kernel.effective_radius * kernel.effective_radius;
  const double surface_below = threshold_ * constants_.reference_density;
  for_each_particle(fluid_count, [&](std::size_t i) {
    const Vec3 position = particles.predicted_position[i];
    double density = 0.0;
    for (const std::uint32_t j : neighbours_of(neighbours, i)) {
      const double distance_squared = (particles.predicted_position[j] - position).squaredNorm();
      if (distance_squared < radius_squared) density += kernel.weight(std::sqrt(distance_squared));
    }
    particles.number_density[i] = density;
    particles.free_surface[i] = density < surface_below ? 1 : 0;
  });
  context.count_items(fluid_count);
}

}  // namespace riffle
