#include "systems/dem/solid_cell_sort.hpp"

#include <algorithm>

#include "systems/physics/geometry/domain.hpp"

namespace riffle {

void SolidCellSort::run(SystemContext& context) {
  const std::int64_t every = context.model.solids.sort_every;
  if (every <= 0 || (context.step() + 1) % static_cast<std::uint64_t>(every) != 0) return;
  Solids& solids = whole_group<Solids>(
      context.write<GrainState>(), context.write<GrainProperties>(), context.write<GrainTotalForce>(),
      context.write<GrainContactForce>(), context.write<GrainDrag>(), context.write<GrainSampledFluid>(),
      context.write<GrainVoidage>(), context.write<GrainAddedMass>(), context.write<GrainLubrication>());
  if (solids.size() < 2) return;
  const double largest_radius = *std::max_element(solids.radius.begin(), solids.radius.end());
  const DomainBox domain = domain_box(context.model);
  permute_fields(solids, cell_order(solids, domain.low, 2.0 * largest_radius));
  context.count_items(solids.size());
}

}  // namespace riffle
