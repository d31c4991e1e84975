#include "systems/physics/dem/neighbour_range.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace riffle {

double solid_grid_cell_limit(std::size_t grains) { return std::max(8.0 * static_cast<double>(grains), 65536.0); }

SolidGridShape solid_grid_shape(const std::vector<Vec3>& positions, const DomainBox& domain, double cell_size) {
  // The grains' box, clipped to the domain (a grain outside it stops the run at the domain check; until then it
  // sits in an edge cell). Non-finite positions are left out here for the same reason.
  Vec3 low = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 high = -low;
  for (const Vec3& p : positions)
    if (std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2])) {
      low = low.cwiseMin(p);
      high = high.cwiseMax(p);
    }
  low = low.cwiseMax(domain.low);
  high = high.cwiseMin(domain.high);
  if (!((low.array() <= high.array()).all())) low = high = domain.low;
  SolidGridShape shape;
  shape.origin = low;
  shape.cell_size = cell_size > 0.0 && std::isfinite(cell_size) ? cell_size : 1.0;
  const Vec3 extent = high - low;
  const double limit = solid_grid_cell_limit(positions.size());
  auto axis_cells = [&](int axis) {
    // Clamped before the cast: 1e300 m of extent over a 1 um cell is no int64.
    return std::clamp(std::ceil(extent[axis] / shape.cell_size), 1.0, 1e15);
  };
  for (;;) {
    const double total = axis_cells(0) * axis_cells(1) * axis_cells(2);
    if (total <= limit) break;
    // Straight to about the limit, then by 1/8 steps: the per-axis ceilings can keep the first guess a bit high.
    shape.cell_size *= std::max(1.125, 0.999 * std::cbrt(total / limit));
  }
  for (int axis = 0; axis < 3; ++axis)
    shape.cells[static_cast<std::size_t>(axis)] = static_cast<std::int64_t>(axis_cells(axis));
  return shape;
}

double halo_width(const Solids& solids, const Model& model, double skin) {
  if (solids.size() == 0) return 0.0;
  const double largest = *std::max_element(solids.radius.begin(), solids.radius.end());
  return 2.0 * largest + skin + lubrication_reach(model.coupling, largest, std::numeric_limits<double>::infinity());
}

double default_skin(const Solids& solids) {
  if (solids.size() == 0) return 0.0;
  return 0.5 * *std::min_element(solids.radius.begin(), solids.radius.end());
}

}  // namespace riffle
