#pragma once
// Copies the water the grains sample (positions, velocities, pressure gradients of the fluid particles) into
// FluidSample before the step's two branches start (docs/COUPLING.md): the grains' branch then samples the water
// at the step start while the fluid's branch advances it beside them. About 1 MB at l0 = 5 mm, a tenth of a
// millisecond, against the sampling itself, which this takes off the end of the step.
#include "systems/system.hpp"

namespace riffle {

class FluidSampleCopy final : public System {
 public:
  /// `viscous_stress`: also copy the last prediction's nu <lap u> ([coupling] viscous_stress; ParticlePrediction is
  /// read only then, so the step graph without it is unchanged).
  explicit FluidSampleCopy(bool viscous_stress = false) : viscous_stress_(viscous_stress) {}
  std::string_view name() const override { return "fluid_sample_copy"; }
  Access access() const override {
    Access access{component_ids<ParticleState, ParticlePressure>(), component_ids<FluidSample>()};
    if (viscous_stress_) access.reads.push_back(ParticlePrediction::kId);
    return access;
  }
  void run(SystemContext& context) override;

 private:
  bool viscous_stress_;
};

}  // namespace riffle
