#include "systems/mps/fluid_checks.hpp"

#include "systems/physics/ranks/rank_comm.hpp"

#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "systems/physics/geometry/domain.hpp"

namespace riffle {

namespace {
bool finite(const Vec3& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }
}  // namespace

void FluidChecks::run(SystemContext& context) {
  const ParticleState& particles = context.read<ParticleState>();
  const ParticleDensity& densities = context.read<ParticleDensity>();
  FluidSummary& summary = context.write<FluidSummary>();
  StepStatus& status = context.write<StepStatus>();
  const std::size_t fluid_count = fluid_slot_count(particles);
  const DomainBox domain = domain_box(context.model);
  constexpr std::size_t kNoProblem = std::numeric_limits<std::size_t>::max();
  const std::size_t first_bad = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, fluid_count, 4096), kNoProblem,
      [&](const tbb::blocked_range<std::size_t>& range, std::size_t found) {
        for (std::size_t i = range.begin(); i < range.end() && i < found; ++i)
          if (!finite(particles.position[i]) || !finite(particles.velocity[i]) || !domain.contains(particles.position[i]))
            return i;
        return found;
      },
      [](std::size_t a, std::size_t b) { return std::min(a, b); });

  const double n0 = constants_.reference_density;
  const double volume = constants_.particle_volume;
  const double half_mass = 0.5 * volume * context.model.fluid.density;
  summary.fluid_count = fluid_count;
  summary.kinetic_energy =
      deterministic_sum(fluid_count, [&](std::size_t i) { return half_mass * particles.velocity[i].squaredNorm(); });
  summary.volume = deterministic_sum(fluid_count, [&](std::size_t i) {
    return densities.free_surface[i] || !(densities.number_density[i] > 0.0) ? volume
                                                                             : volume * n0 / densities.number_density[i];
  });
  double density_ratio_sum = deterministic_sum(fluid_count, [&](std::size_t i) {
    return densities.free_surface[i] ? 0.0 : densities.number_density[i] / n0;
  });
  double max_speed_squared = 0.0;
  for (std::size_t i = 0; i < fluid_count; ++i) max_speed_squared = std::max(max_speed_squared, particles.velocity[i].squaredNorm());
  // Over MPI ranks the water's totals: each rank's sums added in rank order (the same for a given rank count).
  // fluid_pressure has summed the surface count already.
  if (over_ranks_) {
    const std::vector<double> totals = ranks::sum_in_rank_order(
        {static_cast<double>(fluid_count), summary.kinetic_energy, summary.volume, density_ratio_sum});
    summary.fluid_count = static_cast<std::size_t>(totals[0]);
    summary.kinetic_energy = totals[1];
    summary.volume = totals[2];
    density_ratio_sum = totals[3];
    max_speed_squared = ranks::max(max_speed_squared);
  }
  const std::size_t interior = summary.fluid_count - std::min(summary.fluid_count, summary.surface_count);
  summary.mean_density_ratio = interior == 0 ? 1.0 : density_ratio_sum / static_cast<double>(interior);
  summary.max_speed = std::sqrt(max_speed_squared);
  summary.courant = summary.max_speed * context.dt / constants_.spacing;
  context.count_items(fluid_count);

  if (!status.ok()) return;
  if (first_bad != kNoProblem) {
    const bool is_finite = finite(particles.position[first_bad]) && finite(particles.velocity[first_bad]);
    status.problem = is_finite ? StepProblem::kLeftDomain : StepProblem::kNonFinite;
    status.phase = "fluid";
    status.entity = particles.id[first_bad];
    status.position = particles.position[first_bad];
    status.velocity = particles.velocity[first_bad];
  } else if (!std::isfinite(summary.solver_residual)) {
    status.problem = StepProblem::kSolverFailed;
    status.phase = "fluid";
  } else if (static_cast<double>(summary.removed_count()) >
             context.model.fluid.escape_fraction_limit * static_cast<double>(summary.initial_fluid_count)) {
    // fluid_escape removed more of the water than the scene accepts: the run no longer models its experiment.
    status.problem = StepProblem::kTooManyEscaped;
    status.phase = "fluid";
  } else if (context.model.fluid.schemes.conservative_gradient) {
    // The conservative gradient's sum form lifts a surface particle (p = 0 while p - G . r grows with its height)
    // harder the higher it rises: unstable at a free surface (docs/FLUID.md, "A momentum-conserving gradient").
    // Stop at once, naming the first flagged particle still here (fluid_escape may have removed others), rather
    // than let the surface blow up.
    std::size_t flagged = 0;
    while (flagged < fluid_count && !densities.free_surface[flagged]) ++flagged;
    if (flagged < fluid_count) {
      status.problem = StepProblem::kSurfaceWithConservativeGradient;
      status.phase = "fluid";
      status.entity = particles.id[flagged];
      status.position = particles.position[flagged];
      status.velocity = particles.velocity[flagged];
    }
  }
}

}  // namespace riffle
