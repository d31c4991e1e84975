#pragma once
// The water over MPI ranks: at the step's start, when the neighbour lists are to be rebuilt on any rank, each
// particle (fluid, wall or dummy) goes with all its fields to the rank whose box holds it (migrate_fluid_particles,
// systems/physics/ranks/fluid_ranks.hpp), so that the search that follows builds every rank's lists and ghosts
// around the particles in its box. Registered only in a run over ranks (the one-rank step graph is unchanged), first
// in the step, before the step-start search, whose rebuild test it asks (FluidNeighbourSearch::lists_still_valid):
// between rebuilds nothing moves between ranks. Before the migration the boxes are cut anew when the work they hold
// (fluid_work_per_box) has grown unequal (a dam break's water runs out of its box), as the grains' are.
#include "systems/system.hpp"
#include "systems/physics/geometry/periodic_box.hpp"
#include "systems/physics/mps/mps_common.hpp"

namespace riffle {

class FluidRankMigration final : public System {
 public:
  /// `reach`: the lists' widest radius (r_e + skin), the distance within which a wall works for the water.
  FluidRankMigration(double effective_radius, double reach, const PeriodicBox& box)
      : effective_radius_(effective_radius), reach_(reach), box_(box) {}
  std::string_view name() const override { return "fluid_rank_migration"; }
  Access access() const override { return {{}, component_ids<FluidParticles, FluidNeighbours>()}; }
  void run(SystemContext& context) override;

 private:
  double effective_radius_;
  double reach_;
  PeriodicBox box_;
};

}  // namespace riffle
