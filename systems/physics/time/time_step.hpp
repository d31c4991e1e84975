#pragma once
// The one place that decides how long an engine step is and how it is cut into the grains' sub-steps: run.dt,
// shortened by the fluid's stability limits (numerics 1.5: the Courant number and the viscous diffusion number; the
// deep water's hydrostatic limit, docs/FLUID.md) and by the water's relaxation under the grains' drag (docs/COUPLING.md, "The drag's step limit"), then split into
// sub-steps no longer than the scene's solid_dt(). The stepper asks once per step and stores the
// answer in the World; the diagnostics print it.
#include <optional>
#include <cstdint>

#include "components/model.hpp"
#include "components/step_lengths.hpp"
#include "components/solids.hpp"
#include "systems/physics/mps/mps_common.hpp"

namespace riffle {

/// [1/s] The fastest rate at which the grains' drag pulls the water around them towards their velocity, over the wet
/// grains (0 if none): per grain, lambda = dF/du summed over the grains in a volume of water, per mass of that water,
/// for the drag law as solid_drag applies it (F = k V (u - v) / s, s = eps in the mixture reading, else 1) and its
/// reaction as fluid_drag_reaction spreads it (over eps in the mixture reading): with (1 - eps) / V grains per volume,
///     lambda = k(eps, d, |slip|) (1 - eps) / (rho_f s_w s),   s_w = eps (mixture) or 1 (pore),
/// k the drag per volume and slip of drag_law.hpp at the grain's sampled voidage and slip (the secant coefficient:
/// the tangent of the quadratic Ergun term is at most twice it). The reaction is explicit and a step late: the drag
/// of step n uses the water sampled at its start and reaches the water in step n + 1's prediction, so the water's
/// slip obeys u_{n+2} = u_{n+1} - a u_n, a = lambda_tangent dt, which oscillates for a > 1/4 and grows for a > 1.
/// Not covered: the self-induced correction's dilute grains (eps > 0.8) draw a drag up to 1/(1 - gain) times k V / s
/// from the sampled velocity, but their (1 - eps) < 0.2 keeps their rate small.
double water_drag_rate(const Model& model, const GrainState& grains, const GrainProperties& properties,
                       const GrainSampledFluid& sampled, const GrainVoidage& voidages);

/// The lengths of the next step. `fluid` is the scene's MPS particles (nullptr without a fluid): its largest speed,
/// its depth and the viscosity may shorten run.dt, and so may `drag_rate` (water_drag_rate, 0 = no grains in the
/// water): the step is at most coupling.drag_number / drag_rate. A step below fluid.min_dt is returned as it is; the
/// stepper stops on it.
StepLengths decide_step_lengths(const Model& model, const ParticleState* fluid, double drag_rate = 0.0);
/// The same from the water's largest squared speed (none: no water) and its depth [m] (water_depth; 0: no limit),
/// given where they are not this table's: over MPI ranks, every rank's largest speed and the whole water's extent.
StepLengths decide_step_lengths(const Model& model, std::optional<double> fluid_max_speed_squared, double drag_rate,
                                double water_depth = 0.0);
/// The largest |u|^2 of the table's fluid particles (0 without any).
double max_squared_speed(const ParticleState& particles);

/// [m] The lowest and highest of the fluid particles' centres along gravity's direction (low > high: no fluid
/// particle, or no gravity): the water's extent that sets its hydrostatic head.
struct WaterExtent {
  double low = 0.0;
  double high = -1.0;
};
WaterExtent water_extent(const ParticleState& particles, const Vec3& gravity);
/// [m] H, the water's depth for the hydrostatic limit: the extent plus l0 (each particle stands for a layer l0
/// thick); 0 without fluid or gravity.
inline double water_depth(const WaterExtent& extent, double spacing) {
  return extent.high >= extent.low ? extent.high - extent.low + spacing : 0.0;
}

}  // namespace riffle
