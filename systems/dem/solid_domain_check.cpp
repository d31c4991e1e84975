#include "systems/dem/solid_domain_check.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "systems/physics/geometry/domain.hpp"

namespace riffle {

namespace {
constexpr std::size_t kDomainCheckChunk = 2048;  // grains per parallel task

bool finite(const Vec3& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }
}  // namespace

void SolidDomainCheck::run(SystemContext& context) {
  const GrainState& grains = context.read<GrainState>();
  StepStatus& status = context.write<StepStatus>();
  const DomainBox domain = grain_domain_box(context.model);
  constexpr std::size_t kNoProblem = std::numeric_limits<std::size_t>::max();
  // The lowest offending slot: min is associative and commutative, so any split gives the same answer.
  const std::size_t first_bad = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, grains.size(), kDomainCheckChunk), kNoProblem,
      [&](const tbb::blocked_range<std::size_t>& range, std::size_t found) {
        for (std::size_t i = range.begin(); i < range.end() && i < found; ++i) {
          const bool ok = finite(grains.position[i]) && finite(grains.velocity[i]) &&
                          finite(grains.angular_velocity[i]) && domain.contains(grains.position[i]);
          if (!ok) return i;
        }
        return found;
      },
      [](std::size_t a, std::size_t b) { return std::min(a, b); });
  context.count_items(grains.size());
  if (first_bad == kNoProblem || !status.ok()) return;
  const bool is_finite = finite(grains.position[first_bad]) && finite(grains.velocity[first_bad]) &&
                         finite(grains.angular_velocity[first_bad]);
  status.problem = is_finite ? StepProblem::kLeftDomain : StepProblem::kNonFinite;
  status.phase = "solids";
  status.entity = grains.id[first_bad];
  status.position = grains.position[first_bad];
  status.velocity = grains.velocity[first_bad];
}

}  // namespace riffle
