#include "systems/fluid_number_density.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <stdexcept>

#include "systems/mps_operators.hpp"

namespace riffle {

void compute_number_density(FluidParticles& particles, const FluidNeighbours& neighbours, const WendlandKernel& kernel,
                            double reference_density, double surface_threshold) {
  const std::size_t count = particles.size();
  if (neighbours.particle_count() != count)
    throw std::logic_error("compute_number_density: the neighbour lists were built for " +
                           std::to_string(neighbours.particle_count()) + " particles, not " + std::to_string(count));
  const double threshold = surface_threshold * reference_density;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 512), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      const NeighbourSpan span{neighbours.slots.data() + neighbours.offsets[i],
                               neighbours.slots.data() + neighbours.offsets[i + 1]};
      const double density = number_density(particles.position[i], particles.position, span, kernel);  // numerics 1.1
      particles.number_density[i] = density;
      // numerics 3.4 (beta from the amendments); walls and dummies have no PPE row, so never a Dirichlet node.
      particles.free_surface[i] =
          particles.kind[i] == static_cast<std::int32_t>(FluidKind::kFluid) && density < threshold ? 1 : 0;
    }
  });
}

FluidNumberDensity::FluidNumberDensity(const NumberDensitySettings& settings)
    : kernel_{settings.effective_radius},
      reference_density_(lattice_constants(3, settings.spacing, settings.effective_radius).number_density),
      surface_threshold_(settings.surface_threshold) {}

void FluidNumberDensity::run(SystemContext& context) {
  FluidParticles& particles = context.write<FluidParticles>();
  context.count_items(particles.size());
  compute_number_density(particles, context.read<FluidNeighbours>(), kernel_, reference_density_, surface_threshold_);
}

}  // namespace riffle
