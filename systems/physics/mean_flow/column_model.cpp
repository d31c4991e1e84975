#include "systems/physics/mean_flow/column_model.hpp"

#include "systems/physics/ranks/rank_comm.hpp"

#include <algorithm>
#include <cmath>

namespace riffle {

ColumnGrid column_grid(const MeanFlowModel& model) { return {model.bottom, model.cell_size, model.cells}; }

ColumnEnds column_ends(const MeanFlowModel& model, bool along_x) {
  ColumnEnds ends;
  ends.top_given = model.top_boundary == MeanFlowModel::Top::kLid;
  ends.top_value = along_x ? model.lid_velocity : 0.0;
  return ends;
}

double mean_flow_body_force(const MeanFlowModel& model, double gravity, double bed_surface, double time) {
  if (model.shields_number > 0.0) {
    // The slope whose weight, carried by the water above the bed, is the bed shear stress of the Shields number.
    const double depth = std::max(model.top - bed_surface, model.cell_size);
    const double stress = model.shields_number * (model.shields_density - model.density) * gravity *
                          model.shields_diameter;
    return stress / (model.density * depth);
  }
  return model.body_force.prescribed(time);
}

std::vector<double> profile_forcing_target(const MeanFlowModel& model) {
  const MeanFlowModel::ProfileForcing& forcing = model.profile_forcing;
  if (!forcing.enabled) return {};
  const ColumnGrid grid = column_grid(model);
  std::vector<double> target(grid.cells, 0.0);
  const double span = model.top - forcing.base;
  for (std::size_t i = 0; i < grid.cells; ++i) {
    const double above = grid.centre(i) - forcing.base;
    if (above > 0.0) target[i] = forcing.velocity * std::pow(above / span, forcing.exponent);
  }
  return target;
}

double profile_forcing_stress(const MeanFlowModel& model, const MeanFlowColumn& column) {
  if (!model.profile_forcing.enabled) return 0.0;
  const ColumnGrid grid = column_grid(model);
  const std::vector<double> target = profile_forcing_target(model);
  const double rate = model.profile_forcing.rate();
  double pull = 0.0;
  for (std::size_t i = 0; i < grid.cells; ++i) {
    const double above_bed = std::clamp(grid.face(i + 1) - column.bed_surface, 0.0, grid.cell_height);
    if (above_bed <= 0.0) continue;
    const double water = 1.0 - (column.solid_fraction.empty() ? 0.0 : column.solid_fraction[i]);
    pull += model.density * water * above_bed * rate * (target[i] - column.velocity_x[i]);
  }
  return pull;
}

double column_plan_area(const Model& model) { return model.tank.size.x() * model.tank.size.y(); }

void fill_solid_fraction(const Model& model, const GrainState& grains, const GrainProperties& properties,
                         MeanFlowColumn& column, std::vector<double>& scratch) {
  const ColumnGrid grid = column_grid(model.mean_flow);
  scratch.assign(grid.cells, 0.0);
  for (std::size_t grain = 0; grain < grains.size(); ++grain)
    deposit_sphere(grid, grains.position[grain].z(), properties.radius[grain], 1.0, scratch);
  if (column.over_ranks) scratch = ranks::sum_in_rank_order(scratch);  // every rank's grains
  const double cell_volume = column_plan_area(model) * grid.cell_height;
  // The water keeps at least min_voidage of a cell (the drag law's own bound): the overlaps of a compressed bed
  // cannot leave a cell without water.
  const double most = 1.0 - model.coupling.min_voidage;
  column.solid_fraction.resize(grid.cells);
  for (std::size_t i = 0; i < grid.cells; ++i) column.solid_fraction[i] = std::min(scratch[i] / cell_volume, most);
  column.bed_surface = bed_surface(grid, column.solid_fraction);
}

double column_bed_stress(const MeanFlowModel& model, const MeanFlowColumn& column) {
  return model.density * column.body_force * (model.top - column.bed_surface) + column.top_stress +
         profile_forcing_stress(model, column);
}

}  // namespace riffle
