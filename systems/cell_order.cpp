#include "systems/cell_order.hpp"

#include <tbb/parallel_sort.h>

#include <cmath>
#include <cstdint>
#include <utility>

namespace riffle {

std::vector<std::size_t> cell_order(const std::vector<Vec3>& positions, std::size_t count, const Vec3& origin,
                                    double cell_size) {
  std::vector<std::pair<std::uint64_t, std::size_t>> keys(count);
  for (std::size_t i = 0; i < count; ++i) {
    const Vec3 cell = ((positions[i] - origin) / cell_size).array().floor().max(0.0).min(1048575.0);
    const auto x = static_cast<std::uint64_t>(cell[0]);
    const auto y = static_cast<std::uint64_t>(cell[1]);
    const auto z = static_cast<std::uint64_t>(cell[2]);
    keys[i] = {(z << 40) | (y << 20) | x, i};
  }
  // (key, slot) pairs are unique, so an unstable parallel sort still gives one answer.
  tbb::parallel_sort(keys.begin(), keys.end());
  std::vector<std::size_t> order(count);
  for (std::size_t k = 0; k < count; ++k) order[k] = keys[k].second;
  return order;
}

}  // namespace riffle
