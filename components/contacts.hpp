#pragma once
// Grain-grain and grain-wall contact candidates (a Verlet neighbour list with a skin) and their persistent state.
//
// Pairs are stored once, from the grain with the lower slot ("first") to the higher ("second"), grouped by first
// grain in CSR form. Slots change only when the list is rebuilt (the rebuild may reorder the grains by cell); the
// tangential springs are carried over by grain id, so contact history survives reordering and checkpoints.
// The contact pass adds each pair's force to both grains, slab by slab (systems/physics/dem/contact_slabs.hpp), in
// an order that does not depend on the thread count.
#include <cereal/types/vector.hpp>
#include <cstdint>
#include <string_view>
#include <type_traits>
#include <vector>

#include "components/component_id.hpp"
#include "components/halo.hpp"
#include "components/vec.hpp"

namespace riffle {

struct Contacts {
  static constexpr ComponentId kId = component_id<Contacts>;
  static constexpr std::string_view kName = "contacts";
  static constexpr bool kPersistent = true;

  // Grain-grain candidates.
  std::vector<std::uint32_t> pair_offsets;     ///< grains + 1: pairs of first grain i are [offsets[i], offsets[i+1])
  std::vector<std::uint32_t> pair_second;      ///< slot of the second grain (> first), or of a ghost (halo below)
  std::vector<Vec3> pair_spring;               ///< [m] tangential spring, on the first grain; zero when apart
  /// [N m] rolling spring torque on the first grain ([contact] rolling_law = "elastic_plastic"; zero otherwise and
  /// when apart)
  std::vector<Vec3> pair_rolling_spring;
  std::vector<double> pair_overlap;            ///< [m] > 0 while touching, 0 when apart
  // Reverse index for pair forces gathered per grain (lubrication): for grain j, the pairs where it is second,
  // ascending.
  std::vector<std::uint32_t> second_offsets;   ///< grains + 1
  std::vector<std::uint32_t> second_pairs;     ///< pair indices
  // The contact pass's slabs (systems/physics/dem/contact_slabs.hpp): slots grouped by slab, a pure function of
  // build_position and the list's reach, so not checkpointed (rebuilt on resume, as the halo is).
  std::vector<std::uint32_t> slab_offsets;     ///< slabs + 1; empty: one slab of every grain in slot order
  std::vector<std::uint32_t> slab_grains;      ///< grains
  bool slab_periodic = false;                  ///< the slabs' axis is periodic: the last slab neighbours the first

  // Grain-wall candidates, grouped by grain.
  std::vector<std::uint32_t> wall_pair_offsets;  ///< grains + 1
  std::vector<std::uint32_t> wall_pair_wall;     ///< wall slot (walls are never reordered)
  std::vector<Vec3> wall_pair_spring;            ///< [m] tangential spring, on the grain
  std::vector<Vec3> wall_pair_rolling_spring;    ///< [N m] rolling spring torque on the grain (as pair_rolling_spring)
  std::vector<Vec3> wall_pair_force;             ///< [N] force on the grain (the wall gets the negative)
  std::vector<Vec3> wall_pair_torque;            ///< [N m] torque on the grain
  std::vector<double> wall_pair_overlap;         ///< [m] > 0 while touching, 0 when apart

  // Periodic boxes ([tank] periodic): the ghosts of the grains within the list's reach of a seam. A pair's second
  // slot may be a ghost (>= grains, see components/halo.hpp); its force goes to the owner (the reverse index above
  // is by owner slot). Not checkpointed, hence not in for_each_member: the halo is a pure function of
  // build_position (systems/physics/geometry/periodic_box.hpp build_halo), rebuilt from it on resume; the ghost copies are
  // exchanged every sub-step by solid_neighbours.
  Halo halo;
  GrainGhosts ghosts;
  /// A run spread over MPI ranks: the other ranks' grains near this one's box, whose copies are in `ghosts` too (a
  /// pair's second slot >= grains is then one of them). Not checkpointed, like the halo.
  RankHalo ranks;

  // Rebuild bookkeeping.
  std::vector<Vec3> build_position;              ///< [m] grain positions at the last rebuild (per slot)
  Vec3 build_tank_displacement = Vec3::Zero();   ///< [m] tank displacement at the last rebuild
  double skin = 0.0;                             ///< [m] the skin the list was built with
  std::uint64_t rebuilds = 0;                    ///< rebuilds so far
  bool valid = false;                            ///< false until the first build (and after a resize)

  std::size_t pair_count() const { return pair_second.size(); }
  std::size_t wall_pair_count() const { return wall_pair_wall.size(); }

  /// Every member once, in checkpoint order: `visit(name, persistent, member)`. The arrays are not one value per
  /// grain throughout (pairs, CSR offsets), so this table drives the checkpoint only, not resize or reorder.
  template <class Self, class Visit>
  static void for_each_member(Self& self, Visit&& visit) {
    visit("pair_offsets", true, self.pair_offsets);
    visit("pair_second", true, self.pair_second);
    visit("pair_spring", true, self.pair_spring);
    visit("pair_rolling_spring", true, self.pair_rolling_spring);
    visit("pair_overlap", true, self.pair_overlap);
    visit("second_offsets", true, self.second_offsets);
    visit("second_pairs", true, self.second_pairs);
    visit("wall_pair_offsets", true, self.wall_pair_offsets);
    visit("wall_pair_wall", true, self.wall_pair_wall);
    visit("wall_pair_spring", true, self.wall_pair_spring);
    visit("wall_pair_rolling_spring", true, self.wall_pair_rolling_spring);
    visit("wall_pair_force", true, self.wall_pair_force);
    visit("wall_pair_torque", true, self.wall_pair_torque);
    visit("wall_pair_overlap", true, self.wall_pair_overlap);
    visit("build_position", true, self.build_position);
    visit("build_tank_displacement", true, self.build_tank_displacement);
    visit("skin", true, self.skin);
    visit("rebuilds", true, self.rebuilds);
    visit("valid", true, self.valid);
  }

  template <class Archive>
  void serialize(Archive& archive) {
    for_each_member(*this, [&](const char* name, bool persistent, auto& member) {
      // Formats before kFirstFormatWithRollingSprings have no rolling springs: zero, one per pair (visited after the
      // tangential springs, whose sizes they take).
      if constexpr (requires { archive.format_version(); })
        if (archive.format_version() < kFirstFormatWithRollingSprings) {
          if constexpr (std::is_same_v<std::decay_t<decltype(member)>, std::vector<Vec3>>) {
            if (std::string_view(name) == "pair_rolling_spring") {
              member.assign(pair_spring.size(), Vec3::Zero());
              return;
            }
            if (std::string_view(name) == "wall_pair_rolling_spring") {
              member.assign(wall_pair_spring.size(), Vec3::Zero());
              return;
            }
          }
        }
      if (persistent) archive(member);
      // Formats up to kLastFormatWithPairForces kept each pair's force and torques after its spring; the contact
      // pass recomputes them every sub-step, so a resume reads and drops them.
      if constexpr (requires { archive.format_version(); })
        if (archive.format_version() <= kLastFormatWithPairForces && std::string_view(name) == "pair_spring") {
          std::vector<Vec3> force, torque_first, torque_second;
          archive(force, torque_first, torque_second);
        }
    });
  }

  /// The last checkpoint format with per-pair forces and torques (engine/output/checkpoint.hpp).
  static constexpr std::uint32_t kLastFormatWithPairForces = 12;
  /// The first checkpoint format with the rolling springs.
  static constexpr std::uint32_t kFirstFormatWithRollingSprings = 15;
};

}  // namespace riffle
