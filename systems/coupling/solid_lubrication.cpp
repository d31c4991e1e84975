#include "systems/coupling/solid_lubrication.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <numbers>

#include "systems/physics/dem/contact_law.hpp"
#include "systems/physics/coupling/lubrication.hpp"
#include "systems/physics/ranks/grain_ranks.hpp"

namespace riffle {

namespace {
constexpr std::size_t kLubricationChunk = 256;  // grains per parallel task

/// The second grain of a candidate pair as the lubrication reads it, as solid_contacts does
/// (systems/dem/solid_contacts.cpp): a real grain (no periodic axis: plain array reads, the walled box unchanged),
/// or in a periodic box a real or a ghost through the halo (components/halo.hpp), exchanged by solid_neighbours
/// every sub-step. A ghost's wetness is its owner's (the ghosts carry no sampled fluid).
struct RealGrains {
  const Vec3* position_;
  const Vec3* velocity_;
  const double* radius_;
  const double* mass_;
  const double* weight_;
  const std::int32_t* fixed_;
  const Vec3& position(std::uint32_t j) const { return position_[j]; }
  const Vec3& velocity(std::uint32_t j) const { return velocity_[j]; }
  double radius(std::uint32_t j) const { return radius_[j]; }
  double mass(std::uint32_t j) const { return mass_[j]; }
  double weight(std::uint32_t j) const { return weight_[j]; }
  bool fixed(std::uint32_t j) const { return fixed_[j] != 0; }
};
struct GhostedGrains {
  Ghosted<Vec3> position_, velocity_;
  Ghosted<double> radius_, mass_;
  const double* weight_;
  const std::int32_t* fixed_;
  const Halo* halo_;
  const Vec3& position(std::uint32_t j) const { return position_[j]; }
  const Vec3& velocity(std::uint32_t j) const { return velocity_[j]; }
  double radius(std::uint32_t j) const { return radius_[j]; }
  double mass(std::uint32_t j) const { return mass_[j]; }
  double weight(std::uint32_t j) const { return weight_[halo_->owner_of(j)]; }
  bool fixed(std::uint32_t j) const { return fixed_[halo_->owner_of(j)] != 0; }
};

/// Over MPI ranks: slots past this rank's grains are the other ranks' grains (Contacts::ghosts, RankHalo), with
/// their water's sampling weights as their owners send them.
struct RankGrains {
  const GrainState* grains_;
  const GrainProperties* properties_;
  const GrainGhosts* ghosts_;
  const double* weight_;
  const double* ghost_weight_;
  const std::int32_t* ghost_fixed_;
  std::uint32_t real_count_;
  const Vec3& position(std::uint32_t j) const {
    return j < real_count_ ? grains_->position[j] : ghosts_->position[j - real_count_];
  }
  const Vec3& velocity(std::uint32_t j) const {
    return j < real_count_ ? grains_->velocity[j] : ghosts_->velocity[j - real_count_];
  }
  double radius(std::uint32_t j) const {
    return j < real_count_ ? properties_->radius[j] : ghosts_->radius[j - real_count_];
  }
  double mass(std::uint32_t j) const { return j < real_count_ ? properties_->mass[j] : ghosts_->mass[j - real_count_]; }
  double weight(std::uint32_t j) const { return j < real_count_ ? weight_[j] : ghost_weight_[j - real_count_]; }
  bool fixed(std::uint32_t j) const {
    return (j < real_count_ ? properties_->fixed[j] : ghost_fixed_[j - real_count_]) != 0;
  }
};

/// Pass 1 (below): each grain-grain candidate once, from its first grain (always real), the second read through
/// `neighbours`.
template <class Neighbours>
void lubrication_first(const GrainState& grains, const GrainProperties& properties, const double* weights,
                       const Neighbours& neighbours, const Contacts& contacts, const Walls& walls,
                       const CouplingModel& settings, double mu, double dt, Vec3* pair_force,
                       GrainLubrication& lubrication) {
  const std::size_t count = grains.size();
  const Vec3* const positions = grains.position.data();
  const double* const radii = properties.radius.data();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, kLubricationChunk), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      Vec3 force = Vec3::Zero();
      const std::uint32_t pair_begin = contacts.pair_offsets[i], pair_end = contacts.pair_offsets[i + 1];
      const bool wet = weights[i] > 0.0;
      if (!wet)
        for (std::uint32_t k = pair_begin; k < pair_end; ++k) pair_force[k] = Vec3::Zero();
      if (wet) {
        const double radius = radii[i];
        const Vec3 position = positions[i];
        for (std::uint32_t k = pair_begin; k < pair_end; ++k) {
          pair_force[k] = Vec3::Zero();
          const std::uint32_t j = contacts.pair_second[k];
          const Vec3 centre_line = neighbours.position(j) - position;
          const double radius_j = neighbours.radius(j);
          const double a = reduced_radius(radius, radius_j);
          const double cutoff = settings.lubrication_cutoff_gap(a);
          // Many candidates of a bed are beyond the cut-off: settled without a root.
          const double reach = radius + radius_j + cutoff;
          const double distance_squared = centre_line.squaredNorm();
          if (!(distance_squared < reach * reach) || !(distance_squared > 0.0)) continue;
          if (!(neighbours.weight(j) > 0.0)) continue;
          const double distance = std::sqrt(distance_squared);
          const double gap = distance - radius - radius_j;
          const Vec3 normal = centre_line / distance;  // from i to j
          const double approach = (grains.velocity[i] - neighbours.velocity(j)).dot(normal);
          // Touching over the whole sub-step: the contact law's (swept_coefficient counts only the film).
          if (gap + 0.5 * std::abs(approach) * dt <= 0.0) continue;
          const double roughness = settings.roughness_gap(a);
          const double at_gap = pair_lubrication_coefficient(radius, radius_j, gap, mu, roughness, cutoff);
          const double swept = swept_coefficient(at_gap, 6.0 * std::numbers::pi * mu * a * a, gap, approach, dt, roughness, cutoff);
          const double reduced_mass =
              pair_reduced_mass(properties.mass[i], neighbours.mass(j), properties.fixed[i] != 0, neighbours.fixed(j));
          const Vec3 on_first = -implicit_coefficient(swept, dt, reduced_mass) * approach * normal;
          pair_force[k] = on_first;
          force += on_first;
        }
        for (std::uint32_t k = contacts.wall_pair_offsets[i]; k < contacts.wall_pair_offsets[i + 1]; ++k) {
          const std::uint32_t wall = contacts.wall_pair_wall[k];
          const Vec3& normal = walls.normal[wall];  // into the domain, away from the wall
          const double gap = (position - walls.point[wall]).dot(normal) - radius;
          const double cutoff = settings.lubrication_cutoff_gap(radius);
          // Moving tank walls: the approach speed relative to the wall.
          const double approach = -(grains.velocity[i] - walls.velocity[wall]).dot(normal);
          // Beyond the cut-off, or touching over the whole sub-step (the contact law's).
          if (!(gap < cutoff) || gap + 0.5 * std::abs(approach) * dt <= 0.0) continue;
          const double roughness = settings.roughness_gap(radius);
          const double at_gap = wall_lubrication_coefficient(radius, gap, mu, roughness, cutoff);
          const double swept =
              swept_coefficient(at_gap, 6.0 * std::numbers::pi * mu * radius * radius, gap, approach, dt, roughness, cutoff);
          force += implicit_coefficient(swept, dt, properties.mass[i]) * approach * normal;
        }
      }
      lubrication.lubrication_force[i] = force;
    }
  });
}
}  // namespace

SolidLubrication::SolidLubrication(const Model& model)
    : model_(model.coupling), viscosity_(model.water_kinematic_viscosity() * model.water_density()) {}

void SolidLubrication::run(SystemContext& context) {
  const GrainState& grains = context.read<GrainState>();
  const GrainProperties& properties = context.read<GrainProperties>();
  const GrainSampledFluid& sampled = context.read<GrainSampledFluid>();
  const Contacts& contacts = context.read<Contacts>();
  const Walls& walls = context.read<Walls>();
  GrainLubrication& lubrication = context.write<GrainLubrication>();
  const double dt = context.dt;
  const double mu = viscosity_;
  const std::size_t count = grains.size();
  pair_force_.resize(contacts.pair_count());  // every entry is written below
  if (contacts.pair_offsets.size() != count + 1) {  // no list yet (the contacts build it first)
    for (Vec3& force : lubrication.lubrication_force) force = Vec3::Zero();
    return;
  }

  // 1. Each grain-grain candidate once, from its first grain: the force on the first grain into the pair scratch,
  //    and each grain's sum over its wall candidates and the pairs where it is first, in pair order. A periodic
  //    box: the second grain may be a ghost (solid_neighbours built and exchanged the halo, whose width includes the
  //    lubrication cut-off); its reaction goes to its owner in pass 2 (the reverse index is by owner slot).
  // Locals: the pair scratch written below could alias the model and the grain arrays as far as the compiler knows.
  const CouplingModel settings = model_;
  Vec3* const pair_force = pair_force_.data();
  const double* const weights = sampled.fluid_weight.data();
  if (contacts.ranks.active) {
    exchange_rank_ghost_values(sampled.fluid_weight, contacts, ghost_weight_);
    const RankGrains neighbours{&grains, &properties, &contacts.ghosts, weights, ghost_weight_.data(),
                                contacts.ranks.ghost_fixed.data(), static_cast<std::uint32_t>(count)};
    lubrication_first(grains, properties, weights, neighbours, contacts, walls, settings, mu, dt, pair_force,
                      lubrication);
  } else if (contacts.halo.valid) {
    const GhostedGrains neighbours{ghosted(grains.position, contacts.ghosts.position, contacts.halo),
                                   ghosted(grains.velocity, contacts.ghosts.velocity, contacts.halo),
                                   ghosted(properties.radius, contacts.ghosts.radius, contacts.halo),
                                   ghosted(properties.mass, contacts.ghosts.mass, contacts.halo), weights,
                                   properties.fixed.data(), &contacts.halo};
    lubrication_first(grains, properties, weights, neighbours, contacts, walls, settings, mu, dt, pair_force,
                      lubrication);
  } else {
    const RealGrains neighbours{grains.position.data(), grains.velocity.data(), properties.radius.data(),
                                properties.mass.data(), weights, properties.fixed.data()};
    lubrication_first(grains, properties, weights, neighbours, contacts, walls, settings, mu, dt, pair_force,
                      lubrication);
  }
  // 2. Each grain takes minus the pairs where it is second, ascending: equal and opposite to the bit, thread-count
  //    independent.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, kLubricationChunk), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i)
      for (std::uint32_t s = contacts.second_offsets[i]; s < contacts.second_offsets[i + 1]; ++s)
        lubrication.lubrication_force[i] -= pair_force_[contacts.second_pairs[s]];
  });
  // Over ranks the other ranks' grains take their reaction at home, added in rank order.
  if (contacts.ranks.active) return_rank_ghost_sums(contacts, pair_force_, -1.0, lubrication.lubrication_force);
  context.count_items(count);
}

}  // namespace riffle
