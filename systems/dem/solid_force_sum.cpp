#include "systems/dem/solid_force_sum.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace riffle {

void SolidForceSum::run(SystemContext& context) {
  Solids& solids = context.write<Solids>();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, solids.size(), 4096), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      solids.force[i] = solids.contact_force[i] + solids.drag_force[i] + solids.pressure_force[i];
      solids.torque[i] = solids.contact_torque[i];
    }
  });
  context.count_items(solids.size());
}

}  // namespace riffle
