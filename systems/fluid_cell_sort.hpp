#pragma once
// Reorders the MPS particles by cell every `fluid.sort_every` steps, so that the neighbours every pair loop gathers
// (number density, sources, PPE rows, gradient) sit close in memory, and the neighbour search finds them nearly in
// slot order. Sloshing water mixes: unsorted, the pair loops and the search slow down two- to threefold within a
// few periods (docs/BENCHMARKS.md). The cells are those of the neighbour search (fluid_search_cell_size) on a
// lattice that rides with the tank, so wall and dummy particles keep their cells and their order after the first
// sort. Fluid particles stay in slots [0, F), walls and dummies after them; ids and every per-particle field travel
// together (permute_fields walks the field table). The order is a pure function of the positions and the step, so
// it is the same for any thread count and after a resume; the neighbour lists, which hold slots, are marked stale.
#include "engine/system.hpp"
#include "systems/fluid_common.hpp"

namespace riffle {

class FluidCellSort final : public System {
 public:
  /// `search_radius` [m]: the neighbour search's radius (r_e + skin), whose cells the particles are grouped by.
  FluidCellSort(std::int64_t every, double search_radius) : every_(every), search_radius_(search_radius) {}
  std::string_view name() const override { return "fluid_cell_sort"; }
  Access access() const override { return {{}, {ComponentId::kFluid, ComponentId::kFluidNeighbours}}; }
  void run(SystemContext& context) override;

 private:
  std::int64_t every_;
  double search_radius_;
};

}  // namespace riffle
