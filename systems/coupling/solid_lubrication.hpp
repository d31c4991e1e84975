#pragma once
// solid_lubrication: the normal lubrication force of the water squeezed between two grains, or between a grain and
// a wall, every DEM sub-step (systems/physics/coupling/lubrication.hpp: Cox & Brenner 1967, Brenner 1961, Jeffrey 1982;
// docs/COUPLING.md "Lubrication"). Only wet grains feel it (GrainSampledFluid::fluid_weight > 0; a pair when both
// are wet). The candidates are the contacts' neighbour list, which reaches the cut-off when lubrication is on
// (solid_neighbours adds it to each pair's and wall's reach). Equal and opposite between grains; the walls take the
// reaction (not added to the wall-force probe). Semi-implicit along the normal (implicit_coefficient), so any
// viscosity and roughness is stable at the contacts' sub-step. In a periodic box a pair's second grain may be a ghost
// across the seam (components/halo.hpp), read through the halo as solid_contacts does; its reaction goes to the owner.
// Over MPI ranks likewise a grain of another rank (grain_ranks.hpp): its reaction is sent to its rank.
#include <vector>

#include "systems/system.hpp"

namespace riffle {

class SolidLubrication final : public System {
 public:
  explicit SolidLubrication(const Model& model);
  std::string_view name() const override { return "solid_lubrication"; }
  Access access() const override {
    return {component_ids<GrainState, GrainProperties, GrainSampledFluid, Contacts, Walls>(),
            component_ids<GrainLubrication>()};
  }
  void run(SystemContext& context) override;

 private:
  CouplingModel model_;
  double viscosity_ = 0.0;        ///< [Pa s] mu of the water
  std::vector<Vec3> pair_force_;  ///< [N] scratch: the force on each candidate pair's first grain
  std::vector<double> ghost_weight_;  ///< over MPI ranks: the other ranks' grains' sampling weights (their owners')
};

}  // namespace riffle
