#pragma once
// Slabs of grains for a contact pass that adds each pair's force to both of its grains (Newton's third law) in a
// fixed order whatever the thread count.
//
// The grains are cut into S slabs along one axis, each at least `reach` thick (the longest candidate distance of the
// neighbour list), by their positions at the list's build. A pair's grains then lie in the same slab or in
// neighbouring ones (mod S along a periodic axis), so a pass over the pairs whose first grain lies in slab s writes
// only to slabs s - 1, s and s + 1. Slab s belongs to phase s mod 3; two slabs' tasks that write common grains (two
// slabs apart or closer) run one after the other, the lower phase first, and the others side by side
// (systems/dem/solid_contacts.cpp): every grain receives its contributions from its own slab's task and its two
// neighbours' in phase order, so the sums are the same on any number of threads. Along a periodic axis S is a multiple
// of 3 (slab S - 1 neighbours slab 0); S is rounded down to a multiple of 6 where it reaches 6. Too few slabs (a box
// under three reaches long on every axis) give S = 1: one task.
#include <array>
#include <cstdint>
#include <vector>

#include "components/vec.hpp"
#include "systems/physics/geometry/periodic_box.hpp"

namespace riffle {

/// The phases of the pass (slab s runs in phase s mod 3).
inline constexpr std::uint32_t kContactSlabPhases = 3;

/// How many slabs of at least `reach` fit along one axis: `extent` long, periodic or not (see above).
std::uint32_t contact_slab_count(double extent, double reach, bool periodic);

/// The slabs of `position` (the grains' positions at the list's build, wrapped into a periodic box): the axis giving
/// the most slabs (x before y before z on a tie), `offsets` (S + 1) and `grains` (every slot once, grouped by slab,
/// ascending within it).
struct ContactSlabs {
  int axis = 0;
  bool periodic = false;  ///< the axis is periodic: slab S - 1 neighbours slab 0
  std::vector<std::uint32_t> offsets{0, 0};
  std::vector<std::uint32_t> grains;
  std::uint32_t count() const { return static_cast<std::uint32_t>(offsets.size() - 1); }
};
ContactSlabs contact_slabs(const std::vector<Vec3>& position, double reach, const PeriodicBox& box);

/// The order of the slabs' tasks: task s writes the grains of slabs s - 1, s and s + 1, so two tasks within two slabs
/// of each other (around the seam along a periodic axis) write common grains and run one after the other, the one of
/// the lower phase (s mod 3) first; the others run side by side as soon as those before them are done. Each task also
/// zeroes the sums of the slabs it is the first to write (the lowest phase of the three that write it).
struct ContactSlabSchedule {
  std::vector<std::vector<std::uint32_t>> after;   ///< per task: the tasks that wait for it
  std::vector<std::uint32_t> waits_for;            ///< per task: how many tasks it waits for
  std::vector<std::vector<std::uint32_t>> zeroes;  ///< per task: the slabs whose sums it zeroes first
};
ContactSlabSchedule contact_slab_schedule(std::uint32_t slabs, bool periodic);

/// Whether slabs `a` and `b` of `slabs` are the same or neighbours: a pair's grains must be, for the pass to hold.
bool neighbouring_slabs(const ContactSlabs& slabs, std::uint32_t a, std::uint32_t b);

}  // namespace riffle
