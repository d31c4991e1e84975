#include "systems/physics/ranks/coupling_ranks.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "systems/physics/ranks/rank_boxes.hpp"
#include "systems/physics/ranks/rank_comm.hpp"

namespace riffle {

bool near_part(const Vec3& point, const PartBox& part, double reach, const PeriodicBox& box) {
  for (int axis = 0; axis < 3; ++axis) {
    const double low = part.low[axis] - reach, high = part.high[axis] + reach;
    const double x = point[axis];
    bool near = x >= low && x <= high;
    if (!near && box.periodic[static_cast<std::size_t>(axis)]) {
      const double period = box.length[axis];
      near = (x + period >= low && x + period <= high) || (x - period >= low && x - period <= high);
    }
    if (!near) return false;
  }
  return true;
}

std::vector<std::vector<std::uint32_t>> indices_near_other_ranks(std::span<const Vec3> positions,
                                                                 const CouplingBoxes& boxes, const PeriodicBox& box) {
  const auto me = static_cast<std::size_t>(ranks::rank());
  std::vector<std::vector<std::uint32_t>> near(boxes.of_rank.size());
  for (std::size_t r = 0; r < boxes.of_rank.size(); ++r) {
    if (r == me) continue;
    for (std::size_t i = 0; i < positions.size(); ++i)
      for (const PartBox& part : boxes.of_rank[r])
        if (near_part(positions[i], part, boxes.reach, box)) {
          near[r].push_back(static_cast<std::uint32_t>(i));
          break;
        }
  }
  return near;
}

double overflow_over_ranks(std::span<const Vec3> positions, const PartBox& own, const PeriodicBox& box) {
  double overflow = 0.0;
  for (const Vec3& position : positions) {
    // Per axis the distance outside the box's interval, the nearest image's along a periodic axis.
    double squared = 0.0;
    for (int axis = 0; axis < 3; ++axis) {
      const auto outside = [&](double x) {
        return std::max({own.low[axis] - x, x - own.high[axis], 0.0});
      };
      double distance = outside(position[axis]);
      if (box.periodic[static_cast<std::size_t>(axis)]) {
        const double period = box.length[axis];
        distance = std::min({distance, outside(position[axis] + period), outside(position[axis] - period)});
      }
      squared += distance * distance;
    }
    overflow = std::max(overflow, std::sqrt(squared));
  }
  return ranks::max(overflow);
}

CouplingBoxes coupling_boxes(const std::vector<Vec3>& box_low, const std::vector<Vec3>& box_high,
                             std::span<const Vec3> members, double reach, const PeriodicBox& box) {
  const std::vector<PartBox> parts = rank_boxes(box_low, box_high);
  CouplingBoxes boxes;
  for (const PartBox& part : parts) boxes.of_rank.push_back({part});
  boxes.reach = reach + overflow_over_ranks(members, parts[static_cast<std::size_t>(ranks::rank())], box);
  return boxes;
}

CouplingBoxes either_family(CouplingBoxes first, const CouplingBoxes& second) {
  for (std::size_t r = 0; r < first.of_rank.size(); ++r)
    first.of_rank[r].insert(first.of_rank[r].end(), second.of_rank[r].begin(), second.of_rank[r].end());
  first.reach = std::max(first.reach, second.reach);
  return first;
}

Vec3 lowest_corner_over_ranks(std::span<const Vec3> positions, std::span<const Vec3> more) {
  Vec3 low = Vec3::Constant(std::numeric_limits<double>::max());
  for (const Vec3& p : positions) low = low.cwiseMin(p);
  for (const Vec3& p : more) low = low.cwiseMin(p);
  // A minimum is exact in any order.
  return Vec3(-ranks::max(-low.x()), -ranks::max(-low.y()), -ranks::max(-low.z()));
}

}  // namespace riffle
