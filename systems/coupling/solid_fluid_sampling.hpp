#pragma once
// Samples the water at every grain once per fluid step (numerics.md 5.2-5.4, 5.6 step 7): the locally averaged
// fluid velocity (seed Eq. 23) and pressure gradient (Shepard averages with the Wendland kernel on
// R_I = d_I/2 + r_e) and the pressure force -V <grad p> (Eq. 13). It reads the water of the step start from
// FluidSample and runs first in the grains' branch (phase solid_step, docs/COUPLING.md), beside the fluid's step
// graph; the sub-steps then hold these fixed (solid_drag). The voidage is solid_voidage's. With added mass or the
// history force on, also the water's acceleration -<grad p>/rho + g (Maxey & Riley 1983). With
// [coupling] sampling_vertical_radius the kernel is an ellipsoid, R_v across the bed (docs/COUPLING.md, "A thin bed's
// sampling"; systems/physics/coupling/sampling_kernel.hpp).
#include "systems/system.hpp"
#include "systems/physics/geometry/cell_grid.hpp"
#include "systems/physics/mps/mps_common.hpp"

namespace riffle {

class SolidFluidSampling final : public System {
 public:
  explicit SolidFluidSampling(const Model& model);
  std::string_view name() const override { return "solid_fluid_sampling"; }
  Access access() const override {
    // With the self-induced correction, the pressure force loses the grain's own reaction (GrainDrag's last drag
    // with GrainAddedMass's added-mass and history forces, which the water took back with it; GrainVoidage's reading
    // of it), docs/COUPLING.md; the water's acceleration (added mass, history force) gains the other grains'
    // reaction, estimated from the drag and the voidage.
    // A bulk-velocity body force is the controller's state (FluidSummary, the last step's force), read only then.
    Access access{component_ids<FluidSample, GrainState, GrainProperties>(), component_ids<GrainSampledFluid>()};
    if (self_induced_velocity_ || fluid_acceleration_) {
      access.reads.push_back(component_id<GrainDrag>);
      access.reads.push_back(component_id<GrainVoidage>);
    }
    if (self_induced_velocity_ && pressure_gradient_) access.reads.push_back(component_id<GrainAddedMass>);
    if (body_force_.kind == BodyForceModel::Kind::kBulkVelocity) access.reads.push_back(component_id<FluidSummary>);
    return access;
  }
  void run(SystemContext& context) override;

 private:
  MpsConstants constants_;
  bool pressure_gradient_;  ///< the grains feel -V <grad p> (CouplingModel::pressure_gradient)
  bool viscous_stress_;     ///< the grains feel V rho <nu lap u> (CouplingModel::viscous_stress)
  bool fluid_acceleration_; ///< the water's acceleration is sampled (added mass or history force on)
  double density_;          ///< [kg/m^3] the water's
  bool self_induced_velocity_;  ///< CouplingModel::self_induced_velocity
  CouplingModel::FluidVelocity fluid_velocity_;  ///< the water took the drag over flux_share
  double vertical_radius_;      ///< [m] CouplingModel::sampling_vertical_radius: 0 = the isotropic kernel
  BodyForceModel body_force_;   ///< the water's body force and how the grains feel it (docs/COUPLING.md)
  double overlap_;              ///< R^3 <rho_s rho_w> (self_induced.hpp), with the correction on
  CellGrid fluid_grid_;
};

}  // namespace riffle
