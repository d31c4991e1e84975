#pragma once
// Explicit prediction (seed 000 Eq. 2; numerics 2.1): u* = u^k + dt (nu lap u + g), r* = r^k + dt u*, with the
// lambda0 Laplacian (numerics 1.4); wall and dummy particles carry the wall velocity (no slip).
// With ECS on (seed 000 Eq. 6; numerics 2.3) the same pass over the neighbours at (r^k, u^k) also forms the ECS
// input |e| Dn/Dt + |Dn/Dt| e, with e = (n^k - n0)/n0 and Dn/Dt the HS rate, fluid-wall pairs counted twice (no
// wall row takes their half): both need the same pairs at the same state, and one pass instead of two saves about
// a tenth of the fluid step (docs/BENCHMARKS.md).
// Driven flows (docs/FLUID.md): a body force f along x joins g; the SPS eddy viscosity nu_t = (C_s l0)^2 |S|
// (Gotoh, Shibahara & Sakai 2001) joins nu with the pair viscosity nu + (nu_t,i + nu_t,j)/2; a moving lid's
// particles carry its velocity into the viscous term, extrapolated across its plane (no slip: Morris, Fox & Zhu
// 1997), or stay out of it (free slip).
#include <cstdint>
#include <vector>

#include "systems/system.hpp"
#include "systems/physics/mps/mps_common.hpp"

namespace riffle {

class FluidPredict final : public System {
 public:
  explicit FluidPredict(const FluidModel& fluid)
      : fluid_(fluid), constants_(mps_constants(fluid)), kernel_(constants_.effective_radius) {}
  std::string_view name() const override { return "fluid_predict"; }
  // A scene with a body force or a lid also writes FluidSummary (the force applied, the lids' traction, the bulk
  // velocity; the controller's integral), so only such scenes gain the edges.
  Access access() const override {
    if (fluid_.reports_driving())
      return {component_ids<FluidNeighbours>(),
              component_ids<ParticleState, ParticlePrediction, ParticleDragReaction, FluidSummary>()};
    return {component_ids<FluidNeighbours>(), component_ids<ParticleState, ParticlePrediction, ParticleDragReaction>()};
  }
  void run(SystemContext& context) override;

 private:
  /// The body force along x for this step [m/s^2] (the controller's output for kind bulk_velocity).
  double body_force(SystemContext& context, const ParticleState& particles, std::size_t fluid_count);
  /// Viscous term with the SPS eddy viscosity, free-slip lids and the lids' traction; the plain loop
  /// in run() is left as it was so that scenes without these give main's bits.
  void driven_viscous_loop(SystemContext& context, const Vec3& body_acceleration);

  FluidModel fluid_;
  MpsConstants constants_;
  WendlandKernel kernel_;
  std::vector<Vec3> acceleration_;  ///< [m/s^2] scratch: the gather reads u^k while u* is formed
  std::vector<double> eddy_viscosity_;  ///< [m^2/s] nu_t per fluid slot (turbulence = "sps", scatter_viscosity > 0)
  std::vector<std::int32_t> lid_of_;    ///< per slot: the lid (index among the lid boxes) or -1
  std::vector<Vec3> lid_force_;         ///< [N] per fluid slot and lid: the lid's viscous force on the particle
  /// Over MPI ranks: each real's lid and nu_t (0 for walls) as sent to the other ranks' ghosts, and the ghosts' own.
  std::vector<std::int32_t> real_lid_, ghost_lid_;
  std::vector<double> real_eddy_, ghost_eddy_;
};

}  // namespace riffle
