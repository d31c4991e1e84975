#include "systems/coupling/solid_voidage.hpp"

#include <algorithm>
#include <cmath>

#include "systems/physics/coupling/drag_law.hpp"
#include "systems/physics/mps/mps_common.hpp"
#include "systems/physics/geometry/domain.hpp"
#include "systems/physics/geometry/periodic_box.hpp"
#include "systems/physics/geometry/tank_kinematics.hpp"
#include "systems/physics/ranks/coupling_ranks.hpp"
#include "systems/physics/ranks/rank_comm.hpp"

namespace riffle {

SolidVoidage::SolidVoidage(const Model& model, bool over_ranks)
    : particle_volume_(mps_constants(model.fluid).particle_volume),
      spacing_(model.fluid.spacing),
      voidage_radius_(model.coupling.voidage_radius),
      min_voidage_(model.coupling.min_voidage),
      vertical_radius_(model.coupling.voidage_vertical_radius),
      over_tank_(model.coupling.voidage_volume == CouplingModel::VoidageVolume::kTank),
      self_corrected_(model.coupling.voidage_estimate == CouplingModel::VoidageEstimate::kSelfCorrected),
      over_ranks_(over_ranks) {}

void SolidVoidage::gather_near_ranks(SystemContext& context, double reach) {
  const GrainState& grains = context.read<GrainState>();
  const GrainProperties& properties = context.read<GrainProperties>();
  const ParticleState& particles = context.read<ParticleState>();
  const RankHalo& grain_ranks = context.read<Contacts>().ranks;
  const PeriodicBox box = periodic_box(context.model);
  const CouplingBoxes boxes = coupling_boxes(grain_ranks.box_low, grain_ranks.box_high, grains.position, reach, box);
  grain_positions_.assign(grains.position.begin(), grains.position.end());
  exchange_records(
      indices_near_other_ranks(grains.position, boxes, box),
      [&](ByteWriter& out, std::uint32_t i) {
        out.put(grains.position[i]);
        out.put(properties.radius[i]);
      },
      [&](ByteReader& in) {
        grain_positions_.push_back(in.get<Vec3>());
        grain_volumes_.push_back(grain_volume(in.get<double>()));
      });
  fluid_positions_.clear();
  std::size_t own_fluid = 0;
  if (!over_tank_) {  // over the tank's volume the water's particles are not read
    own_fluid = fluid_slot_count(particles);
    const auto fluid_end = particles.position.begin() + static_cast<std::ptrdiff_t>(own_fluid);
    fluid_positions_.assign(particles.position.begin(), fluid_end);
    exchange_records(
        indices_near_other_ranks(std::span<const Vec3>(particles.position.data(), own_fluid), boxes, box),
        [&](ByteWriter& out, std::uint32_t i) { out.put(particles.position[i]); },
        [&](ByteReader& in) { fluid_positions_.push_back(in.get<Vec3>()); });
  }
  // The nodes where one grid over every rank's points has them.
  grid_.anchor_lattice(
      lowest_corner_over_ranks(grains.position, std::span<const Vec3>(fluid_positions_.data(), own_fluid)));
}

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
  // Over ranks: the largest of all the ranks' grains, as one rank sees them.
  if (over_ranks_ && voidage_radius_ <= 0.0) largest_radius = ranks::max(largest_radius);  // read once, below
  // numerics 5.3: R_eps >= max(3 l0, d_max); twice d_max keeps a lone grain's own volume from dominating its voidage.
  if (voidage_radius_ <= 0.0) voidage_radius_ = std::max(3.0 * spacing_, 4.0 * largest_radius);
  const Model& model = context.model;
  const DomainBox domain = domain_box(model);
  // The cells: voidage_cell_ratio R_eps (docs/COUPLING.md, "The voidage at a grain"); along z R_eps across the bed
  // when it is set ("A thin bed's voidage").
  const double cell_ratio = voidage_cell_ratio(self_corrected_);
  const double across = vertical_radius_ > 0.0 ? vertical_radius_ : voidage_radius_;
  const Vec3 cell(cell_ratio * voidage_radius_, cell_ratio * voidage_radius_, cell_ratio * across);
  // Over ranks a grain's voidage reads the nodes of its cell, smoothed from their neighbours, which hold the deposits
  // of the points within a cell of them: everything within three cells of a grain, and a fourth for the cells'
  // rounding. One rank reads its own tables.
  const bool spread = over_ranks_ && context.read<Contacts>().ranks.active;
  if (spread) gather_near_ranks(context, 4.0 * cell.maxCoeff());
  const std::vector<Vec3>& grain_positions = spread ? grain_positions_ : grains.position;
  const std::vector<Vec3>& fluid_positions = spread ? fluid_positions_ : particles.position;
  const std::size_t fluid_count = spread ? fluid_positions_.size() : fluid_slot_count(particles);
  if (over_tank_) {
    // The grains alone, over the volume of the tank (where it is at the end of the step, where the grains now are,
    // as fluid_escape; dt = 0 in the initial-forces pass) that each node covers: exact, so the cells may be finer
    // than the water's lattice.
    const Vec3 tank_low = model.tank.origin + tank_kinematics(model.tank.motion, context.time + context.dt).displacement;
    grid_.build(grain_positions, grain_volumes_, grain_positions, 0, 0.0, cell, domain.low, domain.high,
                periodic_box(model));
    grid_.fill_box_volume(tank_low, tank_low + model.tank.size);
  } else {
    // Over the space the fluid particles fill (walls and the free surface truncate both deposits alike).
    grid_.build(grain_positions, grain_volumes_, fluid_positions, fluid_count, particle_volume_, cell, domain.low,
                domain.high, periodic_box(model));
  }
  if (!self_corrected_) {
    // The trilinear estimate: cells of (2 pi / 21)^(1/3) R_eps (one cell holds the volume of the Wendland kernel on
    // R_eps, numerics 1.2), trilinear deposit and read back, the grain's own volume included.
    for_each_particle(grains.size(), [&](std::size_t grain) {
      voidages.voidage[grain] = std::clamp(1.0 - grid_.solid_fraction(grains.position[grain]), min_voidage_, 1.0);
    });
    context.count_items(grains.size());
    return;
  }
  // docs/COUPLING.md, "The voidage at a grain": the deposits smoothed by one binomial pass; each grain reads the other
  // grains' fraction exactly (its own deposit, read back, taken out) and gets its own volume back times 1 - S(0), the
  // share its neighbours' excluded volume leaves out.
  grid_.smooth();
  for_each_particle(grains.size(), [&](std::size_t grain) {
    const GrainSolidFraction read = grid_.grain_fraction(grains.position[grain], grain_volumes_[grain]);
    const double others = std::max(read.included - read.own, 0.0);
    voidages.voidage[grain] =
        std::clamp(1.0 - self_corrected_solid_fraction(others, read.own), min_voidage_, 1.0);
  });
  context.count_items(grains.size());
}

}  // namespace riffle
