#pragma once
// The MPS particles of a run spread over MPI ranks (domain decomposition; components/halo.hpp, FluidRankHalo): each
// rank owns the particles (fluid, wall and dummy) inside its box and computes their operators; the other ranks'
// particles within the operators' reach of its box (r_e + the lists' skin) are its ghosts, after its reals in the
// neighbour lists' slots, as a periodic tank's ghosts are (in a periodic tank the images across its faces are ghosts
// too, from any rank, its own included). What moves between ranks, and when:
//   - at a neighbour-list rebuild at the step's start: the particles that left a box go to the rank that owns their
//     new position, with every field (migrate_fluid_particles); then each rank sends every other its particles
//     within reach of that rank's box (build_fluid_rank_ghosts: ids, kinds, the searched positions, velocities);
//   - where a periodic tank copies its ghosts' fields (the searches' positions and velocities, the pressures after
//     the solve): the same fields from their owners, point to point (exchange_fluid_ghost_field).
// The fluid slots stay first in every rank's table (fluid_slot_count: the neighbour lists are built for them).
// The systems call them where the water meets the ranks (systems/mps/: fluid_rank_migration, the searches, the
// pressure solve, the correction, the shifting); tests/mpi/fluid_ranks.cpp tests them alone.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "components/fluid.hpp"
#include "components/halo.hpp"
#include "systems/physics/geometry/periodic_box.hpp"
#include "systems/physics/ranks/rank_comm.hpp"
#include "systems/physics/ranks/rank_messages.hpp"

namespace riffle {

/// The work weight of a wall or dummy particle relative to a fluid particle's in the split: walls are searched as
/// neighbours but have no list, no pressure row and no update of their own.
inline constexpr double kFluidWallWeight = 0.25;
/// ... and of one with no fluid of its table within the reach given: the searches' grids leave it out, so it costs
/// only its memory (a dam break's tank is mostly empty walls). Not zero, so that a region of walls alone still
/// counts for something in the cuts.
inline constexpr double kFluidFarWallWeight = 0.02;

/// Each particle's work weight: 1 for fluid; for a wall or dummy, kFluidWallWeight where the table holds a fluid
/// particle within about `reach` (cells of `reach`, the 27 around its own), kFluidFarWallWeight elsewhere. With
/// `reach` <= 0 every wall and dummy weighs kFluidWallWeight.
std::vector<double> fluid_work_weights(const ParticleState& particles, double reach);

/// Splits a table that every rank built whole (the same scene or checkpoint on every rank) over the ranks: boxes by a
/// recursive bisection of the particles' positions over [domain_low, domain_high] weighted by fluid_work_weights
/// (`reach`), each rank keeping the particles in its box, fluid first. Deterministic: every rank computes the same
/// boxes from the same table, without a message.
void split_fluid_over_ranks(FluidParticles& particles, FluidRankHalo& ranks, const Vec3& domain_low,
                            const Vec3& domain_high, double reach = 0.0);

/// The work (fluid_work_weights, `reach`) each rank's box holds, summed over all the ranks' particles in rank order:
/// the same on every rank. Collective.
std::vector<double> fluid_work_per_box(const ParticleState& particles, const FluidRankHalo& ranks, double reach);

/// Cuts the boxes anew when the largest box's work (fluid_work_per_box) passes `above` times the mean and the mean
/// by two fluid particles' worth: the split's bisection over every rank's positions and weights gathered on every
/// rank (the same boxes everywhere). Call before a migration, which then moves the particles. Returns whether it
/// cut; counts the cuts in ranks.rebalances. Collective.
bool rebalance_fluid_ranks(const ParticleState& particles, FluidRankHalo& ranks, double reach, double above);

/// Sends the particles outside this rank's box to their owners with every field, and appends those that arrive,
/// keeping the fluid slots first (each kind in its old order, the arrivals after, in rank order). In a periodic tank
/// the caller wraps the positions first: a particle past a face belongs to the box holding it wrapped. Collective.
/// Returns the number of particles that left.
std::size_t migrate_fluid_particles(FluidParticles& particles, FluidRankHalo& ranks);

/// Sends every rank this rank's particles within `reach` of its box (their ids, kinds, `positions` and velocities)
/// and fills `ghosts` (position, velocity, kind) and the FluidRankHalo's ghost ids, send lists and offsets with what
/// the others send. `positions` are those the search uses (r^k or r*). In a periodic tank each particle's images
/// across the periodic faces go too (to this rank as well, so the ranks' ghosts replace the periodic halo): a ghost is
/// then an image, its position the real's plus whole periods. Collective.
void build_fluid_rank_ghosts(const ParticleState& particles, const std::vector<Vec3>& positions, double reach,
                             const PeriodicBox& box, FluidRankHalo& ranks, FluidGhosts& ghosts);

/// How far the farthest of any rank's particles lies outside its rank's box at `positions` (0 when all are inside),
/// the same on every rank. A particle leaves its box between migrations (the lists' skin allows half a skin) and r*
/// may lie up to a step's travel past a periodic face: the ghosts' reach grows by this, so that every particle within
/// the lists' radius of a real is a real or a ghost whatever box the real sits in. Collective.
double fluid_box_overflow(const std::vector<Vec3>& positions, const FluidRankHalo& ranks);

/// The ghosts' positions from their owners' `real` positions (r^k or r*) plus each copy's periodic shift, along the
/// last build's send lists, point to point. Collective.
void exchange_fluid_ghost_positions(const std::vector<Vec3>& real, const FluidRankHalo& ranks, std::vector<Vec3>& ghost);

/// Throws unless the ghosts were built (build_fluid_rank_ghosts) for a table of `reals` particles: a field sent to
/// them holds one value per particle, walls and dummies included.
void check_fluid_ghost_build(std::size_t reals, const FluidRankHalo& ranks);

/// ghost[g] for every ghost from `sent(r, n)`, the value of the n-th copy sent to rank r along the last build's send
/// lists, point to point (the sizes are known on both sides). Collective.
template <class T, class Sent>
void send_to_fluid_ghosts(const FluidRankHalo& ranks, const Sent& sent, std::vector<T>& ghost) {
  const auto count = static_cast<std::size_t>(ranks::size());
  constexpr std::size_t kBytes = std::is_same_v<T, Vec3> ? 3 * sizeof(double) : sizeof(T);
  std::vector<std::vector<std::byte>> outgoing(count);
  std::vector<std::size_t> incoming_bytes(count);
  for (std::size_t r = 0; r < count; ++r) {
    ByteWriter out(outgoing[r]);
    for (std::size_t n = 0; n < ranks.send_slots[r].size(); ++n) out.put(T(sent(r, n)));
    incoming_bytes[r] = kBytes * (ranks.receive_offsets[r + 1] - ranks.receive_offsets[r]);
  }
  const std::vector<std::vector<std::byte>> incoming = ranks::exchange_known(outgoing, incoming_bytes);
  ghost.resize(ranks.ghost_count());
  for (std::size_t r = 0; r < count; ++r) {
    ByteReader in(incoming[r]);
    for (std::uint32_t g = ranks.receive_offsets[r]; g < ranks.receive_offsets[r + 1]; ++g) ghost[g] = in.get<T>();
  }
}

/// ghost[g] = the owner's real[slot] for every ghost: a field that does not move with a periodic image (not a
/// position). T: Vec3 or a plain number type. Collective.
template <class T>
void exchange_fluid_ghost_field(const std::vector<T>& real, const FluidRankHalo& ranks, std::vector<T>& ghost) {
  check_fluid_ghost_build(real.size(), ranks);
  send_to_fluid_ghosts<T>(ranks, [&](std::size_t r, std::size_t n) { return real[ranks.send_slots[r][n]]; }, ghost);
}

/// The unknowns of a system with one row per particle of some (the pressure equation's: the fluid particles off the
/// free surface), numbered over all the ranks: this rank's rows follow the lower ranks' (rows [first_row,
/// first_row + own) of global_rows). `local_row[i]`: particle i's row on this rank, or -1 for none.
struct RankRows {
  std::size_t first_row = 0;
  std::size_t global_rows = 0;
  std::vector<std::int64_t> ghost_row;  ///< [G] each ghost's global row on its owner, or -1 for none
};

/// Numbers the rows over the ranks (one gather of the counts) and sends each ghost its owner's global row (a ghost
/// field along the last build's send lists). `local_row` holds one entry per particle and numbers this rank's rows
/// 0 .. own - 1 without gaps. Collective.
RankRows number_rows_over_ranks(const std::vector<std::int32_t>& local_row, const FluidRankHalo& ranks);

/// Reorders the table so that the fluid comes first, each kind keeping its order (a stable partition): what the
/// neighbour lists need (fluid_slot_count).
void put_fluid_first(FluidParticles& particles);

/// Every rank's particles at rank 0, ordered by id (the whole water for the outputs); empty elsewhere. Collective.
FluidParticles gather_fluid_at_root(const FluidParticles& particles);

}  // namespace riffle
