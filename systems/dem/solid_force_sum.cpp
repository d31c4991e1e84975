#include "systems/dem/solid_force_sum.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace riffle {

void SolidForceSum::run(SystemContext& context) {
  const GrainContactForce& contact = context.read<GrainContactForce>();
  const GrainDrag& drag = context.read<GrainDrag>();
  const GrainSampledFluid& sampled = context.read<GrainSampledFluid>();
  GrainTotalForce& total = context.write<GrainTotalForce>();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, total.size(), 4096), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      total.force[i] = contact.contact_force[i] + drag.drag_force[i] + sampled.pressure_force[i];
      total.torque[i] = contact.contact_torque[i];
    }
  });
  // [coupling] viscous_stress: added only then, so that a run without it keeps its bits (+0 would turn a -0 force).
  if (context.model.coupling.viscous_stress)
    for (std::size_t i = 0; i < total.size(); ++i) total.force[i] += sampled.viscous_force[i];
  if (lubrication_) {
    const GrainLubrication& lubrication = context.read<GrainLubrication>();
    for (std::size_t i = 0; i < total.size(); ++i) total.force[i] += lubrication.lubrication_force[i];
  }
  context.count_items(total.size());
}

}  // namespace riffle
