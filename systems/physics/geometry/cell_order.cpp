#include "systems/physics/geometry/cell_order.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <utility>

#include "systems/physics/geometry/cell_index.hpp"

namespace riffle {

std::vector<std::size_t> cell_order(const std::vector<Vec3>& positions, std::size_t count, const Vec3& origin,
                                    double cell_size) {
  std::vector<std::pair<std::uint64_t, std::size_t>> keys(count);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 4096), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      std::uint64_t axis_cell[3];
      for (int axis = 0; axis < 3; ++axis) {
        const double cell = std::floor((positions[i][axis] - origin[axis]) / cell_size);
        axis_cell[axis] = static_cast<std::uint64_t>(clamp_to_cells(cell, 1048575.0));  // a NaN sorts into cell 0
      }
      keys[i] = {(axis_cell[2] << 40) | (axis_cell[1] << 20) | axis_cell[0], i};
    }
  });
  // Sorting again soon after a sort mostly finds the order kept (walls never move across the cells that ride with
  // them): check first, which costs a fraction of the sort.
  const bool sorted = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(1, std::max<std::size_t>(count, 1), 4096), true,
      [&](const tbb::blocked_range<std::size_t>& range, bool ok) {
        for (std::size_t k = range.begin(); ok && k < range.end(); ++k) ok = keys[k - 1].first <= keys[k].first;
        return ok;
      },
      [](bool a, bool b) { return a && b; });
  std::vector<std::size_t> order(count);
  if (sorted) {
    std::iota(order.begin(), order.end(), std::size_t{0});
    return order;
  }
  // A counting sort over the occupied box of cells, stable in slot: O(particles + cells), where a comparison sort of
  // the (key, slot) pairs costs several times more. A stray particle far away would make the box huge: sort then.
  struct Box {
    std::uint64_t low[3] = {~std::uint64_t{0}, ~std::uint64_t{0}, ~std::uint64_t{0}};
    std::uint64_t high[3] = {0, 0, 0};
  };
  constexpr std::uint64_t kAxisMask = (std::uint64_t{1} << 20) - 1;
  const auto axis_of = [&](std::uint64_t key, int axis) { return (key >> (20 * axis)) & kAxisMask; };
  const Box box = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, count, 4096), Box{},
      [&](const tbb::blocked_range<std::size_t>& range, Box box) {
        for (std::size_t k = range.begin(); k < range.end(); ++k)
          for (int axis = 0; axis < 3; ++axis) {
            box.low[axis] = std::min(box.low[axis], axis_of(keys[k].first, axis));
            box.high[axis] = std::max(box.high[axis], axis_of(keys[k].first, axis));
          }
        return box;
      },
      [](Box a, const Box& b) {
        for (int axis = 0; axis < 3; ++axis) {
          a.low[axis] = std::min(a.low[axis], b.low[axis]);
          a.high[axis] = std::max(a.high[axis], b.high[axis]);
        }
        return a;
      });
  const std::uint64_t nx = box.high[0] - box.low[0] + 1, ny = box.high[1] - box.low[1] + 1,
                      nz = box.high[2] - box.low[2] + 1;
  const double cells = static_cast<double>(nx) * static_cast<double>(ny) * static_cast<double>(nz);
  if (cells > 8.0 * static_cast<double>(count) + 1.0e6) {
    // (key, slot) pairs are unique, so an unstable parallel sort still gives one answer.
    tbb::parallel_sort(keys.begin(), keys.end());
    for (std::size_t k = 0; k < count; ++k) order[k] = keys[k].second;
    return order;
  }
  std::vector<std::uint32_t> cell_of(count);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 4096), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t k = range.begin(); k < range.end(); ++k) {
      const std::uint64_t key = keys[k].first;
      cell_of[k] = static_cast<std::uint32_t>(((axis_of(key, 2) - box.low[2]) * ny + (axis_of(key, 1) - box.low[1])) * nx +
                                              (axis_of(key, 0) - box.low[0]));
    }
  });
  std::vector<std::uint32_t> start(static_cast<std::size_t>(cells) + 1, 0);
  for (std::size_t k = 0; k < count; ++k) ++start[cell_of[k] + 1];
  for (std::size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
  for (std::size_t k = 0; k < count; ++k) order[start[cell_of[k]]++] = k;
  return order;
}

}  // namespace riffle
