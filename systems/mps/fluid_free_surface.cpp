#include "systems/mps/fluid_free_surface.hpp"

#include "systems/physics/mps/fluid_pair_batch.hpp"

namespace riffle {

void FluidFreeSurface::run(SystemContext& context) {
  const ParticleState& particles = context.read<ParticleState>();
  const ParticlePrediction& prediction = context.read<ParticlePrediction>();
  ParticleDensity& densities = context.write<ParticleDensity>();
  FluidNeighbours& neighbours = context.write<FluidNeighbours>();
  neighbours.near_count.resize(neighbours.particle_count());
  neighbours.near_slots.resize(neighbours.slots.size());
  const std::size_t fluid_count = fluid_slot_count(particles);
  const WendlandKernel kernel = kernel_;
  const double radius_squared = kernel.effective_radius * kernel.effective_radius;
  const double surface_below = threshold_ * constants_.reference_density;
  // Slots beyond the reals are a periodic tank's ghosts (fluid_neighbours_predicted exchanged their r*).
  const Ghosted<Vec3> predicted_of =
      fluid_ghosted(prediction.predicted_position, neighbours.ghosts.predicted_position, neighbours);
  for_each_particle(fluid_count, [&](std::size_t i) {
    const Vec3 position = prediction.predicted_position[i];
    double density = 0.0;
    std::uint32_t* near = neighbours.near_slots.data() + neighbours.offsets[i];
    std::uint32_t near_count = 0;
    FluidPairBatch batch;
    for_each_pair_within(
        neighbours_of(neighbours, i), radius_squared, kernel, batch,
        [&](std::uint32_t j) -> Vec3 { return predicted_of[j] - position; },
        [&](const FluidPairBatch& pair, std::size_t k) {
          density += pair.weight[k];
          near[near_count++] = pair.slot[k];
        });
    neighbours.near_count[i] = near_count;
    densities.number_density[i] = density;
    densities.free_surface[i] = density < surface_below ? 1 : 0;
  });
  context.count_items(fluid_count);
}

}  // namespace riffle
