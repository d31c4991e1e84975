#include "systems/mps/fluid_rank_migration.hpp"

#include "systems/mps/fluid_neighbours.hpp"
#include "systems/physics/geometry/tank_kinematics.hpp"
#include "systems/physics/ranks/fluid_ranks.hpp"
#include "systems/physics/ranks/grain_ranks.hpp"

namespace riffle {

void FluidRankMigration::run(SystemContext& context) {
  FluidParticles& particles = whole_group<FluidParticles>(
      context.write<ParticleState>(), context.write<ParticlePrediction>(), context.write<ParticlePressure>(),
      context.write<ParticleDensity>(), context.write<ParticleDragReaction>());
  FluidNeighbours& neighbours = context.write<FluidNeighbours>();
  if (!neighbours.ranks.active) return;
  // The step-start search's own test, decided over all the ranks as it decides it.
  const Vec3 tank_displacement = tank_kinematics(context.model.tank.motion, context.time).displacement;
  const bool keep = FluidNeighbourSearch::lists_still_valid(particles.position, fluid_slot_count(particles), neighbours,
                                                            effective_radius_, tank_displacement) &&
                    !neighbours.reordered;
  if (!ranks::any(!keep)) return;
  // A particle past a periodic face belongs to the box that holds it wrapped (fluid_correct wraps r^k already).
  if (box_.any())
    for (Vec3& position : particles.position) position = box_.wrap(position);
  rebalance_fluid_ranks(particles, neighbours.ranks, reach_, kRebalanceAbove);
  const std::size_t left = migrate_fluid_particles(particles, neighbours.ranks);
  context.count_items(left);
  // The lists and built positions hold the old slots: the search rebuilds them.
  neighbours.reordered = true;
}

}  // namespace riffle
