#include "systems/mean_flow/mean_flow_momentum.hpp"

#include <algorithm>
#include <cmath>

namespace riffle {

MeanFlowMomentum::MeanFlowMomentum(const Model& model)
    : model_(model.mean_flow),
      gravity_(std::abs(model.gravity.z())),
      grid_(column_grid(model.mean_flow)),
      ends_x_(column_ends(model.mean_flow, true)),
      ends_y_(column_ends(model.mean_flow, false)),
      target_(profile_forcing_target(model.mean_flow)),
      target_y_(target_.size(), 0.0) {}

void MeanFlowMomentum::run(SystemContext& context) {
  MeanFlowColumn& column = context.write<MeanFlowColumn>();
  const double nu = model_.kinematic_viscosity;
  if (model_.turbulence == MeanFlowModel::Turbulence::kMixingLength) {
    // The floor's friction velocity of the last step (van Driest's z+): lagged like the eddy viscosity itself, and
    // at least the friction velocity of the stress the water above the bed carries (the drive's and the lid's): under
    // a bed the floor carries almost none, and its viscous length nu A+ / u* would otherwise reach up through the bed
    // and damp the water above it.
    const double floor_friction_velocity =
        std::sqrt(std::max(std::abs(column.floor_stress), std::abs(column_bed_stress(model_, column))) / model_.density);
    const TopWall lid{model_.top_boundary == MeanFlowModel::Top::kLid,
                      std::sqrt(std::abs(column.top_stress) / model_.density)};
    const std::vector<double> lengths =
        mixing_lengths(grid_, column.solid_fraction, model_.closure, floor_friction_velocity, nu, lid);
    column.eddy_viscosity =
        eddy_viscosities(grid_, column.velocity_x, column.velocity_y, lengths, ends_x_, ends_y_);
  } else {
    column.eddy_viscosity.assign(grid_.cells + 1, 0.0);
  }
  column.body_force = mean_flow_body_force(model_, gravity_, column.bed_surface, context.time);
  ColumnStep step{model_.density, nu, context.dt, column.body_force};
  if (model_.profile_forcing.enabled) {
    step.relaxation_rate = model_.profile_forcing.rate();
    step.relaxation_target = &target_;
  }
  const ColumnStresses along_x =
      advance_column(grid_, column.solid_fraction, column.eddy_viscosity, column.impulse_x, ends_x_, step,
                     column.velocity_x);
  step.body_force = 0.0;  // the drive is along x
  step.relaxation_target = &target_y_;
  advance_column(grid_, column.solid_fraction, column.eddy_viscosity, column.impulse_y, ends_y_, step,
                 column.velocity_y);
  column.floor_stress = along_x.floor;
  column.top_stress = along_x.top;
  // The grains' impulse is taken: the drag reaction of this step's sub-steps refills it at the step's end.
  std::fill(column.impulse_x.begin(), column.impulse_x.end(), 0.0);
  std::fill(column.impulse_y.begin(), column.impulse_y.end(), 0.0);
  context.count_items(grid_.cells);
}

}  // namespace riffle
