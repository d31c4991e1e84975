#include "systems/coupling/fluid_drag_reaction.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "systems/physics/coupling/drag_law.hpp"
#include "systems/physics/geometry/domain.hpp"
#include "systems/physics/mps/fluid_pair_batch.hpp"
#include "systems/physics/mps/mps_kernel.hpp"
#include "systems/physics/geometry/periodic_box.hpp"
#include "systems/physics/coupling/sampling_kernel.hpp"
#include "systems/coupling/solid_drag.hpp"
#include "systems/physics/ranks/coupling_ranks.hpp"
#include "systems/physics/ranks/rank_comm.hpp"

namespace riffle {

void FluidDragReaction::run(SystemContext& context) {
  const GrainState& grains = context.read<GrainState>();
  const GrainProperties& properties = context.read<GrainProperties>();
  const GrainVoidage& voidages = context.read<GrainVoidage>();
  GrainDrag& drag = context.write<GrainDrag>();
  const ParticleState& particles = context.read<ParticleState>();
  double largest_radius = 0.0;
  for (const double radius : properties.radius) largest_radius = std::max(largest_radius, radius);
  const bool spread = over_ranks_ && context.read<Contacts>().ranks.active;
  if (spread) largest_radius = ranks::max(largest_radius);
  largest_radius_ = largest_radius;
  Points points;
  if (spread) {
    // The grid's reach: a fluid particle reads the nodes of its cell, which hold the impulses of the grains within a
    // cell of them and the fluid volume within a cell of them, and each such grain's share depends on which of its
    // nodes hold water: grains within two cells, fluid within three; the kernel's: grains within R of a fluid
    // particle, and the fluid within R of those grains. A fourth cell for the cells' rounding.
    const double kernel_radius = coupling_kernel_radius(largest_radius, constants_.effective_radius,
                                                        constants_.spacing, self_induced_velocity_);
    const double cell = kGridCellPerKernel * kernel_radius;
    points = gather_near_ranks(context, std::max(4.0 * cell, 2.0 * kernel_radius + cell));
  } else {
    points.grain_position = grains.position;
    points.grain_radius = properties.radius;
    points.grain_voidage = voidages.voidage;
    points.grain_impulse = drag.drag_impulse;
    points.fluid_position = std::span<const Vec3>(particles.position.data(), fluid_slot_count(particles));
    points.own_fluid = points.fluid_position.size();
  }
  if (kernel_reaction_) {  // every grain spreads with its sampling kernel: no grid
    spread_with_sampling_kernel(context, points, false);
  } else {
    // With the self-induced correction the dilute grains (those it applies to) spread with their sampling kernel;
    // the grains of a bed keep the grid, whose cost does not grow with the kernel's neighbour count.
    if (self_induced_velocity_) spread_with_sampling_kernel(context, points, true);
    spread_on_grid(context, points);
  }
  // Over ranks the impulses were spread from copies: this rank's grains take back theirs (zero where spread).
  if (spread)
    std::copy(near_grain_impulse_.begin(), near_grain_impulse_.begin() + static_cast<std::ptrdiff_t>(grains.size()),
              drag.drag_impulse.begin());
  context.count_items(grains.size());
}

FluidDragReaction::Points FluidDragReaction::gather_near_ranks(SystemContext& context, double reach) {
  const GrainState& grains = context.read<GrainState>();
  const GrainProperties& properties = context.read<GrainProperties>();
  const GrainVoidage& voidages = context.read<GrainVoidage>();
  const GrainDrag& drag = context.read<GrainDrag>();
  const ParticleState& particles = context.read<ParticleState>();
  const RankHalo& grain_ranks = context.read<Contacts>().ranks;
  const FluidRankHalo& fluid_ranks = context.read<FluidNeighbours>().ranks;
  const std::size_t own_fluid = fluid_slot_count(particles);
  const std::span<const Vec3> fluid(particles.position.data(), own_fluid);
  // Both families' boxes: the grains this rank's water needs sit near its fluid box, the water its grains need near
  // their box. Each family's members stand up to its overflow outside their rank's box.
  const PeriodicBox box = periodic_box(context.model);
  // Two collectives, in this order on every rank.
  const CouplingBoxes grain_boxes =
      coupling_boxes(grain_ranks.box_low, grain_ranks.box_high, grains.position, reach, box);
  const CouplingBoxes boxes =
      either_family(grain_boxes, coupling_boxes(fluid_ranks.box_low, fluid_ranks.box_high, fluid, reach, box));
  near_grain_position_.assign(grains.position.begin(), grains.position.end());
  near_grain_radius_.assign(properties.radius.begin(), properties.radius.end());
  near_grain_voidage_.assign(voidages.voidage.begin(), voidages.voidage.end());
  near_grain_impulse_.assign(drag.drag_impulse.begin(), drag.drag_impulse.end());
  exchange_records(
      indices_near_other_ranks(grains.position, boxes, box),
      [&](ByteWriter& out, std::uint32_t i) {
        out.put(grains.position[i]);
        out.put(properties.radius[i]);
        out.put(voidages.voidage[i]);
        out.put(drag.drag_impulse[i]);
      },
      [&](ByteReader& in) {
        near_grain_position_.push_back(in.get<Vec3>());
        near_grain_radius_.push_back(in.get<double>());
        near_grain_voidage_.push_back(in.get<double>());
        near_grain_impulse_.push_back(in.get<Vec3>());
      });
  near_fluid_position_.assign(fluid.begin(), fluid.end());
  exchange_records(
      indices_near_other_ranks(fluid, boxes, box), [&](ByteWriter& out, std::uint32_t i) { out.put(fluid[i]); },
      [&](ByteReader& in) { near_fluid_position_.push_back(in.get<Vec3>()); });
  // The grid's nodes where one grid over every rank's points has them.
  grid_.anchor_lattice(lowest_corner_over_ranks(grains.position, fluid));
  Points points;
  points.grain_position = near_grain_position_;
  points.grain_radius = near_grain_radius_;
  points.grain_voidage = near_grain_voidage_;
  points.grain_impulse = near_grain_impulse_;
  points.fluid_position = near_fluid_position_;
  points.own_fluid = own_fluid;
  return points;
}

void FluidDragReaction::spread_on_grid(SystemContext& context, const Points& points) {
  ParticleDragReaction& reaction = context.write<ParticleDragReaction>();
  const std::size_t grain_count = points.grain_position.size();
  // Cells of (2 pi / 21)^(1/3) (r + r_e): one cell holds the volume of the Wendland kernel on R_I (seed Eq. 26's
  // influence domain), so the impulse spreads over the same volume, at a cost linear in the particle counts.
  const double cell_size = kGridCellPerKernel * (largest_radius_ + constants_.effective_radius);
  volumes_.assign(grain_count, 0.0);
  const DomainBox domain = domain_box(context.model);
  // A periodic box: the grid wraps along its periodic axes (whole cells per period), so a grain's stencil by the
  // seam reaches the nodes, and through them the fluid particles, on the other side.
  grid_.build(points.grain_position, volumes_, points.fluid_position, points.fluid_position.size(),
              constants_.particle_volume, cell_size, domain.low, domain.high, periodic_box(context.model));

  // Impulses to the nodes (slot order), then each fluid particle takes its weight's share of its nodes' impulse:
  // sum_j w_jn / W_n = 1 at every node with water, so the water receives exactly minus the grains' impulse.
  node_impulse_.assign(grid_.node_count(), Vec3::Zero());
  for (std::size_t grain = 0; grain < grain_count; ++grain) {
    if (points.grain_impulse[grain].isZero(0.0)) continue;  // also the dilute grains the kernel spreading took
    const CloudInCellStencil stencil = grid_.stencil(points.grain_position[grain]);
    double wet = 0.0;  // weight of the nodes that hold water: a grain at the water's edge gives all to those
    for (std::size_t c = 0; c < 8; ++c) wet += grid_.fluid_volume(stencil.node[c]) > 0.0 ? stencil.weight[c] : 0.0;
    if (wet <= 0.0) continue;  // out of the water since the sampling: its drag was zero while dry
    // Mixture reading: the pore water's relative momentum balance, divided by eps, has -grad p + rho g and the
    // drag per volume over eps (docs/COUPLING.md).
    const double share = 1.0 / (wet * flux_share(fluid_velocity_, points.grain_voidage[grain]));
    for (std::size_t c = 0; c < 8; ++c)
      if (grid_.fluid_volume(stencil.node[c]) > 0.0)
        node_impulse_[stencil.node[c]] -= (stencil.weight[c] * share) * points.grain_impulse[grain];
    points.grain_impulse[grain] = Vec3::Zero();
  }
  for_each_particle(points.own_fluid, [&](std::size_t j) {
    const CloudInCellStencil stencil = grid_.stencil(points.fluid_position[j]);
    Vec3 received = Vec3::Zero();
    // fluid_volume(n) = l0^3 sum_k w_kn, so this particle's share of node n is l0^3 w_jn / fluid_volume(n); per
    // volume l0^3, that is w_jn / fluid_volume(n).
    for (std::size_t c = 0; c < 8; ++c)
      if (stencil.weight[c] > 0.0) received += (stencil.weight[c] / grid_.fluid_volume(stencil.node[c])) * node_impulse_[stencil.node[c]];
    reaction.drag_reaction[j] += received;
  });
}

namespace {

/// Pairs of the kernel spreading a batch at a time (as fluid_pair_batch.hpp's, with a kernel radius per pair): the
/// candidates within their R are kept by advancing the end, then the weights of the batch are evaluated in one
/// straight-line pass the compiler vectorises. Both passes evaluate a pair's weight here, with the same operations
/// as WendlandKernel::weight of the distance (those solid_fluid_sampling's weights are), so the weights a grain is
/// normalised with are, bit for bit, the ones it spreads with.
struct KernelPairBatch {
  std::size_t count = 0;
  alignas(64) double distance_squared[kPairBatch];
  alignas(64) double radius[kPairBatch];          ///< [m] R of the pair's grain
  alignas(64) double inverse_radius[kPairBatch];  ///< [1/m] 1 / R
  alignas(64) double weight[kPairBatch];
  std::uint32_t index[kPairBatch];                ///< the fluid slot (pass 1) or the grain's entry (pass 2)

  /// Adds a candidate; kept (count advanced) only within R.
  void offer(std::uint32_t entry, double squared, const WendlandKernel& kernel) {
    const std::size_t k = count;
    index[k] = entry;
    distance_squared[k] = squared;
    radius[k] = kernel.effective_radius;
    inverse_radius[k] = kernel.inverse_radius;
    count += squared < kernel.effective_radius * kernel.effective_radius ? 1 : 0;
  }
  bool full() const { return count == kPairBatch; }
  void evaluate() {
    for (std::size_t k = 0; k < count; ++k) {
      const double distance = std::sqrt(distance_squared[k]);
      const double q = distance * inverse_radius[k];
      const double one_minus = 1.0 - q;
      const double squared = one_minus * one_minus;
      const double inside = squared * squared * (1.0 + 4.0 * q);  // WendlandKernel::weight_inside
      weight[k] = distance >= radius[k] ? 0.0 : inside;
    }
  }
};

}  // namespace

// The sampling kernel's spreading (docs/COUPLING.md, "Where the drag reaction lands"; seed Eq. 26's own form): grain
// I's impulse goes to the fluid particles j within R_I (r_I + r_e; grain_kernel_radius) with the weights w_Ij / W_I it samples the water
// with (W_I = sum_j w_Ij), at the positions of now. The water then receives exactly minus the grains' impulse, and
// what a grain pushes is what it reads: the reaction's power on the water is -share_I J_I . u_bar_I, which for a held
// grain (J_I = k u_bar_I dt, k > 0) is <= 0 in any water velocity field.
// With the self-induced correction the dilute grains spread this way, since the correction's <1/r> and
// <rho_s rho_w> assume a footprint centred on the grain (the grid's moves with the grain's place in its cell).
// Two gathers, so that nothing depends on the thread count and no two threads write one place:
//  1. per grain (parallel): W_I over the fluid particles within R_I, and a_I = -J_I share_I / (W_I l0^3), the
//     impulse per volume per unit weight (share_I = 1/eps_I in the mixture reading, docs/COUPLING.md);
//  2. per fluid particle (parallel): sum over the grains within R_I of it of w_Ij a_I, the grains met in the fixed
//     order of a grid over their centres.
// In a periodic box a grain cut by a seam is completed by its images (centre + s, s from image_shifts: the nearest
// image of each fluid particle; the period exceeds twice R_I, so none is met twice), as in solid_fluid_sampling; in
// pass 2 the fluid particle looks from x_j + t for its own shifts t, which meets the grain's image centre - t, the
// same point (bit for bit: t = -s) pass 1 summed from. Both passes wrap the grain's centre into the box first.
void FluidDragReaction::spread_with_sampling_kernel(SystemContext& context, const Points& points, bool dilute_only) {
  ParticleDragReaction& reaction = context.write<ParticleDragReaction>();
  const std::size_t fluid_count = points.fluid_position.size();
  const double effective_radius = constants_.effective_radius;
  const PeriodicBox box = periodic_box(context.model);
  spread_slot_.clear();
  spread_centre_.clear();
  spread_kernel_.clear();
  spread_stretch_.clear();
  for (std::size_t grain = 0; grain < points.grain_position.size(); ++grain) {
    if (points.grain_impulse[grain].isZero(0.0)) continue;
    if (dilute_only && !(points.grain_voidage[grain] > kSelfInducedMinVoidage)) continue;
    spread_slot_.push_back(static_cast<std::uint32_t>(grain));
    spread_centre_.push_back(box.any() ? box.wrap(points.grain_position[grain]) : points.grain_position[grain]);
    // The kernel it samples with (grain_kernel_radius: a dilute grain's no narrower than at l0 = r).
    spread_kernel_.emplace_back(grain_kernel_radius(self_induced_velocity_, points.grain_radius[grain],
                                                    effective_radius, constants_.spacing,
                                                    points.grain_voidage[grain]));
    spread_stretch_.push_back(sampling_vertical_stretch(spread_kernel_.back().effective_radius, vertical_radius_));
  }
  // A bed has no dilute grain (the seed's never does): then no grid is built at all.
  if (spread_slot_.empty() || fluid_count == 0) return;
  const std::size_t count = spread_slot_.size();
  double smallest = spread_kernel_[0].effective_radius, largest = smallest;
  for (const WendlandKernel& kernel : spread_kernel_) {
    smallest = std::min(smallest, kernel.effective_radius);
    largest = std::max(largest, kernel.effective_radius);
  }
  const DomainBox domain = domain_box(context.model);
  const double volume = constants_.particle_volume;

  // Pass 1. Cells of half the smallest R, as solid_fluid_sampling's (a query scans about 5^3 cells).
  fluid_grid_.build(points.fluid_position, 0, fluid_count, 0.5 * smallest, domain.low, domain.high);
  spread_per_weight_.assign(count, Vec3::Zero());
  for_each_particle(count, [&](std::size_t k) {
    const Vec3 centre = spread_centre_[k];
    const WendlandKernel kernel = spread_kernel_[k];
    const double stretch = spread_stretch_[k];
    double weight_sum = 0.0;
    KernelPairBatch batch;
    const auto flush = [&] {
      batch.evaluate();
      for (std::size_t pair = 0; pair < batch.count; ++pair) weight_sum += batch.weight[pair];
      batch.count = 0;
    };
    const auto gather = [&](const Vec3& query) {
      const auto keep = [&](const std::uint32_t* first, const std::uint32_t* last) {
        for (const std::uint32_t* j = first; j < last; ++j) {
          batch.offer(*j, sampling_distance_squared(fluid_grid_.member_position(j) - query, stretch), kernel);
          if (batch.full()) flush();
        }
      };
      fluid_grid_.for_each_candidate_run(query, kernel.effective_radius, keep);
    };
    gather(centre);
    std::array<Vec3, 3> shifts;
    const int images = box.any() ? box.image_shifts(centre, kernel.effective_radius, shifts) : 0;
    for (int image = 0; image < images; ++image) gather(centre + shifts[static_cast<std::size_t>(image)]);
    if (batch.count > 0) flush();
    if (weight_sum <= 0.0) return;  // out of the water since the sampling: it keeps its impulse (zero while dry)
    const std::size_t grain = spread_slot_[k];
    const double share = (1.0 / flux_share(fluid_velocity_, points.grain_voidage[grain])) / (weight_sum * volume);
    spread_per_weight_[k] = -share * points.grain_impulse[grain];
    points.grain_impulse[grain] = Vec3::Zero();
  });
  // Only the grains that spread go on (order kept).
  std::size_t wet = 0;
  for (std::size_t k = 0; k < count; ++k) {
    if (spread_per_weight_[k].isZero(0.0)) continue;
    spread_centre_[wet] = spread_centre_[k];
    spread_kernel_[wet] = spread_kernel_[k];
    spread_stretch_[wet] = spread_stretch_[k];
    spread_per_weight_[wet] = spread_per_weight_[k];
    ++wet;
  }
  if (wet == 0) return;

  // Pass 2. A grid over the grains' centres with cells of half the largest R; a fluid particle farther than R_max
  // from the centres' bounding box meets no grain and skips the search (most of the water above a bed).
  grain_grid_.build(spread_centre_, 0, wet, 0.5 * largest, domain.low - Vec3::Constant(largest),
                    domain.high + Vec3::Constant(largest));
  Vec3 low = spread_centre_[0], high = spread_centre_[0];
  for (std::size_t k = 0; k < wet; ++k) {
    low = low.cwiseMin(spread_centre_[k]);
    high = high.cwiseMax(spread_centre_[k]);
  }
  low -= Vec3::Constant(largest);
  high += Vec3::Constant(largest);
  for_each_particle(points.own_fluid, [&](std::size_t j) {  // this rank's fluid receives
    const Vec3 point = points.fluid_position[j];
    Vec3 received = Vec3::Zero();
    bool reached = false;
    KernelPairBatch batch;
    const auto flush = [&] {
      batch.evaluate();
      for (std::size_t pair = 0; pair < batch.count; ++pair)
        received += batch.weight[pair] * spread_per_weight_[batch.index[pair]];
      reached = true;
      batch.count = 0;
    };
    const auto gather = [&](const Vec3& shift) {  // the grains near point + shift, i.e. their images centre - shift
      const Vec3 query = point + shift;
      if ((query.array() < low.array()).any() || (query.array() > high.array()).any()) return;
      grain_grid_.for_each_candidate_run(query, largest, [&](const std::uint32_t* first, const std::uint32_t* last) {
        for (const std::uint32_t* k = first; k < last; ++k) {
          // The same offset as pass 1's, point - (centre + s) with s = -shift, bit for bit, in the same metric
          // (an ellipsoidal kernel's stretched dz): the weights pass 1 normalised with are the ones spread with.
          batch.offer(*k, sampling_distance_squared(point - Vec3(grain_grid_.member_position(k) - shift), spread_stretch_[*k]),
                      spread_kernel_[*k]);
          if (batch.full()) flush();
        }
      });
    };
    gather(Vec3::Zero());
    std::array<Vec3, 3> shifts;
    const int images = box.any() ? box.image_shifts(point, largest, shifts) : 0;
    for (int image = 0; image < images; ++image) gather(shifts[static_cast<std::size_t>(image)]);
    if (batch.count > 0) flush();
    if (reached) reaction.drag_reaction[j] += received;
  });
}

}  // namespace riffle
