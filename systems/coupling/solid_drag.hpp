#pragma once
// Drag on every grain at every sub-step (seed 000 Eqs. 20-25; numerics.md 5.1, 5.6 step 8): from the fluid velocity
// and voidage sampled at the last fluid step (solid_fluid_sampling) and the grain's current velocity. The drag is
// also integrated over the sub-steps (drag_impulse), so the fluid can take back exactly what the grains received
// (fluid_drag_reaction).
#include "engine/core/system.hpp"

namespace riffle {

class SolidDrag final : public System {
 public:
  explicit SolidDrag(const Model& model) : model_(model.coupling), fluid_(model.fluid) {}
  std::string_view name() const override { return "solid_drag"; }
  Access access() const override {
    return {component_ids<GrainState, GrainProperties, GrainSampledFluid, GrainVoidage>(), component_ids<GrainDrag>()};
  }
  void run(SystemContext& context) override;

 private:
  CouplingModel model_;
  FluidModel fluid_;
};

}  // namespace riffle
