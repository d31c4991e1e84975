#pragma once
// The grains' drag given back to the fluid (seed 000 Eq. 26; numerics.md 5.5): after the sub-steps, each grain's
// drag impulse over the fluid step is spread over the fluid particles within R_I = d_I/2 + r_e with weights
// normalised per grain, as an impulse per volume (-J_I w_Ij / sum_k w_Ik / l0^3) that the next prediction applies.
// The weights of each grain sum to one, so the fluid receives exactly minus what the grains received: momentum is
// conserved to rounding. Each fluid particle gathers from the grains around it in grid order, so the sums do not
// depend on the thread count.
#include "engine/system.hpp"
#include "systems/cell_grid.hpp"
#include "systems/fluid_common.hpp"

namespace riffle {

class FluidDragReaction final : public System {
 public:
  explicit FluidDragReaction(const Model& model) : constants_(MpsConstants::from(model.fluid)) {}
  std::string_view name() const override { return "fluid_drag_reaction"; }
  Access access() const override { return {{}, {ComponentId::kSolids, ComponentId::kFluid}}; }
  void run(SystemContext& context) override;

 private:
  MpsConstants constants_;
  CellGrid fluid_grid_, grain_grid_;
  std::vector<double> weight_sums_;  ///< per grain: sum of its kernel weights over the fluid
};

}  // namespace riffle
