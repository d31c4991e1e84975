#include "systems/coupling/solid_voidage.hpp"

#include <algorithm>
#include <cmath>

#include "systems/physics/drag_law.hpp"
#include "systems/physics/mps_common.hpp"
#include "systems/physics/domain.hpp"
#include "systems/physics/periodic_box.hpp"
#include "systems/physics/tank_kinematics.hpp"

namespace riffle {

SolidVoidage::SolidVoidage(const Model& model)
    : particle_volume_(MpsConstants::from(model.fluid).particle_volume),
      spacing_(model.fluid.spacing),
      voidage_radius_(model.coupling.voidage_radius),
      min_voidage_(model.coupling.min_voidage),
      vertical_radius_(model.coupling.voidage_vertical_radius),
      over_tank_(model.coupling.voidage_over_tank),
      self_corrected_(model.coupling.self_corrected_voidage) {}

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
  const DomainBox domain = domain_box(context.model);
  if (over_tank_) {
    run_over_tank(context);
    return;
  }
  const double across = vertical_radius_ > 0.0 ? vertical_radius_ : voidage_radius_;
  if (!self_corrected_) {
    // main before issue 21: cells of (2 pi / 21)^(1/3) R_eps (one cell holds the volume of the Wendland kernel on
    // R_eps, numerics 1.2), trilinear deposit and read back, the grain's own volume included.
    grid_.build(grains.position, grain_volumes_, particles.position, fluid_slot_count(particles), particle_volume_,
                Vec3(kCloudInCellCell * voidage_radius_, kCloudInCellCell * voidage_radius_, kCloudInCellCell * across),
                domain.low, domain.high, periodic_box(context.model));
    for_each_particle(grains.size(), [&](std::size_t grain) {
      voidages.voidage[grain] = std::clamp(1.0 - grid_.solid_fraction(grains.position[grain]), min_voidage_, 1.0);
    });
    context.count_items(grains.size());
    return;
  }
  // docs/COUPLING.md, "The voidage at a grain": cells of 0.42 R_eps smoothed by one binomial pass give a kernel as
  // wide as the trilinear one on 0.668 R_eps cells (standard deviation 0.385 R_eps per axis) but smooth; each grain
  // reads the other grains' fraction exactly (its own deposit, read back, taken out) and gets its own volume back
  // times 1 - S(0), the share its neighbours' excluded volume leaves out.
  grid_.build(grains.position, grain_volumes_, particles.position, fluid_slot_count(particles), particle_volume_,
              Vec3(kSmoothCell * voidage_radius_, kSmoothCell * voidage_radius_, kSmoothCell * across), domain.low,
              domain.high, periodic_box(context.model));
  grid_.smooth();
  for_each_particle(grains.size(), [&](std::size_t grain) {
    const GrainSolidFraction read = grid_.grain_fraction(grains.position[grain], grain_volumes_[grain]);
    const double others = std::max(read.included - read.own, 0.0);
    voidages.voidage[grain] =
        std::clamp(1.0 - self_corrected_solid_fraction(others, read.own), min_voidage_, 1.0);
  });
  context.count_items(grains.size());
}

// docs/COUPLING.md, "A thin bed's voidage": the grains alone on the grid, divided by the volume of the tank (where it
// is now) that each node covers, so the cells can be narrower than the water's lattice, and narrower across the bed
// (R_eps along z) than along it; smoothed and read back as the self-corrected estimate (or the cloud-in-cell one).
void SolidVoidage::run_over_tank(SystemContext& context) {
  const GrainState& grains = context.read<GrainState>();
  GrainVoidage& voidages = context.write<GrainVoidage>();
  const Model& model = context.model;
  const double cell_ratio = self_corrected_ ? kSmoothCell : kCloudInCellCell;
  const double across = vertical_radius_ > 0.0 ? vertical_radius_ : voidage_radius_;
  const Vec3 cell(cell_ratio * voidage_radius_, cell_ratio * voidage_radius_, cell_ratio * across);
  // The end of the step, where the grains now are (as fluid_escape; dt = 0 in the initial-forces pass).
  const Vec3 tank_low = model.tank.origin + tank_kinematics(model.tank.motion, context.time + context.dt).displacement;
  const DomainBox domain = domain_box(model);
  grid_.build(grains.position, grain_volumes_, grains.position, 0, 0.0, cell, domain.low, domain.high,
              periodic_box(model));
  grid_.fill_box_volume(tank_low, tank_low + model.tank.size);
  if (self_corrected_) grid_.smooth();
  for_each_particle(grains.size(), [&](std::size_t grain) {
    double solid = 0.0;
    if (self_corrected_) {
      const GrainSolidFraction read = grid_.grain_fraction(grains.position[grain], grain_volumes_[grain]);
      solid = self_corrected_solid_fraction(std::max(read.included - read.own, 0.0), read.own);
    } else {
      solid = grid_.solid_fraction(grains.position[grain]);
    }
    voidages.voidage[grain] = std::clamp(1.0 - solid, min_voidage_, 1.0);
  });
  context.count_items(grains.size());
}

}  // namespace riffle
