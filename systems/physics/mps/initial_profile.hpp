#pragma once
// The water's initial velocity profile along x ([fluid.initial_velocity], docs/SCENES.md): a shear flow laid in at
// t = 0 so that a run under a moving lid does not spend its first seconds spinning the water up from rest (the
// laminar spin-up of a layer H deep takes ~H^2 / nu: 400 s for 2 cm of water). Pure function: engine/setup calls it
// and the unit tests call the same one.
#include "components/model.hpp"

namespace riffle {

/// u_x [m/s] of the profile at height z [m]: 0 at and below z0 = bottom; u_top at and above z1 = top; between,
/// kLinear: u_top (z - z0) / (z1 - z0) (plane Couette flow); kPower: u_top ((z - z0) / (z1 - z0))^exponent (seed
/// 003's Eq. 27 with exponent 1/7: the turbulent 1/7-power law of Prandtl, 1925). 0 for kNone.
double initial_profile_velocity(const InitialVelocityModel& profile, double z);

}  // namespace riffle
