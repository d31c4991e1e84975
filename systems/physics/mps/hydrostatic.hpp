#pragma once
// The hydrostatic pressure field of a fluid at rest in the moving tank's frame (amendment 1): grad p = rho (g - a),
// a the tank's acceleration. fluid_correct carries a fluid particle's pressure along it to the wall and dummy
// particles of its support (so GC is exact for hydrostatics and the contact line sees p ~ 0); the pressure probes
// carry each fluid particle's pressure along it to the sensor (so a sensor on a wall, outside the fluid, reads).
#include "components/vec.hpp"

namespace riffle {

/// grad p of the fluid at rest in the tank frame [Pa/m]: density [kg/m^3] times (gravity - tank acceleration).
inline Vec3 hydrostatic_gradient(double density, const Vec3& gravity, const Vec3& tank_acceleration) {
  const Vec3 body_acceleration = gravity - tank_acceleration;
  return density * body_acceleration;
}

/// The pressure `offset` away from a point at `pressure`, along the hydrostatic field `gradient`.
inline double hydrostatic_extrapolation(double pressure, const Vec3& gradient, const Vec3& offset) {
  return pressure + gradient.dot(offset);
}

}  // namespace riffle
