#include "systems/physics/geometry/domain.hpp"

#include "systems/physics/geometry/tank_kinematics.hpp"

namespace riffle {

DomainBox domain_box(const Model& model) {
  const TankModel& tank = model.tank;
  const Vec3 sweep = tank_motion_sweep(tank.motion);
  const Vec3 margin = Vec3::Constant(tank.domain_margin) + sweep;
  return {tank.origin - margin, tank.origin + tank.size + margin};
}

DomainBox grain_domain_box(const Model& model) {
  DomainBox domain = domain_box(model);
  for (int axis = 0; axis < 3; ++axis)
    if (model.tank.periodic[static_cast<std::size_t>(axis)]) {
      domain.low[axis] = model.tank.origin[axis] - model.tank.size[axis];
      domain.high[axis] = model.tank.origin[axis] + 2.0 * model.tank.size[axis];
    }
  return domain;
}

double distance_outside_box(const Vec3& low, const Vec3& high, const Vec3& point) {
  const Vec3 gap = (low - point).cwiseMax(point - high).cwiseMax(Vec3::Zero());
  return gap.norm();
}

FluidEscapeKind fluid_escape_kind(const Vec3& position, const Vec3& velocity, double number_density,
                                  const DomainBox& domain, const Vec3& tank_low, const Vec3& tank_high,
                                  double escape_distance) {
  // A NaN is a bug: it stays in the table, and fluid_checks stops the run naming it.
  if (!position.allFinite() || !velocity.allFinite()) return FluidEscapeKind::kNone;
  if (!domain.contains(position)) return FluidEscapeKind::kLeftDomain;
  // The Wendland weight is positive inside r_e and 0 at it: n = 0 exactly when no other particle is within r_e.
  if (number_density == 0.0 && distance_outside_box(tank_low, tank_high, position) > escape_distance)
    return FluidEscapeKind::kFlewFree;
  return FluidEscapeKind::kNone;
}

}  // namespace riffle
