#pragma once
// Time integration of the grains with velocity Verlet (kick-drift-kick), split in two systems so that force
// systems run between them on the drifted positions:
//   solid_kick_drift: v += dt/2 (F/m + g); w += dt/2 T/I; x += dt v
//   (force systems: F, T at the new positions)
//   solid_kick:       v += dt/2 (F/m + g); w += dt/2 T/I
// For a constant force the scheme is exact, which the free-fall verification test relies on. A fixed grain
// (GrainProperties::fixed, a rough floor) skips the kicks and drifts with the tank, as the whole bed does while held.
//
// With [coupling] added_mass, a wet grain's half kicks are implicit in its added mass m_a = C_a(eps) rho V
// (docs/COUPLING.md, "Added mass and history force"): (m + m_a) dv/dt = F + m g + m_a a_f, a_f the water's
// acceleration sampled at the step start. With history_force, the history force of the step start (written by
// solid_history_force) is added to F. Either way the kicks add what these two forces gave the grain to its drag
// impulse, which the water takes back (fluid_drag_reaction), so momentum stays closed.
#include "systems/system.hpp"

namespace riffle {

/// What the kicks need to know of the coupling's inertial forces.
struct KickSettings {
  bool added_mass = false;    ///< implicit added mass (CouplingModel::added_mass)
  bool history = false;       ///< add GrainAddedMass::history_force (CouplingModel::history_force)
  CouplingModel::FluidVelocity fluid_velocity = CouplingModel::FluidVelocity::kPore;  ///< stable_added_mass_coefficient
  double fluid_density = 0.0; ///< [kg/m^3]
  static KickSettings from(const Model& model);
  bool any() const { return added_mass || history; }
};

class SolidKickDrift final : public System {
 public:
  explicit SolidKickDrift(const Model& model) : settings_(KickSettings::from(model)) {}
  std::string_view name() const override { return "solid_kick_drift"; }
  Access access() const override;
  void run(SystemContext& context) override;

 private:
  KickSettings settings_;
};

class SolidKick final : public System {
 public:
  explicit SolidKick(const Model& model) : settings_(KickSettings::from(model)) {}
  std::string_view name() const override { return "solid_kick"; }
  Access access() const override;
  void run(SystemContext& context) override;

 private:
  KickSettings settings_;
};

}  // namespace riffle
