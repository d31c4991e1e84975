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
  const double reach = largest_radius + effective_radius;
  fluid_grid_.build(fluid.position, 0, fluid_count, reach);
  grain_grid_.build(solids.position, 0, solids.size(), reach);

  // Each grain's weight sum over the fluid around it, then each fluid particle gathers its share of every grain's
  // impulse: parallel, and every sum runs in grid order.
  weight_sums_.assign(solids.size(), 0.0);
  for_each_particle(solids.size(), [&](std::size_t grain) {
    if (solids.drag_impulse[grain].isZero(0.0)) return;
    const Vec3 centre = solids.position[grain];
    const WendlandKernel kernel(solids.radius[grain] + effective_radius);
    double sum = 0.0;
    fluid_grid_.for_each_within(fluid.position, centre, kernel.effective_radius,
                                [&](std::uint32_t j) { sum += kernel.weight((fluid.position[j] - centre).norm()); });
    weight_sums_[grain] = sum;
  });
  const double inverse_volume = 1.0 / constants_.particle_volume;
  for_each_particle(fluid_count, [&](std::size_t j) {
    Vec3 received = Vec3::Zero();
    grain_grid_.for_each_within(solids.position, fluid.position[j], reach, [&](std::uint32_t grain) {
      // A grain that left the water since the sampling gives nothing back (its drag was zero while dry).
      if (weight_sums_[grain] <= 0.0) return;
      const double weight =
          WendlandKernel(solids.radius[grain] + effective_radius).weight((fluid.position[j] - solids.position[grain]).norm());
      received -= (weight / weight_sums_[grain]) * solids.drag_impulse[grain];
    });
    fluid.drag_reaction[j] += inverse_volume * received;
  });
  for_each_particle(solids.size(), [&](std::size_t grain) { solids.drag_impulse[grain] = Vec3::Zero(); });
  context.count_items(solids.size());
}

}  // namespace riffle
