#include "systems/solid_cell_sort.hpp"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <tuple>

#include "systems/solid_checks.hpp"

namespace riffle {

std::vector<std::size_t> cell_order(const Solids& solids, const Vec3& origin, double cell_size) {
  const std::size_t count = solids.size();
  std::vector<std::pair<std::uint64_t, std::size_t>> keys(count);
  for (std::size_t i = 0; i < count; ++i) {
    const Vec3 cell = ((solids.position[i] - origin) / cell_size).array().floor().max(0.0).min(1048575.0);
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

void SolidCellSort::run(SystemContext& context) {
  const std::int64_t every = context.model.solids.sort_every;
  if (every <= 0 || (context.step() + 1) % static_cast<std::uint64_t>(every) != 0) return;
  Solids& solids = context.write<Solids>();
  if (solids.size() < 2) return;
  const double largest_radius = *std::max_element(solids.radius.begin(), solids.radius.end());
  const DomainBox domain = solid_domain(context.model);
  permute_fields(solids, cell_order(solids, domain.low, 2.0 * largest_radius));
  context.count_items(solids.size());
}

}  // namespace riffle
