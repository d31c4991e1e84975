#pragma once
// What a grain's drag keeps over a fluid step, set at the step's start (after the sampling): the voidage, the grain's
// size and the sampled water hold over the step's sub-steps, so solid_drag pays there only for what changes.
// - Ergun's law at the grain's voidage (systems/physics/coupling/drag_law.hpp, ErgunDrag, times the grain's volume):
//   solid_drag then needs only the slip (the law's divisions and square roots took more than half of its time in the
//   seed's bed). Grains outside Ergun's range (a voidage above 0.8, or dense_drag = "wen_yu") get 0 and solid_drag
//   evaluates their law whole.
// - With the self-induced correction on: a grain it does not act on (dry, or in a dense bed) has no disturbance and
//   reads the sampled velocity as the undisturbed one (written once here, not at every sub-step).
#include "systems/system.hpp"

namespace riffle {

class SolidDragLaw final : public System {
 public:
  explicit SolidDragLaw(const Model& model);
  std::string_view name() const override { return "solid_drag_law"; }
  Access access() const override {
    return {component_ids<GrainProperties, GrainVoidage, GrainSampledFluid>(), component_ids<GrainDrag>()};
  }
  void run(SystemContext& context) override;

 private:
  CouplingModel model_;
  double density_;    ///< [kg/m^3] the water's, of either fluid family
  double viscosity_;  ///< [Pa s] dynamic
};

}  // namespace riffle
