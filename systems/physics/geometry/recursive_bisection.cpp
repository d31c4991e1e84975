#include "systems/physics/geometry/recursive_bisection.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace riffle {

namespace {

struct Bisection {
  std::span<const Vec3> points;
  std::span<const double> weights;
  std::vector<PartBox> boxes;

  void split(std::vector<std::size_t>& members, const PartBox& box, int parts) {
    if (parts == 1) {
      boxes.push_back(box);
      return;
    }
    const int lower_parts = parts / 2;
    // Cut across the points' longest spread (the box's where it holds none): a tank's box runs up into the air
    // above the water, which a cut along the box's own longest side would slice for nothing.
    const Vec3 extent = box.high - box.low;
    Vec3 spread = extent;
    if (!members.empty()) {
      Vec3 lowest = points[members[0]], highest = points[members[0]];
      for (const std::size_t i : members) {
        lowest = lowest.cwiseMin(points[i]);
        highest = highest.cwiseMax(points[i]);
      }
      spread = highest - lowest;
    }
    int axis = 0;
    for (int a = 1; a < 3; ++a)
      if (spread[a] > spread[axis]) axis = a;
    std::sort(members.begin(), members.end(), [&](std::size_t a, std::size_t b) {
      const double pa = points[a][axis], pb = points[b][axis];
      return pa < pb || (pa == pb && a < b);
    });
    double total = 0.0;
    for (const std::size_t i : members) total += weights[i];
    const double share = static_cast<double>(lower_parts) / static_cast<double>(parts);
    // Without weight to share, cut the box in proportion to the parts.
    double cut = box.low[axis] + share * extent[axis];
    if (total > 0.0) {
      // The first k points (in order along the axis) whose weight passes the lower side's share, or stops just
      // short of it, whichever is nearer; then the cut halfway to the next point, so that no point sits on it.
      const double target = share * total;
      double sum = 0.0;
      std::size_t k = 0;
      while (k < members.size() && sum + weights[members[k]] <= target) sum += weights[members[k++]];
      if (k < members.size() && (sum + weights[members[k]]) - target < target - sum) ++k;
      // Points with equal coordinates stay on one side: move k to the nearest change of coordinate.
      std::size_t up = k, down = k;
      while (up > 0 && up < members.size() && points[members[up]][axis] == points[members[up - 1]][axis]) ++up;
      while (down > 0 && down < members.size() && points[members[down]][axis] == points[members[down - 1]][axis]) --down;
      k = (up - k <= k - down || down == 0) ? up : down;
      if (k > 0 && k < members.size())
        cut = 0.5 * (points[members[k - 1]][axis] + points[members[k]][axis]);
      else if (k == 0 && !members.empty())
        cut = std::min(cut, points[members[0]][axis]);
      else if (!members.empty())
        cut = std::max(cut, std::nextafter(points[members.back()][axis], std::numeric_limits<double>::infinity()));
      cut = std::clamp(cut, box.low[axis], box.high[axis]);
    }
    // The members below the cut (sorted along the axis) go to the lower side.
    const auto lower_count = static_cast<std::size_t>(
        std::partition_point(members.begin(), members.end(),
                             [&](std::size_t i) { return points[i][axis] < cut; }) -
        members.begin());
    std::vector<std::size_t> upper(members.begin() + static_cast<std::ptrdiff_t>(lower_count), members.end());
    members.resize(lower_count);
    PartBox lower_box = box, upper_box = box;
    lower_box.high[axis] = cut;
    upper_box.low[axis] = cut;
    split(members, lower_box, lower_parts);
    split(upper, upper_box, parts - lower_parts);
  }
};

}  // namespace

std::vector<PartBox> recursive_bisection(std::span<const Vec3> points, std::span<const double> weights,
                                         const PartBox& domain, int parts) {
  if (parts < 1) throw std::invalid_argument("recursive_bisection: parts must be at least 1");
  if (points.size() != weights.size())
    throw std::invalid_argument("recursive_bisection: one weight per point");
  Bisection bisection{points, weights, {}};
  bisection.boxes.reserve(static_cast<std::size_t>(parts));
  std::vector<std::size_t> members(points.size());
  std::iota(members.begin(), members.end(), std::size_t{0});
  bisection.split(members, domain, parts);
  return bisection.boxes;
}

double distance_to_box(const PartBox& box, const Vec3& point) {
  const Vec3 below = (box.low - point).cwiseMax(0.0);
  const Vec3 above = (point - box.high).cwiseMax(0.0);
  return (below + above).norm();
}

std::size_t part_of(std::span<const PartBox> boxes, const Vec3& point) {
  std::size_t nearest = 0;
  double nearest_distance = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < boxes.size(); ++k) {
    const PartBox& box = boxes[k];
    if ((point.array() >= box.low.array()).all() && (point.array() < box.high.array()).all()) return k;
    const double distance = distance_to_box(box, point);
    if (distance < nearest_distance) {
      nearest_distance = distance;
      nearest = k;
    }
  }
  return nearest;
}

}  // namespace riffle
