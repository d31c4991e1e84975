#pragma once
// Explicit prediction (seed 000 Eq. 2; numerics 2.1): u* = u^k + dt (nu lap u + g), r* = r^k + dt u*, with the
// lambda0 Laplacian (numerics 1.4); wall and dummy particles carry the wall velocity (no slip).
// With ECS on (seed 000 Eq. 6; numerics 2.3) the same pass over the neighbours at (r^k, u^k) also forms the ECS
// input |e| Dn/Dt + |Dn/Dt| e, with e = (n^k - n0)/n0 and Dn/Dt the HS rate, fluid-wall pairs counted twice (no
// wall row takes their half): both need the same pairs at the same state, and one pass instead of two saves about
// a tenth of the fluid step (docs/BENCHMARKS.md).
#include <vector>

#include "engine/core/system.hpp"
#include "systems/physics/mps_common.hpp"

namespace riffle {

class FluidPredict final : public System {
 public:
  explicit FluidPredict(const FluidModel& fluid) : fluid_(fluid), constants_(MpsConstants::from(fluid)) {}
  std::string_view name() const override { return "fluid_predict"; }
  Access access() const override {
    return {component_ids<FluidNeighbours>(), component_ids<ParticleState, ParticlePrediction, ParticleDragReaction>()};
  }
  void run(SystemContext& context) override;

 private:
  FluidModel fluid_;
  MpsConstants constants_;
  std::vector<Vec3> acceleration_;  ///< [m/s^2] scratch: the gather reads u^k while u* is formed
};

}  // namespace riffle
