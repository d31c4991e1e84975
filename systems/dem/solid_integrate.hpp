#pragma once
// Time integration of the grains with velocity Verlet (kick-drift-kick), split in two systems so that force
// systems run between them on the drifted positions:
//   solid_kick_drift: v += dt/2 (F/m + g); w += dt/2 T/I; x += dt v
//   (force systems: F, T at the new positions)
//   solid_kick:       v += dt/2 (F/m + g); w += dt/2 T/I
// For a constant force the scheme is exact, which the free-fall verification test relies on.
#include "engine/core/system.hpp"

namespace riffle {

class SolidKickDrift final : public System {
 public:
  std::string_view name() const override { return "solid_kick_drift"; }
  Access access() const override {
    return {component_ids<GrainProperties, GrainTotalForce>(), component_ids<GrainState>()};
  }
  void run(SystemContext& context) override;
};

class SolidKick final : public System {
 public:
  std::string_view name() const override { return "solid_kick"; }
  Access access() const override {
    return {component_ids<GrainProperties, GrainTotalForce>(), component_ids<GrainState>()};
  }
  void run(SystemContext& context) override;
};

}  // namespace riffle
