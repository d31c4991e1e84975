#pragma once
// What the grains and the MPS water read of each other across the ranks' edges, in a run of grains in MPS water
// spread over MPI ranks (the grains by grain_ranks, the water by fluid_ranks, each over its own boxes). The coupling's
// kernels and grids reach farther than either family's own halo (a grain samples the water within r + r_e, the
// voidage grid deposits over a few cells of 0.668 R_eps, the drag reaction's over cells of 0.668 (r + r_e)), so each
// coupling system gathers, at the moment it runs, what lies within its own reach of this rank's boxes (the grains'
// and the water's): the other ranks' grains and fluid particles, at their real (unwrapped) positions, never this
// rank's own, once each. A periodic box's seams are handled by the systems as on one rank (grids that wrap, kernels
// completed by images): a copy is sent when any periodic image of it lies within reach of a box.
// Every exchange is an MPI_Alltoallv over the rank layer's communicator (ranks::exchange); the step's systems run one
// after another over ranks (engine/run/stepper.cpp), so no two threads call MPI at once.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "components/vec.hpp"
#include "systems/physics/geometry/periodic_box.hpp"
#include "systems/physics/geometry/recursive_bisection.hpp"

namespace riffle {

/// Every rank's boxes that what this rank sends must reach: the grains' boxes, the water's boxes, or both (one list
/// per rank, in rank order; the same on every rank), and the reach beyond them.
struct CouplingBoxes {
  std::vector<std::vector<PartBox>> of_rank;  ///< [ranks] the boxes of each rank
  double reach = 0.0;                         ///< [m] how far beyond a box a copy is still needed
};

/// Whether `point`, or any of its periodic images along `box`'s periodic axes, lies within `reach` of `part` along
/// every axis (inside the part grown by `reach`).
bool near_part(const Vec3& point, const PartBox& part, double reach, const PeriodicBox& box);

/// For each rank r other than this one, the indices i < positions.size() whose point is near (near_part) any of
/// r's boxes, ascending; this rank's own list is empty.
std::vector<std::vector<std::uint32_t>> indices_near_other_ranks(std::span<const Vec3> positions,
                                                                 const CouplingBoxes& boxes, const PeriodicBox& box);

/// How far the farthest of `positions` lies outside `own` (0 when all are inside), the largest over the ranks: the
/// drift of a family's members out of their boxes between migrations, which every reach must add. Along a periodic
/// axis of `box` the nearest image counts (a member wrapped across a seam before it migrates is still beside its
/// box). Collective.
double overflow_over_ranks(std::span<const Vec3> positions, const PartBox& own, const PeriodicBox& box);

/// Every rank's box of one family's decomposition (its halo's corner lists, `box_low` and `box_high`), to be reached
/// within `reach` plus how far that family's members stray out of their boxes (overflow_over_ranks of this rank's
/// `members`). Collective.
CouplingBoxes coupling_boxes(const std::vector<Vec3>& box_low, const std::vector<Vec3>& box_high,
                             std::span<const Vec3> members, double reach, const PeriodicBox& box);

/// Both families' boxes at once: each rank's boxes of `first`, then of `second`; the larger reach.
CouplingBoxes either_family(CouplingBoxes first, const CouplingBoxes& second);

/// The lowest corner of every rank's `positions` (each coordinate's minimum over all the ranks' points; +huge with
/// none): the anchor of a grid whose nodes must lie where one rank's grid over all the points puts them
/// (VoidageGrid's lattice starts at its points' lowest corner). Collective.
Vec3 lowest_corner_over_ranks(std::span<const Vec3> positions, std::span<const Vec3> more = {});

/// Sends rank r the records `pack(out, i)` of the indices near_ranks[r] and returns, in rank order, what every rank
/// sent here: `unpack(in)` is called once per record received. Collective.
template <class Pack, class Unpack>
std::size_t exchange_records(const std::vector<std::vector<std::uint32_t>>& near_ranks, const Pack& pack,
                             const Unpack& unpack);

}  // namespace riffle

#include "systems/physics/ranks/rank_messages.hpp"

namespace riffle {

template <class Pack, class Unpack>
std::size_t exchange_records(const std::vector<std::vector<std::uint32_t>>& near_ranks, const Pack& pack,
                             const Unpack& unpack) {
  std::vector<std::vector<std::byte>> outgoing(near_ranks.size());
  for (std::size_t r = 0; r < near_ranks.size(); ++r) {
    if (near_ranks[r].empty()) continue;
    ByteWriter out(outgoing[r]);
    out.put(static_cast<std::uint64_t>(near_ranks[r].size()));
    for (const std::uint32_t i : near_ranks[r]) pack(out, i);
  }
  const std::vector<std::vector<std::byte>> incoming = ranks::exchange(outgoing);
  std::size_t received = 0;
  for (const std::vector<std::byte>& bytes : incoming) {
    if (bytes.empty()) continue;
    ByteReader in(bytes);
    const auto count = in.get<std::uint64_t>();
    for (std::uint64_t k = 0; k < count; ++k) unpack(in);
    received += count;
    if (!in.done()) throw std::logic_error("coupling_ranks: a message longer than its records");
  }
  return received;
}

}  // namespace riffle
