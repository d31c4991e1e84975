#include "systems/fluid_cell_sort.hpp"

#include <algorithm>

#include "systems/cell_order.hpp"
#include "systems/fluid_neighbours.hpp"
#include "systems/wall_motion.hpp"

namespace riffle {

void FluidCellSort::run(SystemContext& context) {
  if (every_ <= 0 || context.step() % static_cast<std::uint64_t>(every_) != 0) return;
  FluidParticles& particles = context.write<FluidParticles>();
  const std::size_t fluid_count = fluid_slot_count(particles);
  const double cell_size = fluid_search_cell_size(search_radius_);
  // The search grid's lattice (anchored at the tank's moving origin), shifted by whole cells so that the dummy
  // layers below and beside the tank get non-negative cell indices.
  const Vec3 anchor = context.model.tank.origin +
                      tank_kinematics(context.model.tank.motion, context.time).displacement -
                      Vec3::Constant(64.0 * cell_size);
  std::vector<std::size_t> order = cell_order(particles.position, fluid_count, anchor, cell_size);
  // Walls and dummies: the same key over slots [F, N).
  std::vector<Vec3> boundary(particles.position.begin() + static_cast<std::ptrdiff_t>(fluid_count), particles.position.end());
  const std::vector<std::size_t> boundary_order = cell_order(boundary, boundary.size(), anchor, cell_size);
  order.reserve(particles.size());
  for (const std::size_t k : boundary_order) order.push_back(fluid_count + k);
  if (std::is_sorted(order.begin(), order.end())) return;
  permute_fields(particles, order);
  // The lists hold slots of the old order: an empty record of built positions fails the next skin check.
  context.write<FluidNeighbours>().built_positions.clear();
  context.count_items(particles.size());
}

}  // namespace riffle
