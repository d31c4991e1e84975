#pragma once
// solid_force_sum: each grain's force = contact + drag + pressure force, torque = contact torque. The one place the
// force sources meet, so that each source system writes only its own field.
#include "engine/core/system.hpp"

namespace riffle {

class SolidForceSum final : public System {
 public:
  std::string_view name() const override { return "solid_force_sum"; }
  Access access() const override {
    return {component_ids<GrainContactForce, GrainDrag, GrainSampledFluid>(), component_ids<GrainTotalForce>()};
  }
  void run(SystemContext& context) override;
};

}  // namespace riffle
