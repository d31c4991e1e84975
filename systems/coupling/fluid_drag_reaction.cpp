#include "systems/coupling/fluid_drag_reaction.hpp"

#include <algorithm>
#include <array>

#include "systems/physics/domain.hpp"
#include "systems/physics/mps_kernel.hpp"
#include "systems/physics/periodic_box.hpp"
#include "systems/coupling/solid_drag.hpp"

namespace riffle {

void FluidDragReaction::run(SystemContext& context) {
  const GrainState& grains = context.read<GrainState>();
  const GrainProperties& properties = context.read<GrainProperties>();
  const GrainVoidage& voidages = context.read<GrainVoidage>();
  GrainDrag& drag = context.write<GrainDrag>();
  const ParticleState& particles = context.read<ParticleState>();
  ParticleDragReaction& reaction = context.write<ParticleDragReaction>();
  const std::size_t fluid_count = fluid_slot_count(particles);
  double largest_radius = 0.0;
  for (const double radius : properties.radius) largest_radius = std::max(largest_radius, radius);
  // Cells of (2 pi / 21)^(1/3) (r + r_e): one cell holds the volume of the Wendland kernel on R_I (seed Eq. 26's
  // influence domain), so the impulse spreads over the same volume, at a cost linear in the particle counts.
  // With the self-induced correction the dilute grains (those it applies to) spread with their sampling kernel;
  // the grains of a bed keep the grid, whose cost does not grow with the kernel's neighbour count.
  if (self_induced_velocity_) spread_with_sampling_kernel(context, largest_radius);
  const double cell_size = 0.668 * (largest_radius + constants_.kernel.effective_radius);
  volumes_.assign(grains.size(), 0.0);
  const DomainBox domain = domain_box(context.model);
  // A periodic box: the grid wraps along its periodic axes (whole cells per period), so a grain's stencil by the
  // seam reaches the nodes, and through them the fluid particles, on the other side.
  grid_.build(grains.position, volumes_, particles.position, fluid_count, constants_.particle_volume, cell_size,
              domain.low, domain.high, periodic_box(context.model));

  // Impulses to the nodes (slot order), then each fluid particle takes its weight's share of its nodes' impulse:
  // sum_j w_jn / W_n = 1 at every node with water, so the water receives exactly minus the grains' impulse.
  node_impulse_.assign(grid_.node_count(), Vec3::Zero());
  for (std::size_t grain = 0; grain < grains.size(); ++grain) {
    if (drag.drag_impulse[grain].isZero(0.0)) continue;  // also the dilute grains the kernel spreading took
    const CloudInCellStencil stencil = grid_.stencil(grains.position[grain]);
    double wet = 0.0;  // weight of the nodes that hold water: a grain at the water's edge gives all to those
    for (std::size_t c = 0; c < 8; ++c) wet += grid_.fluid_volume(stencil.node[c]) > 0.0 ? stencil.weight[c] : 0.0;
    if (wet <= 0.0) continue;  // out of the water since the sampling: its drag was zero while dry
    // Mixture reading: the pore water's relative momentum balance, divided by eps, has -grad p + rho g and the
    // drag per volume over eps (docs/COUPLING.md).
    const double share = mixture_velocity_ ? 1.0 / (wet * voidages.voidage[grain]) : 1.0 / wet;
    for (std::size_t c = 0; c < 8; ++c)
      if (grid_.fluid_volume(stencil.node[c]) > 0.0)
        node_impulse_[stencil.node[c]] -= (stencil.weight[c] * share) * drag.drag_impulse[grain];
    drag.drag_impulse[grain] = Vec3::Zero();
  }
  for_each_particle(fluid_count, [&](std::size_t j) {
    const CloudInCellStencil stencil = grid_.stencil(particles.position[j]);
    Vec3 received = Vec3::Zero();
    // fluid_volume(n) = l0^3 sum_k w_kn, so this particle's share of node n is l0^3 w_jn / fluid_volume(n); per
    // volume l0^3, that is w_jn / fluid_volume(n).
    for (std::size_t c = 0; c < 8; ++c)
      if (stencil.weight[c] > 0.0) received += (stencil.weight[c] / grid_.fluid_volume(stencil.node[c])) * node_impulse_[stencil.node[c]];
    reaction.drag_reaction[j] += received;
  });
  context.count_items(grains.size());
}

// With the self-induced correction (docs/COUPLING.md, "The undisturbed fluid velocity"), each grain's impulse goes
// to the fluid particles within R_I = r_I + r_e with the normalised Wendland weights it samples with (seed Eq. 26's
// own form): the water's answer to it is then centred on the grain and isotropic wherever the grain sits, which is
// what the correction's <1/r> and <rho_s rho_w> assume; the grid form's footprint moves with the grain's place in
// its cell. Grains deposit in slot order, one after the other (the sums then do not depend on the thread count),
// and each grain's weights sum to one, so the water receives exactly minus the grains' impulse.
void FluidDragReaction::spread_with_sampling_kernel(SystemContext& context, double largest_radius) {
  const GrainState& grains = context.read<GrainState>();
  const GrainProperties& properties = context.read<GrainProperties>();
  const GrainVoidage& voidages = context.read<GrainVoidage>();
  GrainDrag& drag = context.write<GrainDrag>();
  const ParticleState& particles = context.read<ParticleState>();
  ParticleDragReaction& reaction = context.write<ParticleDragReaction>();
  const std::size_t fluid_count = fluid_slot_count(particles);
  const double effective_radius = constants_.kernel.effective_radius;
  const auto spreads_here = [&](std::size_t grain) {
    return !drag.drag_impulse[grain].isZero(0.0) && voidages.voidage[grain] > kSelfInducedMinVoidage;
  };
  // A bed has no dilute grain (the seed's never does): then the fluid grid is not built at all.
  bool any = false;
  for (std::size_t grain = 0; grain < grains.size() && !any; ++grain) any = spreads_here(grain);
  if (!any) return;
  const DomainBox domain = domain_box(context.model);
  const PeriodicBox box = periodic_box(context.model);
  fluid_grid_.build(particles.position, 0, fluid_count, largest_radius + effective_radius, domain.low, domain.high);
  for (std::size_t grain = 0; grain < grains.size(); ++grain) {
    if (!spreads_here(grain)) continue;
    const Vec3 centre = grains.position[grain];
    const WendlandKernel kernel(properties.radius[grain] + effective_radius);
    // The grain's query centres: itself, and in a periodic box its images across the seams (the nearest image of
    // each fluid particle; the period exceeds twice R_I, so none is met twice), so the impulse lands on the real
    // fluid particles on the other side, the same ones solid_fluid_sampling sampled.
    std::array<Vec3, 4> queries;
    queries[0] = centre;
    std::array<Vec3, 3> shifts;
    const int images = box.any() ? box.image_shifts(centre, kernel.effective_radius, shifts) : 0;
    for (int image = 0; image < images; ++image)
      queries[static_cast<std::size_t>(image) + 1] = centre + shifts[static_cast<std::size_t>(image)];
    const std::size_t query_count = static_cast<std::size_t>(images) + 1;
    double weight_sum = 0.0;
    for (std::size_t q = 0; q < query_count; ++q) {
      const Vec3 query = queries[q];
      fluid_grid_.for_each_within(particles.position, query, kernel.effective_radius, [&](std::uint32_t j) {
        weight_sum += kernel.weight((particles.position[j] - query).norm());
      });
    }
    if (weight_sum <= 0.0) continue;  // out of the water since the sampling: its drag was zero while dry
    // Per volume l0^3; the mixture reading gives the water the drag over eps (docs/COUPLING.md).
    const double share = (mixture_velocity_ ? 1.0 / voidages.voidage[grain] : 1.0) /
                         (weight_sum * constants_.particle_volume);
    const Vec3 impulse = drag.drag_impulse[grain];
    for (std::size_t q = 0; q < query_count; ++q) {
      const Vec3 query = queries[q];
      fluid_grid_.for_each_within(particles.position, query, kernel.effective_radius, [&](std::uint32_t j) {
        reaction.drag_reaction[j] -= (kernel.weight((particles.position[j] - query).norm()) * share) * impulse;
      });
    }
    drag.drag_impulse[grain] = Vec3::Zero();
  }
}

}  // namespace riffle
