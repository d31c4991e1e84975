#pragma once
// The mean-flow column as a scene lays it out (components/model.hpp MeanFlowModel): its grid, what bounds it, its
// drive, the plan area it stands for and the grains' solid fraction in it. Pure functions of the model and the
// grains: the systems (systems/mean_flow, systems/coupling), the set-up and the probes call the same ones.
#include <vector>

#include "components/mean_flow.hpp"
#include "components/model.hpp"
#include "components/solids.hpp"
#include "systems/physics/mean_flow/column.hpp"

namespace riffle {

/// The column's grid as the model lays it out.
ColumnGrid column_grid(const MeanFlowModel& model);
/// What bounds the column along x and along y: the floor at rest; a lid moving along x, or a free top.
ColumnEnds column_ends(const MeanFlowModel& model, bool along_x);
/// [m/s^2] The body force on the water at `time` with the bed surface at `bed_surface`: the Shields drive's
/// Theta (rho_s - rho) g d / (rho (top - z_bed)), else the prescribed body force (constant or sinusoidal).
double mean_flow_body_force(const MeanFlowModel& model, double gravity, double bed_surface, double time);
/// [m/s] The profile forcing's target at each cell centre (empty without one): velocity ((z - base) / (top -
/// base))^exponent above base, 0 at and below it.
std::vector<double> profile_forcing_target(const MeanFlowModel& model);
/// [Pa] The profile forcing's pull on the water above the bed surface, per plan area: the sum over the cells (the
/// part of each above the bed) of rho eps h k (u_target - u) with the column's velocity; 0 without a forcing.
double profile_forcing_stress(const MeanFlowModel& model, const MeanFlowColumn& column);
/// [m^2] The plan area the column stands for: the periodic box's x by y.
double column_plan_area(const Model& model);

/// [Pa] The stress the water above the bed carries into it: its drive over the depth above the bed surface, the
/// lid's traction and the profile forcing's pull above the bed, rho f (top - z_bed) + tau_lid + that pull (the
/// momentum balance of the water above the bed).
double column_bed_stress(const MeanFlowModel& model, const MeanFlowColumn& column);
/// The grains' solid fraction per cell (each sphere's exact volume between the cells' faces over the cell's volume,
/// at most 1 - coupling.min_voidage) and the bed surface, into `column`; `scratch` is reused. Grains in slot order:
/// the sums do not depend on the thread count.
void fill_solid_fraction(const Model& model, const GrainState& grains, const GrainProperties& properties,
                         MeanFlowColumn& column, std::vector<double>& scratch);

}  // namespace riffle
