#pragma once
// Neighbour list for the grains: Verlet candidates within r_i + r_j + skin (and grain-wall candidates within
// r + skin of a wall), rebuilt only when some grain has moved more than half the skin, or a grain plus the tank
// more than the skin, since the last build. A uniform cell grid sized for the smallest pair; each grain searches as
// many cells as its own reach needs, so small grains among large ones stay cheap. On rebuild the grains may be
// reordered by cell for memory locality; tangential springs are carried over by grain id.
#include "engine/system.hpp"

namespace riffle {

/// The skin used when the scene leaves contact.skin at 0: half the smallest grain radius.
double default_skin(const Solids& solids);

/// True if the list built with `contacts` may miss a contact at the current positions.
bool neighbour_list_stale(const Solids& solids, const Contacts& contacts, const TankMotion& tank);

/// Rebuilds the list (and reorders the grains by cell if `reorder`), keeping tangential springs by id.
void rebuild_neighbour_list(Solids& solids, Contacts& contacts, const Walls& walls, const TankMotion& tank,
                            const Model& model, bool reorder);

class SolidNeighbours final : public System {
 public:
  std::string_view name() const override { return "solid_neighbours"; }
  Access access() const override {
    return {{ComponentId::kWalls, ComponentId::kTankMotion}, {ComponentId::kSolids, ComponentId::kContacts}};
  }
  void run(SystemContext& context) override;
};

}  // namespace riffle
