#pragma once
// Drag on every grain at every sub-step (seed 000 Eqs. 20-25; numerics.md 5.1, 5.6 step 8): from the fluid velocity
// and voidage sampled at the last fluid step (solid_fluid_sampling) and the grain's current velocity. The drag is
// also integrated over the sub-steps (drag_impulse), so the fluid can take back exactly what the grains received
// (fluid_drag_reaction). With coupling.self_induced_velocity, the drag uses the undisturbed velocity: the sampled
// one less the grain's own disturbance (systems/physics/coupling/self_induced.hpp), solved together with the drag.
#include <algorithm>
#include <array>
#include <vector>

#include "systems/physics/coupling/drag_law.hpp"
#include "systems/physics/coupling/sampling_kernel.hpp"
#include "systems/system.hpp"

namespace riffle {

/// The self-induced correction holds for dilute grains: at or below this voidage (Ergun's branch, a bed) the
/// water's answer to a grain's drag is screened by its neighbours, and the drag laws already refer to the mean
/// pore velocity.
inline constexpr double kSelfInducedMinVoidage = 0.8;

/// Whether the self-induced correction acts on a grain: it has water around it (`fluid_weight` > 0) and is dilute.
inline bool carries_self_induced_disturbance(const CouplingModel& coupling, double fluid_weight, double voidage) {
  return coupling.self_induced_velocity && fluid_weight > 0.0 && voidage > kSelfInducedMinVoidage;
}

/// [m] A grain's coupling kernel (coupling_kernel_radius): the dilute grain's where the self-induced correction is on
/// (`self_induced`) and would act at this voidage, whether the grain is in the water or not (the sampling decides
/// before the water is read).
inline double grain_kernel_radius(bool self_induced, double radius, double effective_radius, double spacing,
                                  double voidage) {
  return coupling_kernel_radius(radius, effective_radius, spacing, self_induced && voidage > kSelfInducedMinVoidage);
}

/// [kg / (m^3 s)] mu / l_B^2: the other grains' resistance to the water around a grain (Brinkman 1947), (1 - eps)
/// times the drag per grain volume at the slip speed `relative_speed` (the undisturbed water's), over the flux share.
/// It ends a grain's history memory after l_B^2 / nu (the history force). (The self-induced correction's share in a
/// suspension is not this screening: settling grains carry fixed forces; self_induced_suspension_share.) Zero for a
/// lone grain, and with the cloud-in-cell voidage, which counts the grain's own volume (a lone grain would screen
/// itself).
inline double suspension_resistance_per_volume(const CouplingModel& coupling, double voidage, double diameter,
                                               double relative_speed, double flux_share, double density,
                                               double viscosity) {
  if (coupling.voidage_estimate != CouplingModel::VoidageEstimate::kSelfCorrected) return 0.0;
  const double solid_fraction = std::max(0.0, 1.0 - voidage);
  if (solid_fraction <= 0.0) return 0.0;
  return solid_fraction *
         drag_per_volume(voidage, diameter, relative_speed / flux_share, density, viscosity, coupling) / flux_share;
}

/// A grain without the correction: no disturbance in any mode or wall lag, and no undisturbed velocity.
void clear_self_induced_disturbance(GrainDrag& drag, std::size_t grain);

/// The grain's own disturbance as the correction carried it from its last sub-step: the modes' and the walls' lags
/// summed (the sampled velocity less this is the undisturbed water, before this sub-step's update).
inline Vec3 carried_self_induced_disturbance(const GrainDrag& drag, std::size_t grain) {
  return drag.self_induced_fast[grain] + drag.self_induced_middle[grain] + drag.self_induced_slow[grain] +
         drag.self_induced_wall_x[grain] + drag.self_induced_wall_y[grain] + drag.self_induced_wall_z[grain];
}

/// The forces besides the drag that the grain handed the water with its drag impulse over its last sub-step: the
/// added-mass force (both implicit parts, as the last half kick applied it) and the history force's memory
/// (solid_integrate adds their impulse to drag_impulse; zero when off). Their reaction disturbs the water as the
/// drag's does, so what the correction takes out of the water the grain reads includes them.
inline Vec3 inertial_reaction_force(const GrainAddedMass& added, std::size_t grain) {
  return added.added_mass_force[grain] + added.history_force[grain];
}

class SolidDrag final : public System {
 public:
  explicit SolidDrag(const Model& model);
  std::string_view name() const override { return "solid_drag"; }
  Access access() const override {
    return {component_ids<GrainState, GrainProperties, GrainSampledFluid, GrainVoidage, GrainAddedMass>(),
            component_ids<GrainDrag>()};
  }
  void run(SystemContext& context) override;

 private:
  void drag_without_own_disturbance(std::size_t grain, const GrainState& grains, const GrainProperties& properties,
                                    const GrainSampledFluid& sampled, double voidage, double flux_share, double dt,
                                    double fluid_step, const Vec3& tank_shift, const Vec3& inertial_force,
                                    GrainDrag& drag);

  /// The walls' part of the disturbance: the tank's faces that hold the water (not open, not periodic) along each
  /// axis, and where they stand at rest.
  struct TankFaces {
    std::array<std::array<bool, 2>, 3> wall{};  ///< [axis][0 low, 1 high]
    Vec3 low = Vec3::Zero(), high = Vec3::Zero();
  };
  static TankFaces tank_faces(const Model& model);

  CouplingModel model_;
  TankModel tank_;
  TankFaces faces_;
  FluidModel fluid_;         ///< the MPS water's model (the self-induced velocity's kernel)
  double density_;           ///< [kg/m^3] the water's, of either fluid family
  double kinematic_viscosity_;  ///< [m^2/s]
  double effective_radius_;  ///< [m] r_e of the MPS water (FluidModel::constants); 0 with the mean-flow fluid
  double spacing_;           ///< [m] l0 of the MPS water (a dilute grain's kernel, coupling_kernel_radius)
  double fluid_step_;        ///< [s] run.dt, the fluid step before the first (SystemContext::fluid_step)
  double inverse_distance_;  ///< R <1/r> of the spreading and sampling kernels (self_induced.hpp)
};

}  // namespace riffle
