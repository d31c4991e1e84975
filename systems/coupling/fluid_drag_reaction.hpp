#pragma once
// The grains' drag given back to the fluid (seed 000 Eq. 26; numerics.md 5.5): after the sub-steps, each grain's
// drag impulse over the fluid step is spread over the fluid around it as an impulse per volume that the next
// prediction applies. Two forms ([coupling] drag_reaction, docs/COUPLING.md "Where the drag reaction lands"):
//  - "grid" (the default): a cloud-in-cell grid (systems/physics/coupling/voidage_grid.hpp) with cells sized so one cell
//    holds the volume of Eq. 26's influence domain: grain -> nodes -> fluid particles, with weights that sum to one
//    at each step, at a cost linear in the particle counts. Grains deposit in slot order and each fluid particle
//    gathers from its own nodes;
//  - "sampling_kernel": each grain's impulse goes to the fluid particles within R = r + r_e with the normalised
//    Wendland weights it samples the water with (solid_fluid_sampling), so a grain pushes the water it reads. Two
//    gather passes: per grain its weight sum, per fluid particle the sum over the grains that reach it. The dilute
//    grains of the self-induced correction take the same path. With sampling_vertical_radius both passes use the
//    sampling's ellipsoidal kernel (the same stretched offsets), so the footprint stays the sampled one.
// Either way the fluid receives exactly minus what the grains received (momentum conserved to rounding), and
// nothing depends on the thread count.
#include <span>

#include "systems/system.hpp"
#include "systems/physics/coupling/voidage_grid.hpp"
#include "systems/physics/geometry/cell_grid.hpp"
#include "systems/physics/mps/mps_common.hpp"
#include "systems/physics/mps/mps_kernel.hpp"

namespace riffle {

class FluidDragReaction final : public System {
 public:
  /// `over_ranks` (grains in MPS water over MPI ranks): the other ranks' grains and fluid particles within the
  /// grids' and kernels' reach of this rank's grains and water come in first (coupling_ranks.hpp); each rank gives its
  /// own fluid particles their share of every grain's impulse, and zeroes its own grains' impulses.
  explicit FluidDragReaction(const Model& model, bool over_ranks = false)
      : over_ranks_(over_ranks),
        constants_(mps_constants(model.fluid)),
        fluid_velocity_(model.coupling.fluid_velocity),
        self_induced_velocity_(model.coupling.self_induced_velocity),
        kernel_reaction_(model.coupling.sampling_kernel_reaction),
        vertical_radius_(model.coupling.sampling_vertical_radius) {}
  std::string_view name() const override { return "fluid_drag_reaction"; }
  Access access() const override {
    Access access{component_ids<GrainState, GrainProperties, GrainVoidage, ParticleState>(),
                  component_ids<GrainDrag, ParticleDragReaction>()};
    if (over_ranks_)
      for (const ComponentId id : component_ids<Contacts, FluidNeighbours>()) access.reads.push_back(id);
    return access;
  }
  void run(SystemContext& context) override;

 private:
  /// What the reaction reads: the grains (this rank's first, `own_grains` of them) and the fluid particles (this
  /// rank's fluid slots first, `own_fluid` of them: those that receive). On one rank the components themselves.
  struct Points {
    std::span<const Vec3> grain_position;
    std::span<const double> grain_radius, grain_voidage;
    std::span<Vec3> grain_impulse;  ///< zeroed where spread
    std::span<const Vec3> fluid_position;
    std::size_t own_fluid = 0;
  };
  /// The grid's spreading of every grain's impulse still unspread.
  void spread_on_grid(SystemContext& context, const Points& points);
  /// Spreads with the sampling kernel the impulse of every grain with one that is in the water (a fluid particle
  /// within its R), all of them or (dilute_only) those above the self-induced correction's voidage, and zeroes it.
  void spread_with_sampling_kernel(SystemContext& context, const Points& points, bool dilute_only);
  /// Over ranks: the other ranks' grains and fluid particles within `reach` of this rank's boxes after this rank's
  /// own, in the members below; returns them as Points. Collective.
  Points gather_near_ranks(SystemContext& context, double reach);

  /// (2 pi / 21)^(1/3): the grid's cell over the kernel radius r + r_e (one cell holds the Wendland kernel's volume).
  static constexpr double kGridCellPerKernel = 0.668;

  bool over_ranks_;
  double largest_radius_ = 0.0;  ///< [m] the largest grain's radius (over every rank's), this step
  std::vector<Vec3> near_grain_position_, near_grain_impulse_, near_fluid_position_;
  std::vector<double> near_grain_radius_, near_grain_voidage_;

  MpsConstants constants_;
  CouplingModel::FluidVelocity fluid_velocity_;  ///< the water takes the drag per volume over flux_share
  bool self_induced_velocity_ = false;  ///< dilute grains spread with the sampling kernel (CouplingModel)
  bool kernel_reaction_ = false;        ///< every grain spreads with it (CouplingModel::sampling_kernel_reaction)
  double vertical_radius_ = 0.0;        ///< [m] R_v (CouplingModel::sampling_vertical_radius), 0 = isotropic
  CellGrid fluid_grid_;          ///< the fluid particles, for the kernel spreading's weight sums
  CellGrid grain_grid_;          ///< the spreading grains' centres, for the fluid particles' gather
  // The kernel spreading's grains, compact, in slot order: slot, centre (wrapped into a periodic box), kernel
  // (grain_kernel_radius), and the impulse per volume per unit weight the water takes from it (zero: not spread, dry).
  std::vector<std::uint32_t> spread_slot_;
  std::vector<Vec3> spread_centre_;
  std::vector<WendlandKernel> spread_kernel_;
  std::vector<double> spread_stretch_;  ///< R_h / R_v of each kernel (sampling_kernel.hpp), 1 = isotropic
  std::vector<Vec3> spread_per_weight_;
  VoidageGrid grid_;             ///< its fluid deposit is the normalisation; the solid deposit is unused (zero volumes)
  std::vector<double> volumes_;
  std::vector<Vec3> node_impulse_;
};

}  // namespace riffle
