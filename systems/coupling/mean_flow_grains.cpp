#include "systems/coupling/mean_flow_grains.hpp"

#include <algorithm>
#include <cmath>

#include "systems/physics/mean_flow/column_model.hpp"
#include "systems/physics/coupling/drag_law.hpp"
#include "systems/physics/mean_flow/column.hpp"
#include "systems/physics/mean_flow/grain_forces.hpp"
#include "systems/physics/math/counter_random.hpp"
#include "systems/physics/ranks/rank_comm.hpp"

namespace riffle {

MeanFlowSolidFraction::MeanFlowSolidFraction(const Model& model) : model_(model) {}

void MeanFlowSolidFraction::run(SystemContext& context) {
  const GrainState& grains = context.read<GrainState>();
  fill_solid_fraction(model_, grains, context.read<GrainProperties>(), context.write<MeanFlowColumn>(), volume_);
  context.count_items(grains.size());
}

MeanFlowDragReaction::MeanFlowDragReaction(const Model& model) : model_(model) {}

void MeanFlowDragReaction::run(SystemContext& context) {
  const GrainState& grains = context.read<GrainState>();
  const GrainProperties& properties = context.read<GrainProperties>();
  GrainDrag& drag = context.write<GrainDrag>();
  MeanFlowColumn& column = context.write<MeanFlowColumn>();
  const ColumnGrid grid = column_grid(model_.mean_flow);
  const double area = column_plan_area(model_);
  slices_.assign(grid.cells, 0.0);
  // Over MPI ranks each rank's grains give their impulse to a local sum first, added to the column in rank order.
  std::vector<double> local_x, local_y;
  if (column.over_ranks) {
    local_x.assign(grid.cells, 0.0);
    local_y.assign(grid.cells, 0.0);
  }
  double* const impulse_x = column.over_ranks ? local_x.data() : column.impulse_x.data();
  double* const impulse_y = column.over_ranks ? local_y.data() : column.impulse_y.data();
  for (std::size_t grain = 0; grain < grains.size(); ++grain) {
    Vec3& impulse = drag.drag_impulse[grain];
    if (impulse.isZero(0.0)) continue;  // no water reached it (above the surface)
    // The grain's volume per cell, over the part of it inside the column: the shares sum to one, so the water
    // loses exactly the impulse the grain received.
    const double centre = grains.position[grain].z(), radius = properties.radius[grain];
    const double inside = deposit_sphere(grid, centre, radius, 1.0, slices_);
    if (inside > 0.0) {
      const CellSpan span = sphere_cells(grid, centre, radius);
      for (std::size_t i = span.first; i <= span.last; ++i) {
        const double share = slices_[i] / (inside * area);
        impulse_x[i] += share * impulse.x();
        impulse_y[i] += share * impulse.y();
        slices_[i] = 0.0;
      }
    }
    impulse = Vec3::Zero();
  }
  if (column.over_ranks) {
    local_x.insert(local_x.end(), local_y.begin(), local_y.end());
    const std::vector<double> total = ranks::sum_in_rank_order(local_x);
    for (std::size_t i = 0; i < grid.cells; ++i) {
      column.impulse_x[i] += total[i];
      column.impulse_y[i] += total[grid.cells + i];
    }
  }
  context.count_items(grains.size());
}

SolidMeanFlowSampling::SolidMeanFlowSampling(const Model& model) : model_(model) {}

void SolidMeanFlowSampling::run(SystemContext& context) {
  const GrainState& grains = context.read<GrainState>();
  const GrainProperties& properties = context.read<GrainProperties>();
  const MeanFlowColumn& column = context.read<MeanFlowColumn>();
  GrainSampledFluid& sampled = context.write<GrainSampledFluid>();
  GrainVoidage& voidages = context.write<GrainVoidage>();
  const MeanFlowModel& flow = model_.mean_flow;
  const ColumnGrid grid = column_grid(flow);
  const ColumnEnds ends_x = column_ends(flow, true), ends_y = column_ends(flow, false);
  const ColumnEnds fraction_ends;  // no grains below the floor; above the last centre the last value
  const double density = flow.density;
  const bool frame = flow.body_force.grains == BodyForceModel::Grains::kFrame;  // a Shields drive's slope too
  const bool pressure_gradient = !frame && flow.body_force.grains == BodyForceModel::Grains::kPressureGradient &&
                                 model_.coupling.pressure_gradient;
  const bool fluctuations = flow.fluctuations == MeanFlowModel::Fluctuations::kLangevin;
  const TurbulenceIntensities intensities;
  const auto mean_velocity = [&](double z) {
    return Vec3(profile_at(grid, column.velocity_x, z, ends_x), profile_at(grid, column.velocity_y, z, ends_y), 0.0);
  };
  for (std::size_t grain = 0; grain < grains.size(); ++grain) {
    const double z = grains.position[grain].z();
    // Out of the water (a free top), below the floor, or not a number (a grain blown up): no fluid forces.
    if (!(z >= grid.bottom && z <= grid.top())) {
      sampled.fluid_weight[grain] = 0.0;
      sampled.fluid_velocity[grain] = Vec3::Zero();
      sampled.pressure_force[grain] = Vec3::Zero();
      voidages.voidage[grain] = 1.0;
      continue;
    }
    sampled.fluid_weight[grain] = 1.0;
    sampled.fluid_velocity[grain] = mean_velocity(z);
    if (fluctuations) {
      // The Langevin state advances over the step that starts here (context.dt; 0 in the initial forces, which
      // leaves it), with draws named by the grain's id and the step: the same on any thread count and after a resume.
      const TurbulentShear shear = turbulent_shear_at(grid, column, ends_x, ends_y, z);
      Vec3& state = sampled.fluctuation_state[grain];
      state = advance_langevin(state, context.dt, lagrangian_time_scale(shear.shear_rate, flow.langevin_c0, intensities),
                               counter_normals(flow.fluctuation_seed, context.step(), grains.id[grain]));
      sampled.fluid_velocity[grain] += fluctuation_velocity(state, shear, intensities);
    }
    const double solid = profile_at(grid, column.solid_fraction, z, fraction_ends);
    voidages.voidage[grain] = std::clamp(1.0 - solid, model_.coupling.min_voidage, 1.0);
    // -V grad p of the hydrostatic pressure, which holds the vertical gravity only (a slope's drive is a body force
    // on the water, not a pressure gradient).
    const double volume = grain_volume(properties.radius[grain]);
    Vec3 force = model_.coupling.pressure_gradient ? Vec3(0.0, 0.0, -volume * density * model_.gravity.z())
                                                   : Vec3::Zero();
    if (frame) force.x() += properties.mass[grain] * column.body_force;
    if (pressure_gradient) force.x() += volume * density * column.body_force;
    if (model_.coupling.lift) {
      // The mean flow's velocity at the grain's top and bottom (clamped to the column: a free top's last value).
      const double radius = properties.radius[grain];
      const Vec3& velocity = grains.velocity[grain];
      force.z() += shear_lift(density, model_.coupling.lift_coefficient, radius, mean_velocity(z + radius) - velocity,
                              mean_velocity(z - radius) - velocity);
    }
    sampled.pressure_force[grain] = force;
  }
  context.count_items(grains.size());
}

}  // namespace riffle
