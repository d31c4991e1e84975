#pragma once
// ECS input at the step start (seed 000 Eq. 6; numerics 2.3): (|e| Dn/Dt + |Dn/Dt| e) with e = (n^k - n0)/n0
// and Dn/Dt the HS rate at (r^k, u^k), fluid-wall pairs counted twice (no wall row takes their half).
#include <vector>

#include "engine/system.hpp"
#include "systems/fluid_common.hpp"

namespace riffle {

class FluidEcsSource final : public System {
 public:
  explicit FluidEcsSource(const FluidModel& fluid) : constants_(MpsConstants::from(fluid)) {}
  std::string_view name() const override { return "fluid_ecs_source"; }
  Access access() const override { return {{ComponentId::kFluidNeighbours}, {ComponentId::kFluid}}; }
  void run(SystemContext& context) override;

 private:
  MpsConstants constants_;
};

}  // namespace riffle
