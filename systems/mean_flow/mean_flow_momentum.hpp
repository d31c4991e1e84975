#pragma once
// Advances the mean-flow fluid's column by one engine step (systems/physics/mean_flow/column.hpp): the eddy
// viscosity of the closure from the last velocities, the drive of this step (a body force, a lid, a profile forcing along x), the grains' drag impulse of the last
// step taken from the water, and one implicit step of each horizontal velocity component. Runs first in the step,
// so the grains' sub-steps read the water this step leaves (solid_mean_flow_sampling).
#include "systems/physics/mean_flow/column_model.hpp"
#include "systems/system.hpp"

namespace riffle {

class MeanFlowMomentum final : public System {
 public:
  explicit MeanFlowMomentum(const Model& model);
  std::string_view name() const override { return "mean_flow_momentum"; }
  Access access() const override { return {{}, component_ids<MeanFlowColumn>()}; }
  void run(SystemContext& context) override;

 private:
  const MeanFlowModel& model_;
  double gravity_;  ///< [m/s^2] |g_z|, for the Shields drive
  ColumnGrid grid_;
  ColumnEnds ends_x_, ends_y_;
  std::vector<double> target_;  ///< [m/s] the profile forcing's target per cell along x (empty without one)
  std::vector<double> target_y_;  ///< [m/s] and along y: at rest (the forcing pulls the whole velocity, seed 003 Eq. 25)
};

}  // namespace riffle
