#pragma once
// Reorders the MPS particles by cell, so that the neighbours every pair loop gathers (number density, sources, PPE
// rows, gradient) sit close in memory, and the neighbour search finds them nearly in slot order (its insertion sort
// then has little to do). Sloshing water mixes: unsorted, the pair loops and the search slow down two- to threefold
// within a few periods (docs/BENCHMARKS.md).
//
// When: every `fluid.sort_every` steps, and every `fluid.sort_every_fast` steps while the fastest particle moves more
// than 0.15 l0 in a step (half the default skin of 0.3 l0: the water moves together, the next fastest about as far, so
// then not even the wide lists outlive a step; the threshold does not follow the skin settings, so that they change no
// result). It runs after the prediction, right before the search at the predicted positions r*, and sorts by the cells
// of r*: in fast flow that search rebuilds the lists every step anyway, so a sort then costs only the permutation, no
// extra rebuild. The decision depends only on the step and the state, so a resumed run sorts where the uninterrupted
// one did.
//
// The cells are those of the neighbour search (fluid_search_cell_size) on a lattice that rides with the tank, so
// wall and dummy particles keep their cells and their order after the first sort, and then only the fluid slots move.
// Fluid particles stay in slots [0, F), walls and dummies after them; ids and every per-particle field travel
// together (the field table). The order is a pure function of the positions, so it is the same for any thread count;
// the neighbour lists, which hold slots, are marked reordered (the built positions travel with the particles).
#include "systems/system.hpp"
#include "systems/physics/mps/mps_common.hpp"

namespace riffle {

class FluidCellSort final : public System {
 public:
  /// `search_radius` [m]: the neighbour search's radius (r_e + skin), whose cells the particles are grouped by.
  /// `fast_displacement` [m]: a step in which some fluid particle moves farther than this counts as fast flow.
  FluidCellSort(std::int64_t every, std::int64_t every_fast, double search_radius, double fast_displacement)
      : every_(every), every_fast_(every_fast), search_radius_(search_radius), fast_displacement_(fast_displacement) {}
  std::string_view name() const override { return "fluid_cell_sort"; }
  Access access() const override { return {{}, component_ids<FluidParticles, FluidNeighbours>()}; }
  void run(SystemContext& context) override;

 private:
  bool due(const SystemContext& context, const FluidParticles& particles, std::size_t fluid_count) const;

  std::int64_t every_;
  std::int64_t every_fast_;
  double search_radius_;
  double fast_displacement_;
};

}  // namespace riffle
