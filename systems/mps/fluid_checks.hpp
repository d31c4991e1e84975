#pragma once
// End-of-step checks and reductions over the fluid: the first non-finite particle, or with [fluid] escape = "stop" the
// first one outside the domain, stops the run with a diagnosis, and so does a removed count (fluid_escape) above
// fluid.escape_fraction_limit of the water laid out; FluidSummary (count, energy, speed, mean n/n0, volume) feeds
// diagnostics.csv and the time-step control.
#include <vector>

#include "systems/system.hpp"
#include "systems/physics/mps/mps_common.hpp"

namespace riffle {

class FluidChecks final : public System {
 public:
  explicit FluidChecks(const FluidModel& fluid) : constants_(mps_constants(fluid)) {}
  std::string_view name() const override { return "fluid_checks"; }
  Access access() const override {
    return {component_ids<ParticleState, ParticleDensity>(), component_ids<FluidSummary, StepStatus>()};
  }
  void run(SystemContext& context) override;

 private:
  MpsConstants constants_;
};

}  // namespace riffle
