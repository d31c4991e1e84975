#pragma once
// Pressure correction (seed 000 Eqs. 8-12; numerics 2.6-2.7, amendment 1): GC gradient with the wall pressure
// extrapolated per pair, p_j = p_i + rho (g - a_tank) . r_ij (or the classic, or a momentum-conserving form,
// [fluid.schemes]), plus repulsive DS; then
// u^{k+1} = u* - dt/rho grad p + du_DS and r^{k+1} = r* + dt (u^{k+1} - u*).
#include <stdexcept>
#include <vector>

#include "systems/system.hpp"
#include "systems/physics/mps/mps_common.hpp"

namespace riffle {

class FluidCorrect final : public System {
 public:
  explicit FluidCorrect(const FluidModel& fluid)
      : fluid_(fluid), constants_(mps_constants(fluid)), kernel_(constants_.effective_radius) {
    // The scene reader refuses both; a model built in code must not apply GC's C_i on top of the pair form.
    if (fluid.schemes.conservative_gradient && fluid.schemes.gradient_correction)
      throw std::logic_error("fluid_correct: conservative_gradient replaces the gradient correction: turn gc off");
  }
  std::string_view name() const override { return "fluid_correct"; }
  // A bulk-velocity body force is the controller's state: read from FluidSummary (fluid_predict), in those scenes only.
  Access access() const override {
    if (fluid_.body_force.kind == BodyForceModel::Kind::kBulkVelocity)
      return {component_ids<FluidNeighbours, ParticlePrediction, FluidSummary>(),
              component_ids<ParticleState, ParticlePressure>()};
    return {component_ids<FluidNeighbours, ParticlePrediction>(), component_ids<ParticleState, ParticlePressure>()};
  }
  void run(SystemContext& context) override;

 private:
  FluidModel fluid_;
  MpsConstants constants_;
  WendlandKernel kernel_;
};

}  // namespace riffle
