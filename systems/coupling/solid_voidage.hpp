#pragma once
// The voidage at every grain at the end of each fluid step (numerics.md 5.3 in grid form; docs/COUPLING.md, "The
// voidage at a grain"): solid volume over the space the fluid particles fill, both deposited on a grid of cells
// 0.668 R_eps wide (systems/physics/coupling/voidage_grid.hpp; the fluid particles are the space quadrature, so walls and the
// free surface truncate both alike), smoothed by one binomial pass, read back at the grain's centre without the
// grain's own deposit, which comes back times 1 - S(0) (a lone grain reads 1 wherever it is), and clipped to
// [min_voidage, 1]; 1 where no node around the grain holds water. `voidage_estimate = "cloud_in_cell"`: main's
// reading (no smoothing, the own volume included). It runs at the end of the step, before fluid_drag_reaction
// divides the drag by it; the grains' next sub-steps use the same value (solid_drag).
#include <vector>

#include "systems/system.hpp"
#include "systems/physics/coupling/voidage_grid.hpp"

namespace riffle {

class SolidVoidage final : public System {
 public:
  /// `over_ranks` (grains in MPS water over MPI ranks): the grid also holds the other ranks' grains and fluid
  /// particles within its reach of this rank's grains (coupling_ranks.hpp), so each grain reads what one rank reads.
  explicit SolidVoidage(const Model& model, bool over_ranks = false);
  std::string_view name() const override { return "solid_voidage"; }
  Access access() const override {
    Access access{component_ids<ParticleState, GrainState, GrainProperties>(), component_ids<GrainVoidage>()};
    if (over_ranks_) access.reads.push_back(Contacts::kId);
    return access;
  }
  void run(SystemContext& context) override;

 private:
  double particle_volume_;  ///< [m^3] l0^3
  double spacing_;          ///< [m] l0
  double voidage_radius_;   ///< [m] R_eps; 0 until the first run picks it from the grains present
  double min_voidage_;      ///< [1]
  double vertical_radius_;  ///< [m] R_eps along z; 0 = voidage_radius_
  bool over_tank_;          ///< true: the grains' volume over the tank's, not over the fluid particles'
  bool self_corrected_;     ///< false: the trilinear (cloud-in-cell) reading with the grain's own volume included
  bool over_ranks_;
  VoidageGrid grid_;
  std::vector<double> grain_volumes_;
  // Over ranks: this rank's grains, then the other ranks' within reach (positions, volumes), and the fluid particles
  // likewise (this rank's fluid slots, then the others').
  std::vector<Vec3> grain_positions_, fluid_positions_;

  /// Fills grain_positions_, grain_volumes_ (past this rank's) and fluid_positions_ with this rank's and the other
  /// ranks' within `reach` of this rank's grains. Collective.
  void gather_near_ranks(SystemContext& context, double reach);
};

}  // namespace riffle
