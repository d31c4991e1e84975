#pragma once
// The contact history a pair list holds, by grain id: what outlives the list's slots when it is rebuilt (the grains
// reordered, wrapped through a periodic face, handed to another rank), written to a checkpoint, or gathered from the
// ranks. A pair's second slot is a real grain, a periodic image (components/halo.hpp, Halo) or another rank's grain
// (RankHalo); the id behind it is the same whichever.
#include <cstdint>
#include <vector>

#include "components/contacts.hpp"
#include "components/solids.hpp"

namespace riffle {

/// The id of the grain behind slot j of the pair list (a real, a periodic image or another rank's ghost).
EntityId grain_id_behind(const Solids& solids, const Contacts& contacts, std::uint32_t j);

/// Every touching pair's tangential spring (overlap > 0), by id and oriented for the lower id, grain by grain in list
/// order. Empty when the list does not match the grains (not built, or built for other slots).
std::vector<CarriedSpring> touching_pair_springs(const Solids& solids, const Contacts& contacts);

/// Every touching wall contact's spring, as (grain id, wall slot), grain by grain in list order; empty as above.
std::vector<CarriedSpring> touching_wall_springs(const Solids& solids, const Contacts& contacts);

/// Orders springs by (lower, higher): the order a lookup by id searches.
inline bool spring_order(const CarriedSpring& a, const CarriedSpring& b) {
  return a.lower != b.lower ? a.lower < b.lower : a.higher < b.higher;
}

}  // namespace riffle
