#pragma once
// The grains' drag given back to the fluid (seed 000 Eq. 26; numerics.md 5.5): after the sub-steps, each grain's
// drag impulse over the fluid step is spread over the fluid around it as an impulse per volume that the next
// prediction applies. The spreading goes through a cloud-in-cell grid (systems/physics/voidage_grid.hpp) with cells sized
// so one cell holds the volume of Eq. 26's influence domain: grain -> nodes -> fluid particles, with weights that
// sum to one at each step, so the fluid receives exactly minus what the grains received (momentum conserved to
// rounding) at a cost linear in the particle counts. Grains deposit in slot order and each fluid particle gathers
// from its own nodes, so nothing depends on the thread count.
#include "engine/core/system.hpp"
#include "systems/physics/voidage_grid.hpp"
#include "systems/physics/cell_grid.hpp"
#include "systems/physics/mps_common.hpp"

namespace riffle {

class FluidDragReaction final : public System {
 public:
  explicit FluidDragReaction(const Model& model)
      : constants_(MpsConstants::from(model.fluid)),
        mixture_velocity_(model.coupling.mixture_velocity),
        self_induced_velocity_(model.coupling.self_induced_velocity) {}
  std::string_view name() const override { return "fluid_drag_reaction"; }
  Access access() const override {
    return {component_ids<GrainState, GrainProperties, GrainVoidage, ParticleState>(),
            component_ids<GrainDrag, ParticleDragReaction>()};
  }
  void run(SystemContext& context) override;

 private:
  void spread_with_sampling_kernel(SystemContext& context, double largest_radius);

  MpsConstants constants_;
  bool mixture_velocity_ = false;  ///< the water takes the drag per volume over eps (CouplingModel)
  bool self_induced_velocity_ = false;  ///< spread with the sampling kernel (CouplingModel::self_induced_velocity)
  CellGrid fluid_grid_;          ///< the fluid particles, for the kernel spreading
  VoidageGrid grid_;             ///< its fluid deposit is the normalisation; the solid deposit is unused (zero volumes)
  std::vector<double> volumes_;
  std::vector<Vec3> node_impulse_;
};

}  // namespace riffle
