#pragma once
// Neighbour lists of all MPS particles (fluid, wall, dummy) within a search radius (>= r_e; numerics 1.1, 1.3):
// a uniform cell grid over the particles' bounding box with cells at least one radius wide, counted, scanned and
// filled in parallel (oneTBB). Each particle's list is its neighbours' slots in ascending order, self excluded, so
// the lists (and every sum over them) do not depend on the thread count, the grid or the cell size.
//
// Choice: the lists live in their own component, FluidNeighbours (like Contacts for the grains), not in
// FluidParticles: the build reads the particles and writes only the lists, so the scheduler can order it before
// every operator that reads the lists and writes the particles. The lists are rebuilt from positions every step
// (the fluid moves less than l0 per step; a skin, as in OpenMps' r_e (1 + 2 Cr), can be had by passing a larger
// radius: the operators cut at r_e themselves).
#include <vector>

#include "engine/system.hpp"

namespace riffle {

/// Builds `neighbours` for `positions`: j is a neighbour of i (j != i) iff |r_j - r_i| < radius. Non-finite
/// positions get no neighbours and are nobody's neighbour.
void build_fluid_neighbours(const std::vector<Vec3>& positions, double radius, FluidNeighbours& neighbours);

class FluidNeighbourSearch final : public System {
 public:
  /// `radius` [m]: the search radius, normally the effective radius r_e.
  explicit FluidNeighbourSearch(double radius) : radius_(radius) {}
  std::string_view name() const override { return "fluid_neighbours"; }
  Access access() const override { return {{ComponentId::kFluid}, {ComponentId::kFluidNeighbours}}; }
  void run(SystemContext& context) override;

 private:
  double radius_;
};

}  // namespace riffle
