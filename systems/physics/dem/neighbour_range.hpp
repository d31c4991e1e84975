#pragma once
// How far the grains' neighbour search reaches and the grid it searches: the skin, the halo's width at a periodic
// seam and the cell grid's shape. Pure functions of the grains and the model, shared by the neighbour list
// (systems/dem/solid_neighbours), the checkpoint's validation (which rebuilds a halo) and the scene's budget.
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "components/model.hpp"
#include "components/solids.hpp"
#include "components/vec.hpp"
#include "systems/physics/geometry/domain.hpp"

namespace riffle {

/// The gap below which a pair (or a grain and a wall: radius_2 = infinity) feels lubrication; 0 when it is off.
/// The list reaches skin beyond it, so a pair that comes within it before the next rebuild is in the list.
inline double lubrication_reach(const CouplingModel& coupling, double radius_1, double radius_2) {
  if (!coupling.lubrication) return 0.0;
  return coupling.lubrication_cutoff_gap(std::isinf(radius_2) ? radius_1 : radius_1 * radius_2 / (radius_1 + radius_2));
}

/// The box and cells of the grain grid. It spans the grains' bounding box (clipped to the domain), not the whole
/// domain: a wide domain_margin or a large tank amplitude is empty space. Its cells are `cell_size` wide (the
/// smallest pair's reach) unless that would give more than solid_grid_cell_limit(grains) cells (one tiny grain among
/// large ones, grains spread over a big box): then wider. The lists are sorted per grain, so the shape changes no
/// pair, only the cost of the search.
struct SolidGridShape {
  Vec3 origin = Vec3::Zero();          ///< [m] min corner of cell (0, 0, 0)
  double cell_size = 1.0;              ///< [m]
  std::array<std::int64_t, 3> cells{1, 1, 1};
  double cell_count() const {
    return static_cast<double>(cells[0]) * static_cast<double>(cells[1]) * static_cast<double>(cells[2]);
  }
};
/// max(8 grains, 65536): a few cells per grain, and a floor below which the grid's memory does not matter.
double solid_grid_cell_limit(std::size_t grains);
SolidGridShape solid_grid_shape(const std::vector<Vec3>& positions, const DomainBox& domain, double cell_size);

/// The skin used when the scene leaves contact.skin at 0: half the smallest grain radius.
double default_skin(const Solids& solids);

/// [m] How far from a periodic face a grain needs ghosts: the longest candidate distance of the list (the largest
/// pair's r_i + r_j + skin, plus the lubrication cut-off when on).
double halo_width(const Solids& solids, const Model& model, double skin);

}  // namespace riffle
