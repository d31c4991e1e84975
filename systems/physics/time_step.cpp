#include "systems/physics/time_step.hpp"

#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>

namespace riffle {

double fluid_time_step(const FluidModel& fluid, const ParticleState& particles, double max_dt) {
  const std::size_t fluid_count = fluid_slot_count(particles);
  const double max_speed = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, fluid_count, 4096), 0.0,
      [&](const tbb::blocked_range<std::size_t>& range, double found) {
        for (std::size_t i = range.begin(); i < range.end(); ++i)
          found = std::max(found, particles.velocity[i].squaredNorm());
        return found;
      },
      [](double a, double b) { return std::max(a, b); });
  double dt = max_dt;
  if (max_speed > 0.0) dt = std::min(dt, fluid.courant * fluid.spacing / std::sqrt(max_speed));
  if (fluid.kinematic_viscosity > 0.0)
    dt = std::min(dt, fluid.diffusion_number * fluid.spacing * fluid.spacing / fluid.kinematic_viscosity);
  return dt;
}

}  // namespace riffle
