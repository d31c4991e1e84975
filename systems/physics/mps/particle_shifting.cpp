#include "systems/physics/mps/particle_shifting.hpp"

#include <cmath>

namespace riffle {

double shifting_diffusivity(ShiftingLaw law, double coefficient, double smoothing_length, double speed, double dt) {
  if (law == ShiftingLaw::kConstant) return coefficient * smoothing_length * smoothing_length;
  return coefficient * smoothing_length * std::abs(speed) * dt;
}

Vec3 fickian_shift(double diffusivity, const Vec3& concentration_gradient, double max_length) {
  Vec3 shift = -diffusivity * concentration_gradient;
  const double length = shift.norm();
  if (length > max_length && length > 0.0) shift *= max_length / length;
  return shift;
}

Vec3 shift_off_wall(const Vec3& shift, const Vec3& offset) {
  const double length = offset.norm();
  if (length == 0.0) return shift;
  const Vec3 direction = offset / length;
  const double toward = shift.dot(direction);
  return toward > 0.0 ? Vec3(shift - toward * direction) : shift;
}

Vec3 tangential_shift(const Vec3& shift, const Vec3& normal) { return shift - normal.dot(shift) * normal; }

Vec3 nearest_image_difference(const PeriodicBox& box, const Vec3& difference) {
  Vec3 nearest = difference;
  for (int axis = 0; axis < 3; ++axis)
    if (box.periodic[static_cast<std::size_t>(axis)] && box.length[axis] > 0.0)
      nearest[axis] -= box.length[axis] * std::round(difference[axis] / box.length[axis]);
  return nearest;
}

}  // namespace riffle
