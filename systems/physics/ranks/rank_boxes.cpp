#include "systems/physics/ranks/rank_boxes.hpp"

#include <algorithm>
#include <numeric>

#include "systems/physics/ranks/rank_comm.hpp"

namespace riffle {

std::vector<PartBox> rank_boxes(const std::vector<Vec3>& low, const std::vector<Vec3>& high) {
  std::vector<PartBox> boxes(low.size());
  for (std::size_t r = 0; r < boxes.size(); ++r) boxes[r] = {low[r], high[r]};
  return boxes;
}

void store_rank_boxes(const std::vector<PartBox>& boxes, std::vector<Vec3>& low, std::vector<Vec3>& high) {
  low.clear();
  high.clear();
  for (const PartBox& box : boxes) {
    low.push_back(box.low);
    high.push_back(box.high);
  }
}

std::vector<double> weight_per_box(std::span<const Vec3> positions, std::span<const double> weights,
                                   std::span<const PartBox> boxes) {
  std::vector<double> mine(boxes.size(), 0.0);
  for (std::size_t i = 0; i < weights.size(); ++i) mine[part_of(boxes, positions[i])] += weights[i];
  return ranks::sum_in_rank_order(mine);
}

bool boxes_out_of_balance(const std::vector<double>& per_box, double above) {
  if (per_box.empty()) return false;
  const double total = std::accumulate(per_box.begin(), per_box.end(), 0.0);
  const double mean = total / static_cast<double>(per_box.size());
  const double largest = *std::max_element(per_box.begin(), per_box.end());
  return total > 0.0 && largest > above * mean && largest >= mean + 2.0;
}

std::vector<PartBox> bisect_over_ranks(std::span<const Vec3> positions, std::span<const double> weights,
                                       const PartBox& domain, int parts) {
  std::vector<double> mine;
  mine.reserve(4 * weights.size());
  for (std::size_t i = 0; i < weights.size(); ++i) {
    const Vec3& position = positions[i];
    mine.insert(mine.end(), {position.x(), position.y(), position.z(), weights[i]});
  }
  const std::vector<double> all = ranks::gather_all(mine);
  std::vector<Vec3> points(all.size() / 4);
  std::vector<double> all_weights(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    points[i] = Vec3(all[4 * i], all[4 * i + 1], all[4 * i + 2]);
    all_weights[i] = all[4 * i + 3];
  }
  return recursive_bisection(points, all_weights, domain, parts);
}

}  // namespace riffle
