#pragma once
// Reorders the grains by grid cell every `solids.sort_every` steps so that neighbours sit close in memory.
// Ids and all per-grain fields travel together (permute_fields walks the field table); state kept per pair is keyed
// by id, so it stays valid. The order is a pure function of the positions, hence identical for any thread count.
#include <cstddef>
#include <vector>

#include "systems/system.hpp"
#include "systems/physics/geometry/cell_order.hpp"

namespace riffle {

/// Slot order that sorts grains by the linear index (z, y, x) of their cell; ties keep the current order.
inline std::vector<std::size_t> cell_order(const Solids& solids, const Vec3& origin, double cell_size) {
  return cell_order(solids.position, solids.size(), origin, cell_size);
}

class SolidCellSort final : public System {
 public:
  std::string_view name() const override { return "solid_cell_sort"; }
  Access access() const override { return {{}, component_ids<Solids>()}; }
  void run(SystemContext& context) override;
};

}  // namespace riffle
