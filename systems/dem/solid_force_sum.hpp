#pragma once
// solid_force_sum: each grain's force = contact + drag + pressure force (+ the viscous stress force and lubrication
// when the scene has them on),
// torque = contact torque. The one place the force sources meet, so that each source system writes only its own
// field.
#include "systems/system.hpp"

namespace riffle {

class SolidForceSum final : public System {
 public:
  /// `lubrication`: add GrainLubrication (read only then, so the step graph without it is unchanged).
  explicit SolidForceSum(bool lubrication = false) : lubrication_(lubrication) {}
  std::string_view name() const override { return "solid_force_sum"; }
  Access access() const override {
    Access access{component_ids<GrainContactForce, GrainDrag, GrainSampledFluid>(), component_ids<GrainTotalForce>()};
    if (lubrication_) access.reads.push_back(GrainLubrication::kId);
    return access;
  }
  void run(SystemContext& context) override;

 private:
  bool lubrication_;
};

}  // namespace riffle
