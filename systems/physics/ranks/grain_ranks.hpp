#pragma once
// The grains of a run spread over MPI ranks (domain decomposition; components/halo.hpp, RankHalo): each rank owns the
// grains inside its box and integrates them; the other ranks' grains within the neighbour list's reach of its box are
// its ghosts. What moves between ranks, and when:
//   - at a neighbour-list rebuild (every rank rebuilds when any rank's list is stale): the grains that left a box go to
//     the rank that owns their new position, with every field and the springs of their pairs (those of which they
//     hold the lower id, and their wall pairs); then each rank sends every other the grains within reach of its box,
//     ghosts for its search (ids, kinematics, radius, mass, material, fixed);
//   - every sub-step, before the contact pass: the ghosts' positions, velocities and spins from their owners;
//   - every sub-step, after it: each ghost's share of its pairs' forces and torques back to its owner, which adds them
//     in rank order (a fixed order: a run is reproducible for a given rank count).
// A one-rank run never calls these.
#include <cstddef>
#include <vector>

#include "components/contacts.hpp"
#include "components/solids.hpp"
#include "systems/physics/geometry/periodic_box.hpp"

namespace riffle {

/// Splits a world that every rank built whole (the same scene or checkpoint on every rank) over the ranks: boxes by a
/// recursive bisection of the grains' positions over [domain_low, domain_high] with equal weights, then each rank
/// keeps the grains in its box and the springs of their pairs (carried to the first rebuild, which every rank then
/// does). Deterministic: every rank computes the same boxes from the same world, without a message.
void split_grains_over_ranks(Solids& solids, Contacts& contacts, const Vec3& domain_low, const Vec3& domain_high);

/// The grains every rank's box holds (the rank's position in `ranks`' boxes), summed over the ranks: what each rank
/// owns after a migration. Collective.
std::vector<double> grains_per_box(const Solids& solids, const RankHalo& ranks);

/// The imbalance above which a rebuild cuts the boxes anew (LAMMPS's customary `fix balance` threshold): at 1.1 the
/// slowest rank does at most about a tenth more than the mean before the boxes follow the bed.
inline constexpr double kRebalanceAbove = 1.1;

/// Cuts the boxes anew when the imbalance of the grain counts the boxes hold (grains_per_box) passes `above`, and
/// the largest holds at least two grains more than the mean (so that a few grains over few ranks do not cut at every
/// rebuild): the same recursive bisection as the split, over every rank's grain positions gathered on every rank (the
/// same boxes everywhere, without a choice left to any rank; a bisection of distributed points would replace the
/// gather past about 10^7 grains). The next migrate_grains moves the grains to their new owners. Collective. Returns
/// true if it cut.
bool rebalance_grain_ranks(const Solids& solids, RankHalo& ranks, double above);

/// Sends the grains outside this rank's box to their owners, with their springs (`pair_springs`: springs by id,
/// oriented for the lower id, of the pairs this rank lists; those whose lower id leaves go with it; `wall_springs`:
/// those of the leaving grains go with them), and appends the grains that arrive, adding the springs they bring.
/// Collective. Returns the number of grains that left.
std::size_t migrate_grains(Solids& solids, RankHalo& ranks, std::vector<CarriedSpring>& pair_springs,
                           std::vector<CarriedSpring>& wall_springs);

/// Sends every rank this rank's grains within `reach` of its box, and fills `contacts.ghosts` and the RankHalo's ghost
/// ids, flags, send lists and offsets with what the others send. In a periodic box each grain's images across the
/// periodic faces go too (to this rank as well): a ghost is an image, its position the real's plus whole periods.
/// Collective.
void build_rank_ghosts(const Solids& solids, Contacts& contacts, double reach, const PeriodicBox& box);

/// The ghosts' positions, velocities and angular velocities from their owners (along the send lists of the last
/// build). Collective.
void exchange_rank_ghost_motion(const Solids& solids, Contacts& contacts);

/// Each ghost's share of its pairs' forces and torques (RankHalo::pair_force_on_ghost, summed per ghost in pair order)
/// sent to its owner and added there to `force` and `torque`, in rank order. Collective.
void return_rank_ghost_forces(const Contacts& contacts, std::vector<Vec3>& force, std::vector<Vec3>& torque);

/// ghost[g] = the owner's real[slot] for every ghost (a per-grain number the ghosts' build does not carry, such as
/// the water's sampling weight), along the last build's send lists, point to point. Collective.
void exchange_rank_ghost_values(const std::vector<double>& real, const Contacts& contacts, std::vector<double>& ghost);

/// Each ghost's sum of `pair_value` over its pairs (RankHalo::ghost_pairs, in pair order), times `factor`, sent to its
/// owner and added there to `add_to`, in rank order: a pair force other than the contacts' (the lubrication's).
/// Collective.
void return_rank_ghost_sums(const Contacts& contacts, const std::vector<Vec3>& pair_value, double factor,
                            std::vector<Vec3>& add_to);

/// A grain's touching wall contact as a checkpoint and the wall probes need it.
struct WallContactState {
  EntityId grain = 0;
  std::uint32_t wall = 0;
  Vec3 spring = Vec3::Zero(), rolling = Vec3::Zero(), force = Vec3::Zero(), torque = Vec3::Zero();
  double overlap = 0.0;
};

/// Every rank's touching pairs (their springs by id, for the lower id) and its grains' touching wall contacts, at
/// rank 0 in rank order (empty elsewhere). Collective.
void gather_contacts_at_root(const Solids& solids, const Contacts& contacts, std::vector<CarriedSpring>& pair_springs,
                             std::vector<WallContactState>& walls);

/// Every rank's grains at rank 0, ordered by id (a whole world's grains for the outputs); empty on the other ranks.
/// Collective.
Solids gather_grains_at_root(const Solids& solids);

}  // namespace riffle
