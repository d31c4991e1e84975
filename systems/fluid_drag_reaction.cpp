#include "systems/fluid_drag_reaction.hpp"

#include <algorithm>

namespace riffle {

void FluidDragReaction::run(SystemContext& context) {
  Solids& solids = context.write<Solids>();
  FluidParticles& fluid = context.write<FluidParticles>();
  const std::size_t fluid_count = fluid_slot_count(fluid);
  const double effective_radius = constants_.kernel.effective_radius;
  double largest_radius = 0.0;
  for (const double radius : solids.radius) largest_radius = std::max(largest_radius, radius);
  fluid_grid_.build(fluid.position, 0, fluid_count, largest_radius + effective_radius);
  const double inverse_volume = 1.0 / constants_.particle_volume;
  for (std::size_t grain = 0; grain < solids.size(); ++grain) {
    const Vec3 impulse = solids.drag_impulse[grain];
    solids.drag_impulse[grain] = Vec3::Zero();
    if (impulse.isZero(0.0)) continue;
    const Vec3 centre = solids.position[grain];
    const WendlandKernel kernel(solids.radius[grain] + effective_radius);
    partners_.clear();
    weights_.clear();
    double weight_sum = 0.0;
    fluid_grid_.for_each_within(fluid.position, centre, kernel.effective_radius, [&](std::uint32_t j) {
      const double weight = kernel.weight((fluid.position[j] - centre).norm());
      if (weight <= 0.0) return;
      partners_.push_back(j);
      weights_.push_back(weight);
      weight_sum += weight;
    });
    // A grain that left the water since the sampling gives nothing back (its drag was zero while dry).
    if (weight_sum <= 0.0) continue;
    for (std::size_t k = 0; k < partners_.size(); ++k)
      fluid.drag_reaction[partners_[k]] -= (weights_[k] / weight_sum * inverse_volume) * impulse;
  }
  context.count_items(solids.size());
}

}  // namespace riffle
