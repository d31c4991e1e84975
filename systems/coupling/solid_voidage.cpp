#include "systems/coupling/solid_voidage.hpp"

#include <algorithm>
#include <cmath>

#include "systems/physics/drag_law.hpp"
#include "systems/physics/mps_common.hpp"
#include "systems/physics/domain.hpp"

namespace riffle {

SolidVoidage::SolidVoidage(const Model& model)
    : particle_volume_(MpsConstants::from(model.fluid).particle_volume),
      spacing_(model.fluid.spacing),
      voidage_radius_(model.coupling.voidage_radius),
      min_voidage_(model.coupling.min_voidage) {}

void SolidVoidage::run(SystemContext& context) {
  const FluidParticles& fluid = context.read<FluidParticles>();
  Solids& solids = context.write<Solids>();
  double largest_radius = 0.0;
  grain_volumes_.resize(solids.size());
  for (std::size_t grain = 0; grain < solids.size(); ++grain) {
    largest_radius = std::max(largest_radius, solids.radius[grain]);
    grain_volumes_[grain] = grain_volume(solids.radius[grain]);
  }
  // numerics 5.3: R_eps >= max(3 l0, d_max); twice d_max keeps a lone grain's own volume from dominating its voidage.
  if (voidage_radius_ <= 0.0) voidage_radius_ = std::max(3.0 * spacing_, 4.0 * largest_radius);
  // Cells of (2 pi / 21)^(1/3) R_eps: one cell holds the volume of the Wendland kernel on R_eps (numerics 1.2),
  // so the grid averages over the same volume as the kernel form of numerics 5.3.
  const DomainBox domain = domain_box(context.model);
  grid_.build(solids.position, grain_volumes_, fluid.position, fluid_slot_count(fluid), particle_volume_,
              0.668 * voidage_radius_, domain.low, domain.high);
  for_each_particle(solids.size(), [&](std::size_t grain) {
    solids.voidage[grain] = std::clamp(1.0 - grid_.solid_fraction(solids.position[grain]), min_voidage_, 1.0);
  });
  context.count_items(solids.size());
}

}  // namespace riffle
