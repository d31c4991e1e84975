#pragma once
// A uniform cell grid over a set of points, for radius queries from other points (grains looking for fluid
// particles, grains for grains). Members of a cell are in ascending index order, and cells are visited in a fixed
// order, so a query visits candidates in an order that depends only on the positions.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "components/vec.hpp"
#include "systems/physics/geometry/cell_index.hpp"

namespace riffle {

/// The most cells a CellGrid over `points` points may have: 64 per point, and at least 4e6 (32 MB).
inline double cell_grid_cell_limit(std::size_t points) { return std::max(64.0 * static_cast<double>(points), 4.0e6); }

class CellGrid {
 public:
  /// Grid over points[first .. first + count) with cells of `cell_size` (at least the largest query radius), within
  /// the box [bound_low, bound_high] (the domain: a point outside it has left the domain, which fails the step; it
  /// is filed in the nearest edge cell instead of stretching the grid to wherever it flew).
  void build(std::span<const Vec3> points, std::size_t first, std::size_t count, double cell_size,
             const Vec3& bound_low, const Vec3& bound_high) {
    cell_size_ = cell_size;
    low_ = Vec3::Constant(1e300);
    Vec3 high = Vec3::Constant(-1e300);
    for (std::size_t k = first; k < first + count; ++k) {
      low_ = low_.cwiseMin(points[k]);
      high = high.cwiseMax(points[k]);
    }
    if (count == 0) low_ = high = Vec3::Zero();
    // Unchanged while every point is inside the bounds; a NaN coordinate leaves the bound.
    for (int axis = 0; axis < 3; ++axis) {
      low_[axis] = low_[axis] >= bound_low[axis] ? std::min(low_[axis], bound_high[axis]) : bound_low[axis];
      high[axis] = high[axis] <= bound_high[axis] ? std::max(high[axis], low_[axis]) : bound_high[axis];
    }
    // Counted in floating point, capped before the conversion. A stray point far from the others (still inside a
    // wide domain) must not make the grid huge either: above cell_grid_cell_limit the cells double until it fits.
    // That changes the order of the visits (and so the last bits of sums over them), but only for a grid that big,
    // which no valid scene's fluid builds (the limit is 64 cells per point).
    auto axis_cells = [&](int axis) {
      const double span = (high[axis] - low_[axis]) / cell_size_;
      return clamp_to_cells(std::floor(span), static_cast<double>((1 << 20) - 1)) + 1.0;
    };
    const double limit = cell_grid_cell_limit(count);
    while (axis_cells(0) * axis_cells(1) * axis_cells(2) > limit && cell_size_ < 1e300) cell_size_ *= 2.0;
    const bool fits = axis_cells(0) * axis_cells(1) * axis_cells(2) <= limit;  // not with an infinite coordinate
    for (int axis = 0; axis < 3; ++axis)
      cells_[static_cast<std::size_t>(axis)] = fits ? static_cast<std::int64_t>(axis_cells(axis)) : 1;
    const std::size_t total = static_cast<std::size_t>(cells_[0] * cells_[1] * cells_[2]);
    start_.assign(total + 1, 0);
    cell_of_.resize(count);
    for (std::size_t k = 0; k < count; ++k) {
      cell_of_[k] = linear(cell(points[first + k]));
      ++start_[cell_of_[k] + 1];
    }
    for (std::size_t c = 0; c < total; ++c) start_[c + 1] += start_[c];
    members_.resize(count);
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t k = 0; k < count; ++k) members_[fill[cell_of_[k]]++] = static_cast<std::uint32_t>(first + k);
    for (auto& coordinate : member_coordinates_) coordinate.resize(count);
    for (std::size_t m = 0; m < count; ++m)
      for (std::size_t axis = 0; axis < 3; ++axis)
        member_coordinates_[axis][m] = points[members_[m]][static_cast<Eigen::Index>(axis)];
  }

  /// The members' coordinates from `member` (a pointer into a run for_each_candidate_run handed out) on, as they
  /// were when the grid was built, x, y and z apart and in the runs' order: a run's distances are then one
  /// vectorised loop over contiguous memory (squared_offsets), where points[*member] would be read one by one.
  struct Coordinates {
    const double* x;
    const double* y;
    const double* z;
  };
  Coordinates member_coordinates(const std::uint32_t* member) const {
    const auto m = static_cast<std::size_t>(member - members_.data());
    return {member_coordinates_[0].data() + m, member_coordinates_[1].data() + m, member_coordinates_[2].data() + m};
  }
  /// The position of the member at `member`, as it was when the grid was built.
  Vec3 member_position(const std::uint32_t* member) const {
    const Coordinates at = member_coordinates(member);
    return Vec3(*at.x, *at.y, *at.z);
  }

  /// Calls visit(first, last) for each row of cells (fixed y, z) that the box of `radius` around `centre` reaches:
  /// [first, last) are the members of the row's cells in that box, in the order for_each_within visits them.
  template <class Visit>
  void for_each_candidate_run(const Vec3& centre, double radius, Visit&& visit) const {
    if (members_.empty()) return;
    const std::array<std::int64_t, 3> from = cell(centre - Vec3::Constant(radius));
    const std::array<std::int64_t, 3> to = cell(centre + Vec3::Constant(radius));
    for (std::int64_t z = from[2]; z <= to[2]; ++z)
      for (std::int64_t y = from[1]; y <= to[1]; ++y)
        visit(members_.data() + start_[linear({from[0], y, z})], members_.data() + start_[linear({to[0], y, z}) + 1]);
  }

  /// Calls visit(index) for every grid point within `radius` of `centre` (radius <= cell size not required).
  template <class Visit>
  void for_each_within(const std::vector<Vec3>& points, const Vec3& centre, double radius, Visit&& visit) const {
    if (members_.empty()) return;
    const std::array<std::int64_t, 3> from = cell(centre - Vec3::Constant(radius));
    const std::array<std::int64_t, 3> to = cell(centre + Vec3::Constant(radius));
    const double radius_squared = radius * radius;
    for (std::int64_t z = from[2]; z <= to[2]; ++z)
      for (std::int64_t y = from[1]; y <= to[1]; ++y)
        for (std::int64_t x = from[0]; x <= to[0]; ++x) {
          const std::size_t c = linear({x, y, z});
          for (std::uint32_t k = start_[c]; k < start_[c + 1]; ++k) {
            const std::uint32_t index = members_[k];
            if ((points[index] - centre).squaredNorm() < radius_squared) visit(index);
          }
        }
  }

 private:
  std::array<std::int64_t, 3> cell(const Vec3& point) const {
    std::array<std::int64_t, 3> result{};
    for (int axis = 0; axis < 3; ++axis) {
      const double scaled = std::floor((point[axis] - low_[axis]) / cell_size_);
      const double top = static_cast<double>(cells_[static_cast<std::size_t>(axis)] - 1);
      result[static_cast<std::size_t>(axis)] = static_cast<std::int64_t>(clamp_to_cells(scaled, top));
    }
    return result;
  }
  std::size_t linear(const std::array<std::int64_t, 3>& c) const {
    return static_cast<std::size_t>((c[2] * cells_[1] + c[1]) * cells_[0] + c[0]);
  }

  double cell_size_ = 1.0;
  Vec3 low_ = Vec3::Zero();
  std::array<std::int64_t, 3> cells_{1, 1, 1};
  std::vector<std::uint32_t> start_, members_;
  std::array<std::vector<double>, 3> member_coordinates_;  ///< points[members_[m]] at the build, per axis
  std::vector<std::size_t> cell_of_;
};

}  // namespace riffle
