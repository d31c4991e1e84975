#pragma once
// Pressure correction (seed 000 Eqs. 8-12; numerics 2.6-2.7, amendment 1): GC gradient with the wall pressure
// extrapolated per pair, p_j = p_i + rho (g - a_tank) . r_ij, plus repulsive DS; then
// u^{k+1} = u* - dt/rho grad p + du_DS and r^{k+1} = r* + dt (u^{k+1} - u*).
#include <vector>

#include "engine/core/system.hpp"
#include "systems/physics/mps_common.hpp"

namespace riffle {

class FluidCorrect final : public System {
 public:
  explicit FluidCorrect(const FluidModel& fluid) : fluid_(fluid), constants_(MpsConstants::from(fluid)) {}
  std::string_view name() const override { return "fluid_correct"; }
  Access access() const override {
    return {component_ids<FluidNeighbours, ParticlePrediction>(), component_ids<ParticleState, ParticlePressure>()};
  }
  void run(SystemContext& context) override;

 private:
  FluidModel fluid_;
  MpsConstants constants_;
};

/// GC matrix C = (D A)^{-1} from the moment sum_j w_ij r_ij r_ij^T / r_ij^2 and n_i = sum_j w_ij, with the inversion
/// safety of numerics 2.6: the identity when n_i < 0.5 n0, det(D A) < 0.05 or lambda_min(D A) < 0.2.
Eigen::Matrix3d gradient_correction_matrix(const Eigen::Matrix3d& moment, double density, double reference_density);

}  // namespace riffle
