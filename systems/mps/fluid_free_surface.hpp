#pragma once
// Number density n* at the predicted positions and the free-surface flag n* < beta n0 (seed 000 Eq. 4;
// numerics 3.4 with beta = 0.93 from the amendments). Only fluid particles: walls are never surface particles.
// The same pass records which Verlet neighbours lie within r_e at r*, so the pressure solve and the correction
// visit only those.
#include <vector>

#include "systems/system.hpp"
#include "systems/physics/mps/mps_common.hpp"

namespace riffle {

class FluidFreeSurface final : public System {
 public:
  explicit FluidFreeSurface(const FluidModel& fluid)
      : constants_(mps_constants(fluid)), kernel_(constants_.effective_radius), threshold_(fluid.surface_threshold) {}
  std::string_view name() const override { return "fluid_free_surface"; }
  Access access() const override {
    return {component_ids<ParticleState, ParticlePrediction>(), component_ids<ParticleDensity, FluidNeighbours>()};
  }
  void run(SystemContext& context) override;

 private:
  MpsConstants constants_;
  WendlandKernel kernel_;
  double threshold_;
};

}  // namespace riffle
