#include "systems/mps/fluid_escape.hpp"

#include "systems/physics/ranks/rank_comm.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <vector>

#include "components/soa.hpp"
#include "systems/physics/geometry/domain.hpp"
#include "systems/physics/geometry/tank_kinematics.hpp"

namespace riffle {

void FluidEscape::run(SystemContext& context) {
  FluidParticles& particles = whole_group<FluidParticles>(
      context.write<ParticleState>(), context.write<ParticlePrediction>(), context.write<ParticlePressure>(),
      context.write<ParticleDensity>(), context.write<ParticleDragReaction>());
  FluidSummary& summary = context.write<FluidSummary>();
  summary.escaped.clear();
  const Model& model = context.model;
  const std::size_t fluid_count = fluid_slot_count(particles);
  const DomainBox domain = domain_box(model);
  // The tank's inner box where it is at the end of the step (the positions are r^{k+1}).
  const Vec3 tank_low =
      model.tank.origin + tank_kinematics(model.tank.motion, context.time + context.dt).displacement;
  const Vec3 tank_high = tank_low + model.tank.size;
  const double distance = model.fluid.escape_distance;
  const auto kind = [&](std::size_t i) {
    return fluid_escape_kind(particles.position[i], particles.velocity[i], particles.number_density[i], domain,
                             tank_low, tank_high, distance);
  };
  // Nearly always none: one parallel pass to find out, the list only when there is something to remove.
  const bool any = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, fluid_count, 4096), false,
      [&](const tbb::blocked_range<std::size_t>& range, bool found) {
        for (std::size_t i = range.begin(); !found && i < range.end(); ++i) found = kind(i) != FluidEscapeKind::kNone;
        return found;
      },
      [](bool a, bool b) { return a || b; });
  context.count_items(fluid_count);
  // Over MPI ranks every rank adds the removals of all (the counts stay the water's); the list is this rank's.
  FluidNeighbours& neighbours = context.write<FluidNeighbours>();
  const bool spread = neighbours.ranks.active;
  if (!(spread ? ranks::any(any) : any)) return;

  std::vector<std::size_t> kept;
  kept.reserve(particles.size());
  for (std::size_t i = 0; i < fluid_count; ++i) {
    const FluidEscapeKind why = kind(i);
    if (why == FluidEscapeKind::kNone)
      kept.push_back(i);
    else
      summary.escaped.push_back(EscapedParticle{particles.id[i], particles.position[i], particles.velocity[i],
                                                why == FluidEscapeKind::kLeftDomain});
  }
  std::size_t left_domain = 0, lone_droplet = 0;
  for (const EscapedParticle& particle : summary.escaped) ++(particle.left_domain ? left_domain : lone_droplet);
  if (spread) {
    const std::vector<double> removed =
        ranks::sum_in_rank_order({static_cast<double>(left_domain), static_cast<double>(lone_droplet)});
    left_domain = static_cast<std::size_t>(removed[0]);
    lone_droplet = static_cast<std::size_t>(removed[1]);
  }
  summary.removed_left_domain += left_domain;
  summary.removed_lone_droplet += lone_droplet;
  for (std::size_t i = fluid_count; i < particles.size(); ++i) kept.push_back(i);
  const std::size_t before = particles.size();
  keep_fields(particles, kept);
  // The lists hold slots of the old table: the next search rebuilds them (its sizes no longer match). The built
  // positions follow the particles, so that it still measures how far each one moved since the build.
  if (neighbours.built_positions.size() == before) keep_slots(neighbours.built_positions, kept);
  neighbours.reordered = true;
}

}  // namespace riffle
