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
  const ParticleState& particles = context.read<ParticleState>();
  const GrainState& grains = context.read<GrainState>();
  const GrainProperties& properties = context.read<GrainProperties>();
  GrainVoidage& voidages = context.write<GrainVoidage>();
  double largest_radius = 0.0;
  grain_volumes_.resize(grains.size());
  for (std::size_t grain = 0; grain < grains.size(); ++grain) {
    largest_radius = std::max(largest_radius, properties.radius[grain]);
    grain_volumes_[grain] = grain_volume(properties.radius[grain]);
  }
  // numerics 5.3: R_eps >= max(3 l0, d_max); twice d_max keeps a lone grain's own volume from dominating its voidage.
  if (voidage_radius_ <= 0.0) voidage_radius_ = std::max(3.0 * spacing_, 4.0 * largest_radius);
  // Cells of (2 pi / 21)^(1/3) R_eps: one cell holds the volume of the Wendland kernel on R_eps (numerics 1.2),
  // so the grid averages over the same volume as the kernel form of numerics 5.3.
  const DomainBox domain = domain_box(context.model);
  grid_.build(grains.position, grain_volumes_, particles.position, fluid_slot_count(particles), particle_volume_,
              0.668 * voidage_radius_, domain.low, domain.high);
  for_each_particle(grains.size(), [&](std::size_t grain) {
    voidages.voidage[grain] = std::clamp(1.0 - grid_.solid_fraction(grains.position[grain]), min_voidage_, 1.0);
  });
  context.count_items(grains.size());
}

}  // namespace riffle
