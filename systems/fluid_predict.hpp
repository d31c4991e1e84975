#pragma once
// Explicit prediction (seed 000 Eq. 2; numerics 2.1): u* = u^k + dt (nu lap u + g), r* = r^k + dt u*, with the
// lambda0 Laplacian (numerics 1.4); wall and dummy particles carry the wall velocity (no slip).
#include <vector>

#include "engine/system.hpp"
#include "systems/fluid_common.hpp"

namespace riffle {

class FluidPredict final : public System {
 public:
  explicit FluidPredict(const FluidModel& fluid) : fluid_(fluid), constants_(MpsConstants::from(fluid)) {}
  std::string_view name() const override { return "fluid_predict"; }
  Access access() const override { return {{ComponentId::kFluidNeighbours}, {ComponentId::kFluid}}; }
  void run(SystemContext& context) override;

 private:
  FluidModel fluid_;
  MpsConstants constants_;
  std::vector<Vec3> acceleration_;  ///< [m/s^2] scratch: the gather reads u^k while u* is formed
};

}  // namespace riffle
