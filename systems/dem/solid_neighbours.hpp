#pragma once
// Neighbour list for the grains: Verlet candidates within r_i + r_j + skin (and grain-wall candidates within
// r + skin of a wall), rebuilt only when some grain has moved more than half the skin, or a grain plus the tank
// more than the skin, since the last build. A uniform cell grid sized for the smallest pair; each grain searches as
// many cells as its own reach needs, so small grains among large ones stay cheap. On rebuild the grains may be
// reordered by cell for memory locality; tangential springs are carried over by grain id. In a periodic box
// ([tank] periodic) the rebuild wraps the grains into the box and builds the halo of ghosts near the seams
// (components/halo.hpp); every sub-step between rebuilds exchanges the ghosts' copies.
#include <array>
#include <cstdint>
#include <vector>

#include "engine/core/system.hpp"
#include "systems/physics/domain.hpp"
#include "systems/physics/periodic_box.hpp"

namespace riffle {

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

/// The exchange of the grains' halo: copies each ghost's owner's position (+ shift), velocity, angular velocity,
/// radius, mass and material into `contacts.ghosts`.
void exchange_grain_halo(const Solids& solids, Contacts& contacts);

/// A list read from a checkpoint has no halo (it is not stored): rebuilds it from the positions the list was built
/// at, the very ghosts in the very order of the run that wrote it. Does nothing without periodic axes or when built.
void restore_halo(const Solids& solids, Contacts& contacts, const Model& model);

/// Whether some grain lies outside the periodic box along a periodic axis (then the list is rebuilt and wraps it).
bool outside_periodic_box(const Solids& solids, const PeriodicBox& box);

/// True if the list built with `contacts` may miss a contact at the current positions.
bool neighbour_list_stale(const Solids& solids, const Contacts& contacts, const TankMotion& tank);

/// Rebuilds the list (and reorders the grains by cell if `reorder`), keeping tangential springs by id.
void rebuild_neighbour_list(Solids& solids, Contacts& contacts, const Walls& walls, const TankMotion& tank,
                            const Model& model, bool reorder);

class SolidNeighbours final : public System {
 public:
  std::string_view name() const override { return "solid_neighbours"; }
  Access access() const override {
    return {component_ids<Walls, TankMotion>(), component_ids<Solids, Contacts>()};
  }
  void run(SystemContext& context) override;
};

}  // namespace riffle
