#pragma once
// The history (Basset) force on every grain, once per fluid step, right after the sampling (phase solid_step;
// docs/COUPLING.md, "Added mass and history force"):
//   F_H = 3/2 d^2 sqrt(pi rho mu) int K(t - tau) dw/dtau dtau,  w = u - v (the drag's slip),
// u the undisturbed water at the grain, as the drag's and the added mass's (Maxey & Riley 1983): with the
// self-induced correction on, the sampled velocity less the grain's own disturbance as the correction last carried it.
// with the windowed kernel K of BassetModes (systems/physics/coupling/added_mass.hpp): each mode's state advances exactly for
// a w that changed linearly since the last update. With Mei & Adrian's kernel (the default) each grain weights the
// modes by its own time scale t_H from its slip (MeiAdrianModeWeights). Dilute grains only (voidage above 0.8, as the
// self-induced correction): inside a bed the force is zero and the memory restarts when the grain leaves it. In a
// dilute suspension the other grains screen the memory after l_B^2 / nu (Brinkman; suspension_resistance_per_volume). The states are grain fields (GrainAddedMass), so they follow the
// grains through reorderings and checkpoints. The force is held over the step's sub-steps; the kicks add it to the
// grain's force and to its drag impulse, which the water takes back.
#include "systems/system.hpp"
#include "systems/physics/coupling/added_mass.hpp"

namespace riffle {

class SolidHistoryForce final : public System {
 public:
  explicit SolidHistoryForce(const Model& model);
  std::string_view name() const override { return "solid_history_force"; }
  Access access() const override {
    return {component_ids<GrainState, GrainProperties, GrainSampledFluid, GrainVoidage, GrainDrag>(),
            component_ids<GrainAddedMass>()};
  }
  void run(SystemContext& context) override;

 private:
  BassetModes modes_;
  MeiAdrianModeWeights finite_reynolds_;  ///< Mei & Adrian's weights per t_H (history_kernel = "mei_adrian")
  bool basset_kernel_;                    ///< history_kernel = "basset": the modes' own weights for every grain
  double kinematic_viscosity_;            ///< [m^2/s]
  double density_;           ///< [kg/m^3]
  double viscosity_;         ///< [Pa s]
  CouplingModel::FluidVelocity fluid_velocity_;  ///< the slip is (u - v) / flux_share, as the drag's
  CouplingModel coupling_;  ///< which grains carry the self-induced correction: u less their own disturbance
};

}  // namespace riffle
