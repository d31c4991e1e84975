#pragma once
// Neighbour list for the grains: Verlet candidates within r_i + r_j + skin (and grain-wall candidates within
// r + skin of a wall), rebuilt only when the two grains that moved most since the last build moved more than the
// skin together (systems/physics/geometry/verlet_skin.hpp), or a grain plus the tank more than the skin. A uniform
// cell grid sized for the smallest pair; each grain searches as many cells as its own reach needs, so small grains
// among large ones stay cheap. On rebuild the grains may be
// reordered by cell for memory locality; tangential springs are carried over by grain id. In a periodic box
// ([tank] periodic) the rebuild wraps the grains into the box and builds the halo of ghosts near the seams
// (components/halo.hpp); every sub-step between rebuilds exchanges the ghosts' copies.
#include <array>
#include <cstdint>
#include <vector>

#include "systems/system.hpp"
#include "systems/physics/dem/neighbour_range.hpp"
#include "systems/physics/geometry/domain.hpp"
#include "systems/physics/geometry/periodic_box.hpp"

namespace riffle {

/// The exchange of the grains' halo: copies each ghost's owner's position (+ shift), velocity, angular velocity,
/// radius, mass and material into `contacts.ghosts`.
void exchange_grain_halo(const Solids& solids, Contacts& contacts);
/// The exchange between rebuilds: the position (+ shift), velocity and angular velocity only (a ghost's radius, mass
/// and material cannot change while its halo stands: the same grains, the same owners).
void exchange_grain_halo_motion(const Solids& solids, Contacts& contacts);

/// A list read from a checkpoint has no halo and no slabs (they are not stored): rebuilds them from the positions the
/// list was built at, the very ghosts in the very order, and the very slabs, of the run that wrote it. Does nothing
/// where they stand (and no halo without periodic axes).
void restore_halo_and_slabs(const Solids& solids, Contacts& contacts, const Model& model);

/// Cuts the list's grains into the contact pass's slabs (systems/physics/dem/contact_slabs.hpp) by their positions
/// at the build, the list's reach and the periodic box.
void slice_contact_slabs(const Solids& solids, Contacts& contacts, const Model& model);

/// True if the list built with `contacts` may miss a contact at the current positions: the two largest displacements
/// since the build add up to more than the skin (over MPI ranks: twice the largest), in the tank's frame where
/// `tank_frame` (the walls ride with the tank: a bed that moves with a shaken tank keeps its list), else in the lab's,
/// with the walls' own motion added.
bool neighbour_list_stale(const Solids& solids, const Contacts& contacts, const TankMotion& tank, bool tank_frame);

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
