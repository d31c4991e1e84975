#include "engine/setup/mean_flow_column.hpp"

#include <cmath>

#include "systems/physics/mean_flow/column_model.hpp"

namespace riffle {

namespace {
/// [m/s] The friction velocity of a steady drive along +x, sqrt(f (top - z_bed)); 0 for a sinusoidal one or none.
double drive_friction_velocity(const MeanFlowModel& flow, double body_force, double bed_surface) {
  if (flow.body_force.kind == BodyForceModel::Kind::kSinusoidal) return 0.0;
  return body_force > 0.0 ? std::sqrt(body_force * (flow.top - bed_surface)) : 0.0;
}
}  // namespace

MeanFlowColumn initial_column(const Model& model, const Solids* grains) {
  const MeanFlowModel& flow = model.mean_flow;
  const ColumnGrid grid = column_grid(flow);
  MeanFlowColumn column;
  column.velocity_x.assign(grid.cells, 0.0);
  column.velocity_y.assign(grid.cells, 0.0);
  column.solid_fraction.assign(grid.cells, 0.0);
  column.impulse_x.assign(grid.cells, 0.0);
  column.impulse_y.assign(grid.cells, 0.0);
  column.eddy_viscosity.assign(grid.cells + 1, 0.0);
  column.bed_surface = grid.bottom;
  if (grains && grains->size() > 0) {
    std::vector<double> scratch;
    fill_solid_fraction(model, *grains, *grains, column, scratch);
  }
  const double bed = column.bed_surface;
  column.body_force = mean_flow_body_force(flow, std::abs(model.gravity.z()), bed, 0.0);
  if (flow.initial == MeanFlowModel::Initial::kTargetProfile) {
    column.velocity_x = profile_forcing_target(flow);  // the forcing's own profile (0 in and below the bed's base)
    return column;
  }
  if (flow.initial != MeanFlowModel::Initial::kLogLaw) return column;
  if (flow.top_boundary == MeanFlowModel::Top::kLid) {
    for (std::size_t i = 0; i < grid.cells; ++i) {
      const double above = grid.centre(i) - bed;
      if (above > 0.0) column.velocity_x[i] = flow.lid_velocity * above / (flow.top - bed);
    }
    // The linear profile's stress, so that the first step's closure sees walls that carry one (van Driest's damping
    // of a wall without stress would leave the first step laminar).
    column.top_stress = flow.density * flow.kinematic_viscosity * flow.lid_velocity / (flow.top - bed);
    column.floor_stress = column.top_stress;
    return column;
  }
  const double friction = drive_friction_velocity(flow, column.body_force, bed);
  if (!(friction > 0.0)) return column;
  double z0 = flow.initial_roughness_length;
  if (!(z0 > 0.0) && flow.shields_diameter > 0.0) z0 = 2.5 * flow.shields_diameter / 30.0;
  if (!(z0 > 0.0) && flow.closure.floor == MixingLengthClosure::Floor::kRough) z0 = flow.closure.roughness / 30.0;
  if (!(z0 > 0.0)) z0 = flow.kinematic_viscosity / (9.0 * friction);
  const double kappa = flow.closure.von_karman;
  for (std::size_t i = 0; i < grid.cells; ++i) {
    const double above = grid.centre(i) - bed;
    if (above > 0.0) column.velocity_x[i] = friction / kappa * std::log(1.0 + above / z0);
  }
  column.floor_stress = flow.density * friction * friction;
  return column;
}

}  // namespace riffle
