#pragma once
// End-of-step checks and reductions over the fluid: the first non-finite particle, or with [fluid] escape = "stop" the
// first one outside the domain, stops the run with a diagnosis, and so does a removed count (fluid_escape) above
// fluid.escape_fraction_limit of the water laid out; FluidSummary (count, energy, speed, mean n/n0, volume) feeds
// diagnostics.csv and the time-step control.
#include <vector>

#include "systems/system.hpp"
#include "systems/physics/mps/mps_common.hpp"
#include "systems/physics/ranks/rank_comm.hpp"

namespace riffle {

class FluidChecks final : public System {
 public:
  /// Over MPI ranks (the water spread over them) the summary's totals are summed over all the ranks.
  explicit FluidChecks(const FluidModel& fluid) : constants_(mps_constants(fluid)), over_ranks_(ranks::distributed()) {}
  std::string_view name() const override { return "fluid_checks"; }
  Access access() const override {
    return {component_ids<ParticleState, ParticleDensity>(), component_ids<FluidSummary, StepStatus>()};
  }
  void run(SystemContext& context) override;

 private:
  MpsConstants constants_;
  bool over_ranks_ = false;
};

}  // namespace riffle
