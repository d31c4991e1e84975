#pragma once
// Fickian particle shifting after the pressure correction (docs/FLUID.md, "Particle shifting";
// systems/physics/mps/particle_shifting.hpp): each fluid particle moves by delta r = -D grad C, C = n / n0 summed over
// fluid, wall and dummy neighbours at r^{k+1} (walls and dummies never move: they only push the water off them), the
// shift capped at fluid.shifting_max l0, without its normal component at free-surface particles and their fluid
// neighbours (Khayyer, Gotoh & Shimizu 2017), and optionally the velocity carried to the new position to first
// order, u += (delta r . grad) u with the GC-corrected gradient (Lind et al. 2012). Positions are wrapped into a
// periodic tank's period as fluid_correct wraps them. Registered only when the scene sets [fluid] shifting.
#include <vector>

#include "systems/system.hpp"
#include "systems/physics/mps/mps_common.hpp"

namespace riffle {

class FluidShift final : public System {
 public:
  explicit FluidShift(const FluidModel& fluid)
      : fluid_(fluid), constants_(mps_constants(fluid)), kernel_(constants_.effective_radius) {}
  std::string_view name() const override { return "fluid_shift"; }
  Access access() const override {
    return {component_ids<FluidNeighbours, ParticlePrediction, ParticleDensity>(), component_ids<ParticleState>()};
  }
  void run(SystemContext& context) override;

 private:
  FluidModel fluid_;
  MpsConstants constants_;
  WendlandKernel kernel_;
  std::vector<Vec3> shift_, velocity_;  // scratch: every shift is computed before any particle moves
  // Over MPI ranks, what a ghost's owner on another rank holds and the shift reads: its correction's displacement,
  // its corrected velocity and its free-surface flag (the reals' displacements in `displacement_`).
  std::vector<Vec3> displacement_, ghost_displacement_, ghost_velocity_;
  std::vector<std::int32_t> ghost_free_surface_;
};

}  // namespace riffle
