#pragma once
// A halo: ghost copies of the real particles that lie within a cutoff of a seam, so that neighbour code sees the
// particles across the seam as if they were next door (docs/ARCHITECTURE.md, "Periodic boundaries and the halo").
//
// Real particles hold slots [0, N), ghosts [N, N + G): ghost g is the image of real particle owner[g], at
// owner's position + shift[g]. Neighbour lists store either kind of slot; `Ghosted<T>` reads a field for any of
// them, and `owner_of` maps a slot to the real particle that receives its force. The halo is family-agnostic (the
// grains' lives in Contacts; the MPS fluid's is the next to come): it knows slots, ids and shifts; each family
// keeps the ghost copies of the fields its neighbour code reads and fills them with `halo_copy`.
//
// What a distributed run (MPI ranks, each a subdomain) replaces: the build (which real particles a neighbour needs)
// and the exchange (here a copy within one box; there a message to the neighbouring rank, which appends the
// received copies after its own reals). The consumers, which read [0, N + G) through Ghosted and send ghost
// forces to owner_of, stay as they are.
#include <cstdint>
#include <vector>

#include "components/vec.hpp"

namespace riffle {

struct Halo {
  std::uint32_t real_count = 0;        ///< N: the real particles when the halo was built
  std::vector<std::uint32_t> owner;    ///< [G] slot of the real particle the ghost copies
  std::vector<EntityId> owner_id;      ///< [G] its id (stable across reorders; contact history is keyed by id)
  std::vector<Vec3> shift;             ///< [m] [G] ghost position = owner position + shift (a sum of periods)
  bool valid = false;                  ///< false until built (never checkpointed: rebuilt from the list's positions)

  std::size_t size() const { return owner.size(); }
  /// The real particle behind slot j of [0, N + G).
  std::uint32_t owner_of(std::uint32_t j) const { return j < real_count ? j : owner[j - real_count]; }
  void clear() {
    real_count = 0;
    owner.clear();
    owner_id.clear();
    shift.clear();
    valid = false;
  }
};

/// One field seen over [0, N + G): reals first, then the ghost copies.
template <class T>
struct Ghosted {
  const T* real = nullptr;
  const T* ghost = nullptr;
  std::uint32_t real_count = 0;
  const T& operator[](std::uint32_t j) const { return j < real_count ? real[j] : ghost[j - real_count]; }
};
template <class T>
Ghosted<T> ghosted(const std::vector<T>& real, const std::vector<T>& ghost, const Halo& halo) {
  return {real.data(), ghost.data(), halo.real_count};
}

/// The exchange of one field: ghost[g] = real[owner[g]].
template <class T>
void halo_copy(const Halo& halo, const std::vector<T>& real, std::vector<T>& ghost) {
  ghost.resize(halo.size());
  for (std::size_t g = 0; g < halo.size(); ++g) ghost[g] = real[halo.owner[g]];
}
/// The exchange of positions: ghost[g] = real[owner[g]] + shift[g].
inline void halo_copy_positions(const Halo& halo, const std::vector<Vec3>& real, std::vector<Vec3>& ghost) {
  ghost.resize(halo.size());
  for (std::size_t g = 0; g < halo.size(); ++g) ghost[g] = real[halo.owner[g]] + halo.shift[g];
}

/// The grains' ghost copies: what the contact code reads of a neighbour.
struct GrainGhosts {
  std::vector<Vec3> position, velocity, angular_velocity;
  std::vector<double> radius, mass;
  std::vector<std::int32_t> material;
};

/// A spring carried by id across a rebuild that has no old list to read it from: a grain that arrived from another
/// rank brings the springs of its pairs, and a world just split over the ranks keeps those of its own pairs.
struct CarriedSpring {
  EntityId lower = 0, higher = 0;  ///< grain ids (pairs: lower < higher), or grain id and wall slot (walls)
  Vec3 spring = Vec3::Zero();      ///< [m] oriented for `lower` (pairs) or the grain (walls)
  Vec3 rolling = Vec3::Zero();     ///< [N m] the rolling spring torque, oriented as `spring`
};

/// The grains of other MPI ranks that this rank's grains may touch, in a run spread over ranks
/// (systems/physics/ranks/grain_ranks.hpp). Each rank owns the grains inside its box (a recursive bisection of the
/// domain); the grains of other ranks within the neighbour list's reach of its box are its ghosts, held as the
/// periodic halo's are, in slots [N, N + G) of Contacts::ghosts after the N reals. A pair of a real grain and a
/// ghost is listed on one rank only, the owner of its lower id, which sends the ghost's share of the force back to
/// the ghost's owner every sub-step (LAMMPS's "newton on"). Not checkpointed: a checkpoint holds every grain, and a
/// resumed run is split again.
struct RankHalo {
  bool active = false;                     ///< the grains are spread over ranks
  Vec3 domain_low = Vec3::Zero(), domain_high = Vec3::Zero();  ///< [m] the domain the boxes tile
  std::vector<Vec3> box_low, box_high;     ///< [m] [ranks] each rank's box (a grain's owner is the box holding it)
  std::uint32_t real_count = 0;            ///< N at the last build
  std::vector<EntityId> ghost_id;          ///< [G] the ghost's id on its owner rank
  std::vector<std::int32_t> ghost_fixed;   ///< [G] its `fixed` flag
  std::vector<std::vector<std::uint32_t>> send_slots;  ///< [ranks] the real slots sent to each rank, in order
  /// [ranks] the periodic image each sent copy is (ghost position = the real's + shift; zero without periodic axes).
  /// A rank's own grains near a periodic face come back to it this way, as images.
  std::vector<std::vector<Vec3>> send_shift;
  std::vector<std::uint32_t> receive_offsets;          ///< [ranks + 1] the ghosts from rank r: [offsets[r], offsets[r+1])
  /// Pairs whose second grain is a ghost, grouped by ghost ([G + 1] offsets, ascending pair index within a ghost),
  /// and each such pair's force and torque on the ghost, from the last contact pass ([pairs]; zero elsewhere).
  std::vector<std::uint32_t> ghost_pair_offsets, ghost_pairs;
  std::vector<Vec3> pair_force_on_ghost, pair_torque_on_ghost;
  /// Springs to restore by id at the next rebuild (arrivals', or those of a world just split).
  std::vector<CarriedSpring> carried_pair_springs, carried_wall_springs;
  std::uint64_t grains_sent = 0;      ///< grains this rank has handed to others so far (migrations)
  std::uint64_t rebalances = 0;       ///< times the boxes were cut anew since the split (the same on every rank)

  std::size_t ghost_count() const { return ghost_id.size(); }
};

/// The MPS particles of other MPI ranks within the fluid operators' reach (r_e + skin) of this rank's box, in a run
/// whose water is spread over ranks (systems/physics/ranks/fluid_ranks.hpp): held in slots [N, N + G) after the N
/// reals, as the periodic halo's ghosts are, with their fields in FluidGhosts. The MPS operators add nothing back to a
/// neighbour (each particle sums its own neighbours' terms), so nothing returns to the owners: the ghosts' fields go
/// one way, at the points the periodic halo's are copied. Not checkpointed: a checkpoint holds every particle.
struct FluidRankHalo {
  bool active = false;                     ///< the particles are spread over ranks
  Vec3 domain_low = Vec3::Zero(), domain_high = Vec3::Zero();  ///< [m] the domain the boxes tile
  std::vector<Vec3> box_low, box_high;     ///< [m] [ranks] each rank's box (a particle's owner is the box holding it)
  std::uint32_t real_count = 0;            ///< N at the last build
  std::vector<EntityId> ghost_id;          ///< [G] the ghost's id on its owner rank
  std::vector<std::vector<std::uint32_t>> send_slots;  ///< [ranks] the real slots sent to each rank, in order
  /// [ranks] the periodic image each sent copy is (its position the real's + shift; zero without periodic axes). A
  /// rank's own particles near a periodic face come back to it this way, as images.
  std::vector<std::vector<Vec3>> send_shift;
  std::vector<std::uint32_t> receive_offsets;          ///< [ranks + 1] the ghosts from rank r: [offsets[r], offsets[r+1])
  std::uint64_t particles_sent = 0;        ///< particles this rank has handed to others so far (migrations)
  std::uint64_t rebalances = 0;            ///< times the boxes were cut anew since the split (the same on every rank)
  std::size_t ghost_count() const { return ghost_id.size(); }
};

/// The MPS particles' ghost copies (fluid, wall and dummy slots alike): what the fluid operators read of a neighbour
/// (systems/mps/). Each search exchanges the positions it searched at, the velocities and the kinds; the pressure
/// solve exchanges the pressures it solved for.
struct FluidGhosts {
  std::vector<Vec3> position;            ///< [m] r^k + shift: the step-start search, the prediction, SPS
  std::vector<Vec3> predicted_position;  ///< [m] r* + shift: free surface, pressure solve, correction
  std::vector<Vec3> velocity;            ///< [m/s]
  std::vector<std::int32_t> kind;        ///< FluidKind
  std::vector<double> pressure;          ///< [Pa] p^{k+1} (the correction's gradient)
};

}  // namespace riffle
