#pragma once
// Advances the mean-flow fluid's column by one engine step (systems/physics/mean_flow/column.hpp): the eddy
// viscosity of the closure from the last velocities, the drive of this step, the grains' drag impulse of the last
// step taken from the water, and one implicit step of each horizontal velocity component. Runs first in the step,
// so the grains' sub-steps read the water this step leaves (solid_mean_flow_sampling).
#include "systems/physics/mean_flow/column.hpp"
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
};

/// The column's grid as the model lays it out.
ColumnGrid column_grid(const MeanFlowModel& model);
/// What bounds the column along x and along y: the floor at rest; a lid moving along x, or a free top.
ColumnEnds column_ends(const MeanFlowModel& model, bool along_x);
/// [m/s^2] The body force on the water at `time` with the bed surface at `bed_surface`: the Shields drive's
/// Theta (rho_s - rho) g d / (rho (top - z_bed)), else the prescribed body force (constant or sinusoidal).
double mean_flow_body_force(const MeanFlowModel& model, double gravity, double bed_surface, double time);

}  // namespace riffle
