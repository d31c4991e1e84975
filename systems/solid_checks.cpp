#include "systems/solid_checks.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace riffle {

namespace {
constexpr std::size_t kGrain = 2048;

bool finite(const Vec3& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }
}  // namespace

DomainBox solid_domain(const Model& model) {
  const TankModel& tank = model.tank;
  const Vec3 sweep = tank.motion.kind == TankMotionModel::Kind::kNone
                         ? Vec3::Zero()
                         : Vec3(tank.motion.amplitude * tank.motion.direction.cwiseAbs());
  const Vec3 margin = Vec3::Constant(tank.domain_margin) + sweep;
  return {tank.origin - margin, tank.origin + tank.size + margin};
}

void SolidDomainCheck::run(SystemContext& context) {
  const Solids& solids = context.read<Solids>();
  StepStatus& status = context.write<StepStatus>();
  const DomainBox domain = solid_domain(context.model);
  constexpr std::size_t kNoProblem = std::numeric_limits<std::size_t>::max();
  // The lowest offending slot: min is associative and commutative, so any split gives the same answer.
  const std::size_t first_bad = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, solids.size(), kGrain), kNoProblem,
      [&](const tbb::blocked_range<std::size_t>& range, std::size_t found) {
        for (std::size_t i = range.begin(); i < range.end() && i < found; ++i) {
          const bool ok = finite(solids.position[i]) && finite(solids.velocity[i]) &&
                          finite(solids.angular_velocity[i]) && domain.contains(solids.position[i]);
          if (!ok) return i;
        }
        return found;
      },
      [](std::size_t a, std::size_t b) { return std::min(a, b); });
  context.count_items(solids.size());
  if (first_bad == kNoProblem || !status.ok()) return;
  const bool is_finite = finite(solids.position[first_bad]) && finite(solids.velocity[first_bad]) &&
                         finite(solids.angular_velocity[first_bad]);
  status.problem = is_finite ? StepProblem::kLeftDomain : StepProblem::kNonFinite;
  status.phase = "solids";
  status.entity = solids.id[first_bad];
  status.position = solids.position[first_bad];
  status.velocity = solids.velocity[first_bad];
}

void SolidSummarize::run(SystemContext& context) {
  const Solids& solids = context.read<Solids>();
  const Vec3 gravity = context.model.gravity;
  struct Sums {
    double translational = 0.0, rotational = 0.0, potential = 0.0, max_speed = 0.0;
  };
  // Deterministic reduce: the split tree depends only on the range and grain size, not on the thread count,
  // so the floating-point sums are identical for any --threads.
  const Sums sums = tbb::parallel_deterministic_reduce(
      tbb::blocked_range<std::size_t>(0, solids.size(), kGrain), Sums{},
      [&](const tbb::blocked_range<std::size_t>& range, Sums partial) {
        for (std::size_t i = range.begin(); i < range.end(); ++i) {
          const double speed_squared = solids.velocity[i].squaredNorm();
          partial.translational += 0.5 * solids.mass[i] * speed_squared;
          partial.rotational += 0.5 * solids.moment_of_inertia[i] * solids.angular_velocity[i].squaredNorm();
          partial.potential -= solids.mass[i] * gravity.dot(solids.position[i]);
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
  context.count_items(solids.size());
}

}  // namespace riffle
