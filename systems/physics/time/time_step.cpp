#include "systems/physics/time/time_step.hpp"

#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "systems/physics/coupling/drag_law.hpp"

namespace riffle {

/// Largest squared speed of the fluid particles (slots [0, F)); max is exact, so the reduction order does not matter.
double max_squared_speed(const ParticleState& particles) {
  const std::size_t fluid_count = fluid_slot_count(particles);
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, fluid_count, 4096), 0.0,
      [&](const tbb::blocked_range<std::size_t>& range, double found) {
        for (std::size_t i = range.begin(); i < range.end(); ++i)
          found = std::max(found, particles.velocity[i].squaredNorm());
        return found;
      },
      [](double a, double b) { return std::max(a, b); });
}

WaterExtent water_extent(const ParticleState& particles, const Vec3& gravity) {
  const double g = gravity.norm();
  const std::size_t fluid_count = fluid_slot_count(particles);
  if (!(g > 0.0) || fluid_count == 0) return {};
  const Vec3 down = gravity / g;
  using Range = std::pair<double, double>;
  const Range range = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, fluid_count, 4096),
      Range{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()},
      [&](const tbb::blocked_range<std::size_t>& block, Range found) {
        for (std::size_t i = block.begin(); i < block.end(); ++i) {
          const double along = down.dot(particles.position[i]);
          found = {std::min(found.first, along), std::max(found.second, along)};
        }
        return found;
      },
      [](const Range& a, const Range& b) { return Range{std::min(a.first, b.first), std::max(a.second, b.second)}; });
  return {range.first, range.second};
}

namespace {

/// Takes `candidate` when it is shorter (std::min's rule: ties keep the current step), naming the limit.
void shorten(StepLengths& lengths, double candidate, StepLimit limit) {
  if (candidate < lengths.dt) {
    lengths.dt = candidate;
    lengths.limit = limit;
  }
}

}  // namespace

double water_drag_rate(const Model& model, const GrainState& grains, const GrainProperties& properties,
                       const GrainSampledFluid& sampled, const GrainVoidage& voidages) {
  const CouplingModel& coupling = model.coupling;
  if (!coupling.enabled || !coupling.drag) return 0.0;
  const double density = model.water_density();
  const double viscosity = model.water_kinematic_viscosity() * density;
  // The mean-flow water holds eps rho per volume and moves with its pore velocity: it relaxes at k (1 - eps) /
  // (rho eps). The MPS water fills all space (rho per volume); the mixture reading's shares are the eps.
  const bool mean_flow = model.mean_flow.enabled;
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, grains.size(), 1024), 0.0,
      [&](const tbb::blocked_range<std::size_t>& range, double found) {
        for (std::size_t grain = range.begin(); grain < range.end(); ++grain) {
          if (!(sampled.fluid_weight[grain] > 0.0)) continue;  // dry: no drag
          const double voidage = voidages.voidage[grain];
          const double share = flux_share(coupling.fluid_velocity, voidage);  // s and s_w (both eps in the mixture)
          const double slip = (sampled.fluid_velocity[grain] - grains.velocity[grain]).norm() / share;
          const double k = drag_per_volume(voidage, 2.0 * properties.radius[grain], slip, density, viscosity, coupling);
          found = std::max(found, mean_flow ? k * (1.0 - voidage) / (density * voidage)
                                            : k * (1.0 - voidage) / (density * share * share));
        }
        return found;
      },
      [](double a, double b) { return std::max(a, b); });
}

StepLengths decide_step_lengths(const Model& model, const ParticleState* fluid, double drag_rate) {
  if (!fluid) return decide_step_lengths(model, std::nullopt, drag_rate);
  return decide_step_lengths(model, max_squared_speed(*fluid), drag_rate,
                             water_depth(water_extent(*fluid, model.gravity), model.fluid.spacing));
}

StepLengths decide_step_lengths(const Model& model, std::optional<double> fluid_max_speed_squared, double drag_rate,
                                double water_depth) {
  StepLengths lengths;
  lengths.dt = model.dt;
  lengths.drag_rate = drag_rate;
  if (fluid_max_speed_squared) {
    const FluidModel& water = model.fluid;
    const double max_speed_squared = *fluid_max_speed_squared;
    if (max_speed_squared > 0.0)
      shorten(lengths, water.courant * water.spacing / std::sqrt(max_speed_squared), StepLimit::kCourant);
    if (water.kinematic_viscosity > 0.0)
      shorten(lengths, water.diffusion_number * water.spacing * water.spacing / water.kinematic_viscosity,
              StepLimit::kDiffusion);
    // Deep water: with a longer step still water more than about 4 / (dt sqrt(g / l0)) layers deep grows a motion
    // from its surface down until it blows up (measured: docs/FLUID.md, "Deep water's step limit").
    const double g = model.gravity.norm();
    if (water_depth > 0.0 && g > 0.0)
      shorten(lengths, water.hydrostatic_number * std::sqrt(water.spacing / g) * water.spacing / water_depth,
              StepLimit::kHydrostatic);
    if (drag_rate > 0.0 && model.coupling.drag_number > 0.0)
      shorten(lengths, model.coupling.drag_number / drag_rate, StepLimit::kDrag);
  } else if (model.mean_flow.enabled && drag_rate > 0.0 && model.coupling.drag_number > 0.0) {
    // The mean-flow water takes the grains' drag a step late, as the MPS water does: the same limit. Its stress is
    // implicit (no diffusion limit) and it does not move across the grid (no Courant limit).
    shorten(lengths, model.coupling.drag_number / drag_rate, StepLimit::kDrag);
  }
  // Sub-steps no longer than the scene's solid_dt(); exactly solid_substeps of them at the full step.
  // (dt < run.dt otherwise, so the count stays within [1, solid_substeps]; clamped in floating point before the cast.)
  lengths.substeps =
      lengths.dt == model.dt
          ? model.solid_substeps
          : static_cast<std::int64_t>(std::clamp(std::ceil(lengths.dt / model.solid_dt() - 1e-9), 1.0,
                                                  static_cast<double>(model.solid_substeps)));
  lengths.substep = lengths.dt / static_cast<double>(lengths.substeps);
  return lengths;
}

}  // namespace riffle
