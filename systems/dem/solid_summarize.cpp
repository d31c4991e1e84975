#include "systems/dem/solid_summarize.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>

#include "systems/physics/ranks/rank_comm.hpp"

namespace riffle {

namespace {
constexpr std::size_t kSummaryChunk = 2048;  // grains per parallel task
}  // namespace

void SolidSummarize::run(SystemContext& context) {
  const GrainState& grains = context.read<GrainState>();
  const GrainProperties& properties = context.read<GrainProperties>();
  const Vec3 gravity = context.model.gravity;
  struct Sums {
    double translational = 0.0, rotational = 0.0, potential = 0.0, max_speed = 0.0;
  };
  // Deterministic reduce: the split tree depends only on the range and grain size, not on the thread count,
  // so the floating-point sums are identical for any --threads.
  const Sums sums = tbb::parallel_deterministic_reduce(
      tbb::blocked_range<std::size_t>(0, grains.size(), kSummaryChunk), Sums{},
      [&](const tbb::blocked_range<std::size_t>& range, Sums partial) {
        for (std::size_t i = range.begin(); i < range.end(); ++i) {
          const double speed_squared = grains.velocity[i].squaredNorm();
          partial.translational += 0.5 * properties.mass[i] * speed_squared;
          partial.rotational += 0.5 * properties.moment_of_inertia[i] * grains.angular_velocity[i].squaredNorm();
          partial.potential -= properties.mass[i] * gravity.dot(grains.position[i]);
          partial.max_speed = std::max(partial.max_speed, std::sqrt(speed_squared));
        }
        return partial;
      },
      [](Sums a, const Sums& b) {
        a.translational += b.translational;
        a.rotational += b.rotational;
        a.potential += b.potential;
        a.max_speed = std::max(a.max_speed, b.max_speed);
        return a;
      });
  SolidSummary& summary = context.write<SolidSummary>();
  summary.translational_energy = sums.translational;
  summary.rotational_energy = sums.rotational;
  summary.potential_energy = sums.potential;
  summary.max_speed = sums.max_speed;
  if (summary.over_ranks) {  // the whole bed's, the same on every rank (sums in rank order)
    const std::vector<double> total =
        ranks::sum_in_rank_order({sums.translational, sums.rotational, sums.potential});
    summary.translational_energy = total[0];
    summary.rotational_energy = total[1];
    summary.potential_energy = total[2];
    summary.max_speed = ranks::max(sums.max_speed);
  }
  context.count_items(grains.size());
}

}  // namespace riffle
