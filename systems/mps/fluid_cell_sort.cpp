#include "systems/mps/fluid_cell_sort.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>

#include "components/soa.hpp"
#include "systems/physics/geometry/cell_order.hpp"
#include "systems/mps/fluid_neighbours.hpp"
#include "systems/physics/geometry/tank_kinematics.hpp"

namespace riffle {

bool FluidCellSort::due(const SystemContext& context, const FluidParticles& particles, std::size_t fluid_count) const {
  const auto every = [&](std::int64_t period) {
    return period > 0 && context.step() % static_cast<std::uint64_t>(period) == 0;
  };
  if (every(every_)) return true;
  if (!every(every_fast_)) return false;
  const double limit = fast_displacement_ * fast_displacement_;
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, fluid_count, 4096), false,
      [&](const tbb::blocked_range<std::size_t>& range, bool fast) {
        for (std::size_t i = range.begin(); !fast && i < range.end(); ++i)
          fast = (particles.predicted_position[i] - particles.position[i]).squaredNorm() > limit;
        return fast;
      },
      [](bool a, bool b) { return a || b; });
}

void FluidCellSort::run(SystemContext& context) {
  FluidParticles& particles = whole_group<FluidParticles>(
      context.write<ParticleState>(), context.write<ParticlePrediction>(), context.write<ParticlePressure>(),
      context.write<ParticleDensity>(), context.write<ParticleDragReaction>());
  const std::size_t fluid_count = fluid_slot_count(particles);
  if (!due(context, particles, fluid_count)) return;
  const double cell_size = fluid_search_cell_size(search_radius_);
  // The search grid's lattice at the predicted positions (anchored at the tank's moving origin at t + dt), shifted by
  // whole cells so that the dummy layers below and beside the tank get non-negative cell indices.
  const Vec3 anchor = context.model.tank.origin +
                      tank_kinematics(context.model.tank.motion, context.time + context.dt).displacement -
                      Vec3::Constant(64.0 * cell_size);
  std::vector<std::size_t> order = cell_order(particles.predicted_position, fluid_count, anchor, cell_size);
  // Walls and dummies: the same key over slots [F, N). They ride with the tank, and so does the lattice, so after the
  // first sort they stay in order and only the fluid slots move.
  std::vector<Vec3> boundary(particles.predicted_position.begin() + static_cast<std::ptrdiff_t>(fluid_count),
                             particles.predicted_position.end());
  const std::vector<std::size_t> boundary_order = cell_order(boundary, boundary.size(), anchor, cell_size);
  const bool boundary_sorted = std::is_sorted(boundary_order.begin(), boundary_order.end());
  if (boundary_sorted && std::is_sorted(order.begin(), order.end())) return;
  FluidNeighbours& neighbours = context.write<FluidNeighbours>();
  const bool keep_built = neighbours.built_positions.size() == particles.size();
  if (!boundary_sorted) {
    order.reserve(particles.size());
    for (const std::size_t k : boundary_order) order.push_back(fluid_count + k);
  }
  permute_fields(particles, order);
  // The lists hold slots of the old order. The built positions travel with the particles, so that the search still
  // knows whether the skin was used up and picks the next skin as if no sort had happened.
  if (keep_built) permute_prefix(neighbours.built_positions, order);
  neighbours.reordered = true;
  context.count_items(order.size());
}

}  // namespace riffle
