#include "systems/physics/dem/touching_springs.hpp"

namespace riffle {

EntityId grain_id_behind(const Solids& solids, const Contacts& contacts, std::uint32_t j) {
  const RankHalo& ranks = contacts.ranks;
  if (ranks.active && j >= ranks.real_count) return ranks.ghost_id[j - ranks.real_count];
  return solids.id[contacts.halo.valid ? contacts.halo.owner_of(j) : j];
}

std::vector<CarriedSpring> touching_pair_springs(const Solids& solids, const Contacts& contacts) {
  std::vector<CarriedSpring> springs;
  if (!contacts.valid || contacts.pair_offsets.size() != solids.size() + 1) return springs;
  for (std::size_t i = 0; i < solids.size(); ++i)
    for (std::uint32_t k = contacts.pair_offsets[i]; k < contacts.pair_offsets[i + 1]; ++k) {
      if (contacts.pair_overlap[k] <= 0.0) continue;
      const EntityId first = solids.id[i], second = grain_id_behind(solids, contacts, contacts.pair_second[k]);
      const Vec3& spring = contacts.pair_spring[k];
      const Vec3& rolling = contacts.pair_rolling_spring[k];
      springs.push_back(first < second ? CarriedSpring{first, second, spring, rolling}
                                       : CarriedSpring{second, first, -spring, -rolling});
    }
  return springs;
}

std::vector<CarriedSpring> touching_wall_springs(const Solids& solids, const Contacts& contacts) {
  std::vector<CarriedSpring> springs;
  if (!contacts.valid || contacts.wall_pair_offsets.size() != solids.size() + 1) return springs;
  for (std::size_t i = 0; i < solids.size(); ++i)
    for (std::uint32_t k = contacts.wall_pair_offsets[i]; k < contacts.wall_pair_offsets[i + 1]; ++k)
      if (contacts.wall_pair_overlap[k] > 0.0)
        springs.push_back({solids.id[i], contacts.wall_pair_wall[k], contacts.wall_pair_spring[k],
                           contacts.wall_pair_rolling_spring[k]});
  return springs;
}

}  // namespace riffle
