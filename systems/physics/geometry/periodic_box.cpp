#include "systems/physics/geometry/periodic_box.hpp"

#include <algorithm>
#include <cmath>

namespace riffle {

bool PeriodicBox::inside(const Vec3& point) const {
  for (int axis = 0; axis < 3; ++axis)
    if (periodic[static_cast<std::size_t>(axis)] &&
        !(point[axis] >= low[axis] && point[axis] < low[axis] + length[axis]))
      return false;
  return true;
}

Vec3 PeriodicBox::wrap(const Vec3& point) const {
  Vec3 wrapped = point;
  for (int axis = 0; axis < 3; ++axis) {
    if (!periodic[static_cast<std::size_t>(axis)] || !std::isfinite(point[axis])) continue;
    const double high = low[axis] + length[axis];
    double x = point[axis];
    // One period either way is the usual case (a grain moves far less than a period per sub-step); floor for more.
    if (x >= high) x -= length[axis];
    else if (x < low[axis]) x += length[axis];
    if (!(x >= low[axis] && x < high)) x -= length[axis] * std::floor((x - low[axis]) / length[axis]);
    // What is left is rounding (-1e-18 + L rounds to L, the one value the box excludes; L - L may round below
    // low): the point is then a rounding error away from the low face, which it becomes.
    if (!(x >= low[axis] && x < high)) x = low[axis];
    wrapped[axis] = x;
  }
  return wrapped;
}

int PeriodicBox::image_shifts(const Vec3& point, double cutoff, std::array<Vec3, 3>& shifts) const {
  // Per axis the one image that can come within cutoff: past the far face if near the low one, and back.
  std::array<double, 3> axis_shift{0.0, 0.0, 0.0};
  for (int axis = 0; axis < 3; ++axis) {
    if (!periodic[static_cast<std::size_t>(axis)]) continue;
    double& shift = axis_shift[static_cast<std::size_t>(axis)];
    if (point[axis] - low[axis] < cutoff) shift = length[axis];
    else if (low[axis] + length[axis] - point[axis] <= cutoff) shift = -length[axis];
  }
  int count = 0;
  // x alone, y alone, x and y (the corner image); z is never periodic (the scene refuses it).
  if (axis_shift[0] != 0.0) shifts[static_cast<std::size_t>(count++)] = Vec3(axis_shift[0], 0.0, 0.0);
  if (axis_shift[1] != 0.0) shifts[static_cast<std::size_t>(count++)] = Vec3(0.0, axis_shift[1], 0.0);
  if (axis_shift[0] != 0.0 && axis_shift[1] != 0.0)
    shifts[static_cast<std::size_t>(count++)] = Vec3(axis_shift[0], axis_shift[1], 0.0);
  return count;
}

double periodic_overshoot(const std::vector<Vec3>& positions, const PeriodicBox& box) {
  double overshoot = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    if (!box.periodic[static_cast<std::size_t>(axis)]) continue;
    const double low = box.low[axis], high = box.low[axis] + box.length[axis];
    for (const Vec3& point : positions)
      if (std::isfinite(point[axis])) overshoot = std::max({overshoot, low - point[axis], point[axis] - high});
  }
  return overshoot;
}

PeriodicBox periodic_box(const Model& model) {
  PeriodicBox box;
  box.low = model.tank.origin;
  box.length = model.tank.size;
  box.periodic = model.tank.periodic;
  return box;
}

bool periodic_cutoff_fits(const PeriodicBox& box, double cutoff) {
  for (int axis = 0; axis < 3; ++axis)
    if (box.periodic[static_cast<std::size_t>(axis)] && !(box.length[axis] > 2.0 * cutoff)) return false;
  return true;
}

void build_halo(const std::vector<Vec3>& positions, const std::vector<EntityId>& ids, const PeriodicBox& box,
                double cutoff, Halo& halo) {
  halo.clear();
  halo.real_count = static_cast<std::uint32_t>(positions.size());
  std::array<Vec3, 3> shifts;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const int count = box.any() ? box.image_shifts(positions[i], cutoff, shifts) : 0;
    for (int k = 0; k < count; ++k) {
      halo.owner.push_back(static_cast<std::uint32_t>(i));
      halo.owner_id.push_back(ids[i]);
      halo.shift.push_back(shifts[static_cast<std::size_t>(k)]);
    }
  }
  halo.valid = true;
}

std::vector<Vec3> periodic_image_shifts(const PeriodicBox& box) {
  std::vector<Vec3> shifts = {Vec3::Zero()};
  for (int axis = 0; axis < 3; ++axis) {
    if (!box.periodic[static_cast<std::size_t>(axis)]) continue;
    const std::size_t before = shifts.size();
    for (const double sign : {1.0, -1.0})
      for (std::size_t k = 0; k < before; ++k) {
        Vec3 shifted = shifts[k];
        shifted[axis] += sign * box.length[axis];
        shifts.push_back(shifted);
      }
  }
  return shifts;
}

}  // namespace riffle
