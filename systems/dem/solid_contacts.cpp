#include "systems/dem/solid_contacts.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <functional>
#include <cmath>
#include <vector>

#include "systems/physics/dem/contact_law.hpp"
#include "systems/physics/dem/contact_slabs.hpp"
#include "systems/physics/ranks/grain_ranks.hpp"

namespace riffle {

namespace {

// Touching grain-grain pairs are evaluated in batches: pass 1 walks the candidates, tests the distance and copies
// the inputs of the touching ones into structure-of-arrays scratch; pass 2 evaluates the batch with the vectorised
// kernel of contact_law.hpp; pass 3 writes each pair's overlap and spring back and adds its force and torques to both
// grains, in pair order. Separated candidates (about half of them in a settled bed) cost only the distance test.

/// The second grain of a pair as the contact code reads it: a real grain (no periodic axis), or in a periodic box a
/// real or a ghost through the halo (components/halo.hpp). One template body serves both, so the walled box keeps
/// its plain array reads.
/// Raw pointers, copied into each task: the compiler cannot tell the pair-array stores from the vectors' own fields,
/// so reading through the vectors would reload their data pointers at every candidate.
struct RealNeighbours {
  const Vec3* position_;
  const Vec3* velocity_;
  const Vec3* angular_velocity_;
  const double* radius_;
  const double* mass_;
  const std::int32_t* material_;
  const std::int32_t* fixed_;
  RealNeighbours(const GrainState& grains, const GrainProperties& properties)
      : position_(grains.position.data()),
        velocity_(grains.velocity.data()),
        angular_velocity_(grains.angular_velocity.data()),
        radius_(properties.radius.data()),
        mass_(properties.mass.data()),
        material_(properties.material.data()),
        fixed_(properties.fixed.data()) {}
  const Vec3& position(std::uint32_t j) const { return position_[j]; }
  const Vec3& velocity(std::uint32_t j) const { return velocity_[j]; }
  const Vec3& angular_velocity(std::uint32_t j) const { return angular_velocity_[j]; }
  double radius(std::uint32_t j) const { return radius_[j]; }
  double mass(std::uint32_t j) const { return mass_[j]; }
  std::int32_t material(std::uint32_t j) const { return material_[j]; }
  bool fixed(std::uint32_t j) const { return fixed_[j] != 0; }
  std::uint32_t owner(std::uint32_t j) const { return j; }
  static constexpr bool kOtherRanks = false;
  bool other_rank(std::uint32_t) const { return false; }
};
/// A run over MPI ranks: slots from N on are other ranks' grains (components/halo.hpp, RankHalo). Their share of a
/// pair's force is kept per pair and sent back to their rank after the pass.
struct RankNeighbours {
  Ghosted<Vec3> position_, velocity_, angular_velocity_;
  Ghosted<double> radius_, mass_;
  Ghosted<std::int32_t> material_, fixed_;
  std::uint32_t real_count_;
  RankNeighbours(const GrainState& grains, const GrainProperties& properties, const Contacts& contacts)
      : position_{grains.position.data(), contacts.ghosts.position.data(), contacts.ranks.real_count},
        velocity_{grains.velocity.data(), contacts.ghosts.velocity.data(), contacts.ranks.real_count},
        angular_velocity_{grains.angular_velocity.data(), contacts.ghosts.angular_velocity.data(),
                          contacts.ranks.real_count},
        radius_{properties.radius.data(), contacts.ghosts.radius.data(), contacts.ranks.real_count},
        mass_{properties.mass.data(), contacts.ghosts.mass.data(), contacts.ranks.real_count},
        material_{properties.material.data(), contacts.ghosts.material.data(), contacts.ranks.real_count},
        fixed_{properties.fixed.data(), contacts.ranks.ghost_fixed.data(), contacts.ranks.real_count},
        real_count_(contacts.ranks.real_count) {}
  const Vec3& position(std::uint32_t j) const { return position_[j]; }
  const Vec3& velocity(std::uint32_t j) const { return velocity_[j]; }
  const Vec3& angular_velocity(std::uint32_t j) const { return angular_velocity_[j]; }
  double radius(std::uint32_t j) const { return radius_[j]; }
  double mass(std::uint32_t j) const { return mass_[j]; }
  std::int32_t material(std::uint32_t j) const { return material_[j]; }
  bool fixed(std::uint32_t j) const { return fixed_[j] != 0; }
  std::uint32_t owner(std::uint32_t j) const { return j; }
  static constexpr bool kOtherRanks = true;
  bool other_rank(std::uint32_t j) const { return j >= real_count_; }
};
struct GhostedNeighbours {
  Ghosted<Vec3> position_, velocity_, angular_velocity_;
  Ghosted<double> radius_, mass_;
  Ghosted<std::int32_t> material_;
  const std::int32_t* fixed_;  // by owner: a ghost is fixed where its owner is (no ghost copy needed)
  const Halo* halo_;
  GhostedNeighbours(const GrainState& grains, const GrainProperties& properties, const Contacts& contacts)
      : position_(ghosted(grains.position, contacts.ghosts.position, contacts.halo)),
        velocity_(ghosted(grains.velocity, contacts.ghosts.velocity, contacts.halo)),
        angular_velocity_(ghosted(grains.angular_velocity, contacts.ghosts.angular_velocity, contacts.halo)),
        radius_(ghosted(properties.radius, contacts.ghosts.radius, contacts.halo)),
        mass_(ghosted(properties.mass, contacts.ghosts.mass, contacts.halo)),
        material_(ghosted(properties.material, contacts.ghosts.material, contacts.halo)),
        fixed_(properties.fixed.data()),
        halo_(&contacts.halo) {}
  const Vec3& position(std::uint32_t j) const { return position_[j]; }
  const Vec3& velocity(std::uint32_t j) const { return velocity_[j]; }
  const Vec3& angular_velocity(std::uint32_t j) const { return angular_velocity_[j]; }
  double radius(std::uint32_t j) const { return radius_[j]; }
  double mass(std::uint32_t j) const { return mass_[j]; }
  std::int32_t material(std::uint32_t j) const { return material_[j]; }
  bool fixed(std::uint32_t j) const { return fixed_[halo_->owner_of(j)] != 0; }
  std::uint32_t owner(std::uint32_t j) const { return halo_->owner_of(j); }
  static constexpr bool kOtherRanks = false;
  bool other_rank(std::uint32_t) const { return false; }
};

/// Where a pass adds the contact forces: the grains' sums (GrainContactForce), as raw pointers (see above).
struct ContactSums {
  Vec3* force;
  Vec3* torque;
};

/// A pair that has just separated carries no overlap or springs (the next touch starts afresh).
void clear_separated(double& overlap, Vec3& spring, Vec3& rolling_spring) {
  overlap = 0.0;
  spring = Vec3::Zero();
  rolling_spring = Vec3::Zero();
}

template <class Neighbours>
void flush_batch(SpherePairBatch& b, const GrainState& grains, const GrainProperties& properties,
                 const Neighbours& neighbours, const ContactModel& model, RollingTerm rolling, double dt,
                 Contacts& contacts, const ContactSums& sums) {
  // Gather the remaining inputs of the touching pairs. The pair coefficients are shared by the whole batch when every
  // pair is of the same two materials (a bed of one material: every batch but those with a wall material's grain),
  // and then copied once; the reduced mass is formed in a loop of its own, which vectorises.
  const std::size_t count = b.count;
  const std::int32_t first_material_i = count > 0 ? properties.material[b.first[0]] : 0;
  const std::int32_t first_material_j = count > 0 ? neighbours.material(b.second[0]) : 0;
  bool one_material_pair = true, any_fixed = false;
  for (std::size_t p = 0; p < count; ++p) {
    const std::uint32_t i = b.first[p], j = b.second[p];
    const Vec3& velocity_i = grains.velocity[i];
    const Vec3& velocity_j = neighbours.velocity(j);
    b.vix[p] = velocity_i.x();
    b.viy[p] = velocity_i.y();
    b.viz[p] = velocity_i.z();
    b.vjx[p] = velocity_j.x();
    b.vjy[p] = velocity_j.y();
    b.vjz[p] = velocity_j.z();
    const Vec3& angular_velocity_i = grains.angular_velocity[i];
    const Vec3& angular_velocity_j = neighbours.angular_velocity(j);
    b.wix[p] = angular_velocity_i.x();
    b.wiy[p] = angular_velocity_i.y();
    b.wiz[p] = angular_velocity_i.z();
    b.wjx[p] = angular_velocity_j.x();
    b.wjy[p] = angular_velocity_j.y();
    b.wjz[p] = angular_velocity_j.z();
    const Vec3& spring = contacts.pair_spring[b.pair[p]];
    b.sx[p] = spring.x();
    b.sy[p] = spring.y();
    b.sz[p] = spring.z();
    b.mass_i[p] = properties.mass[i];
    b.mass_j[p] = neighbours.mass(j);
    any_fixed |= static_cast<int>(properties.fixed[i] != 0) | static_cast<int>(neighbours.fixed(j));
    one_material_pair &= static_cast<int>(properties.material[i] == first_material_i) &
                         static_cast<int>(neighbours.material(j) == first_material_j);
  }
  if (rolling == RollingTerm::kElasticPlastic)
    for (std::size_t p = 0; p < count; ++p) {
      const Vec3& rolling_spring = contacts.pair_rolling_spring[b.pair[p]];
      b.rsx[p] = rolling_spring.x();
      b.rsy[p] = rolling_spring.y();
      b.rsz[p] = rolling_spring.z();
      b.rolling_inertia[p] = pair_rolling_inertia(b.mass_i[p], b.ri[p], b.mass_j[p], b.rj[p],
                                                  properties.fixed[b.first[p]] != 0, neighbours.fixed(b.second[p]));
    }
  if (any_fixed) {
    for (std::size_t p = 0; p < count; ++p)
      b.effective_mass[p] = pair_reduced_mass(b.mass_i[p], b.mass_j[p], properties.fixed[b.first[p]] != 0,
                                              neighbours.fixed(b.second[p]));
  } else {
    for (std::size_t p = 0; p < count; ++p)
      b.effective_mass[p] = pair_reduced_mass(b.mass_i[p], b.mass_j[p], false, false);
  }
  b.shared_coefficients = one_material_pair;
  if (one_material_pair) {
    b.shared = sphere_pair_coefficients(model.law, model.pair(first_material_i, first_material_j));
  } else {
    for (std::size_t p = 0; p < count; ++p) {
      const ContactPairParameters& pair = model.pair(properties.material[b.first[p]], neighbours.material(b.second[p]));
      const SpherePairCoefficients coefficients = sphere_pair_coefficients(model.law, pair);
      b.stiffness_a[p] = coefficients.stiffness_a;
      b.stiffness_b[p] = coefficients.stiffness_b;
      b.damping[p] = coefficients.damping;
      b.damping_ratio[p] = coefficients.damping_ratio;
      b.friction[p] = coefficients.friction;
      b.rolling[p] = coefficients.rolling;
    }
  }
  evaluate_sphere_pair_batch(b, model.law, rolling, dt);
  for (std::size_t p = 0; p < b.count; ++p) {
    const std::uint32_t k = b.pair[p];
    const Vec3 force(b.fx[p], b.fy[p], b.fz[p]);
    contacts.pair_overlap[k] = b.overlap[p];
    contacts.pair_spring[k] = Vec3(b.sx[p], b.sy[p], b.sz[p]);
    if (rolling == RollingTerm::kElasticPlastic) contacts.pair_rolling_spring[k] = Vec3(b.rsx[p], b.rsy[p], b.rsz[p]);
    // Newton's third law: the second grain (its owner, for a ghost) takes the negative force. Only this slab's task
    // writes these grains in this phase (contact_slabs.hpp).
    const std::uint32_t i = b.first[p], j = neighbours.owner(b.second[p]);
    sums.force[i] += force;
    sums.torque[i] += Vec3(b.tix[p], b.tiy[p], b.tiz[p]);
    if constexpr (Neighbours::kOtherRanks) {
      if (neighbours.other_rank(j)) {  // its rank adds it (return_rank_ghost_forces): kept per pair, no race
        contacts.ranks.pair_force_on_ghost[k] = -force;
        contacts.ranks.pair_torque_on_ghost[k] = Vec3(b.tjx[p], b.tjy[p], b.tjz[p]);
        continue;
      }
    }
    sums.force[j] -= force;
    sums.torque[j] += Vec3(b.tjx[p], b.tjy[p], b.tjz[p]);
  }
  b.count = 0;
}

/// The candidates of the grains `slots` (in that order): their pairs' forces added to both grains and their wall
/// forces to the grain, into `sums`.
template <class Neighbours>
void slab_contact_forces(const std::uint32_t* slots, std::size_t slot_count, const GrainState& grains,
                         const GrainProperties& properties, const Neighbours& neighbours, const Walls& walls,
                         Contacts& contacts, const ContactModel& law, RollingTerm rolling, double dt,
                         const ContactSums& sums) {
  SpherePairBatch batch;
  std::size_t count = 0;  // batch.count, in a register while filling
  // Raw pointers held in registers: the compiler cannot tell the batch stores from the vectors' own fields.
  const std::uint32_t* const pair_offsets = contacts.pair_offsets.data();
  const std::uint32_t* const pair_second = contacts.pair_second.data();
  const double* const pair_overlap = contacts.pair_overlap.data();
  const Neighbours view = neighbours;  // a task's own copy, whose pointers stay in registers
  for (std::size_t n = 0; n < slot_count; ++n) {
    const std::uint32_t i = slots[n];
    // Local copies: the pair arrays written below could alias the grain arrays as far as the compiler knows.
    const Vec3 position = grains.position[i];
    const Vec3 velocity = grains.velocity[i];
    const Vec3 angular_velocity = grains.angular_velocity[i];
    const double radius = properties.radius[i];
    const double mass = properties.mass[i];
    const std::int32_t material = properties.material[i];
    const std::uint32_t pair_end = pair_offsets[i + 1];
    for (std::uint32_t k = pair_offsets[i]; k < pair_end; ++k) {
      const std::uint32_t j = pair_second[k];
      const Vec3 centre_line = view.position(j) - position;
      const double radius_j = view.radius(j);
      const double touching_distance = radius + radius_j;
      const double distance_squared = centre_line.squaredNorm();
      // Branch-free compaction: every candidate is written at the batch end, only touching ones advance it (about
      // half the candidates touch, in no predictable pattern, so a branch here would mispredict often).
      const bool touching = (distance_squared < touching_distance * touching_distance) & (distance_squared != 0.0);
      const std::size_t p = count;
      batch.pair[p] = k;
      batch.first[p] = i;
      batch.second[p] = j;
      batch.dx[p] = centre_line.x();
      batch.dy[p] = centre_line.y();
      batch.dz[p] = centre_line.z();
      batch.ri[p] = radius;
      batch.rj[p] = radius_j;
      count += touching;
      // Apart: most candidates stay apart for many sub-steps, so write only when the pair has just separated.
      // One comparison of the two flags: tested one after the other, the first alone would mispredict often.
      const bool was_touching = pair_overlap[k] > 0.0;
      if (__builtin_expect(static_cast<int>(was_touching) > static_cast<int>(touching), 0))
        clear_separated(contacts.pair_overlap[k], contacts.pair_spring[k], contacts.pair_rolling_spring[k]);
      if (count == kContactBatch) {
        batch.count = count;
        flush_batch(batch, grains, properties, view, law, rolling, dt, contacts, sums);
        count = 0;
      }
    }
    for (std::uint32_t k = contacts.wall_pair_offsets[i]; k < contacts.wall_pair_offsets[i + 1]; ++k) {
      const std::uint32_t wall = contacts.wall_pair_wall[k];
      const Vec3& wall_normal = walls.normal[wall];
      const double height = (position - walls.point[wall]).dot(wall_normal);
      const double overlap = radius - height;
      if (overlap <= 0.0) {
        if (contacts.wall_pair_overlap[k] > 0.0) {
          clear_separated(contacts.wall_pair_overlap[k], contacts.wall_pair_spring[k],
                          contacts.wall_pair_rolling_spring[k]);
          contacts.wall_pair_force[k] = Vec3::Zero();
          contacts.wall_pair_torque[k] = Vec3::Zero();
        }
        continue;
      }
      contacts.wall_pair_overlap[k] = overlap;
      ContactGeometry geometry;
      geometry.normal = -wall_normal;  // from the grain towards the wall
      geometry.overlap = overlap;
      const Vec3 arm = radius * geometry.normal;
      geometry.contact_velocity = walls.velocity[wall] - (velocity + angular_velocity.cross(arm));
      geometry.relative_angular_velocity = angular_velocity;
      geometry.effective_radius = radius;  // a plane has zero curvature
      geometry.effective_mass = mass;      // a wall does not move in response
      geometry.rolling_inertia = sphere_rolling_inertia(mass, radius);
      const ContactResponse response =
          evaluate_contact(law.law, law.rolling_law, law.pair(material, walls.material[wall]), geometry,
                           contacts.wall_pair_spring[k], contacts.wall_pair_rolling_spring[k], dt);
      const Vec3 torque = arm.cross(response.force_on_first) + response.rolling_torque_on_first;
      contacts.wall_pair_force[k] = response.force_on_first;  // kept for the walls' reaction (probes)
      contacts.wall_pair_torque[k] = torque;
      sums.force[i] += response.force_on_first;
      sums.torque[i] += torque;
    }
  }
  batch.count = count;
  flush_batch(batch, grains, properties, view, law, rolling, dt, contacts, sums);
}

template <class Neighbours>
void contact_forces(const GrainState& grains, const GrainProperties& properties, const Neighbours& neighbours,
                    const Walls& walls, Contacts& contacts, const ContactModel& law, double dt,
                    GrainContactForce& contact, const ContactSlabSchedule& schedule) {
  bool any_rolling_friction = false;
  for (const ContactPairParameters& pair : law.pairs)
    any_rolling_friction = any_rolling_friction || pair.rolling_friction > 0.0;
  const RollingTerm rolling = rolling_term(law.rolling_law, any_rolling_friction);
  const std::size_t count = grains.size();
  contact.contact_force.resize(count);
  contact.contact_torque.resize(count);
  const ContactSums sums{contact.contact_force.data(), contact.contact_torque.data()};
  // Without slabs (a list not yet sliced), one task in slot order.
  const bool sliced = contacts.slab_offsets.size() >= 2 && contacts.slab_grains.size() == count &&
                      contacts.slab_offsets.back() == count;
  if (!sliced) {
    std::fill(sums.force, sums.force + count, Vec3::Zero());
    std::fill(sums.torque, sums.torque + count, Vec3::Zero());
    std::vector<std::uint32_t> slots(count);
    for (std::size_t i = 0; i < count; ++i) slots[i] = static_cast<std::uint32_t>(i);
    slab_contact_forces(slots.data(), count, grains, properties, neighbours, walls, contacts, law, rolling, dt, sums);
    return;
  }
  const auto slabs = static_cast<std::uint32_t>(contacts.slab_offsets.size() - 1);
  std::vector<std::atomic<std::uint32_t>> waiting(slabs);
  for (std::uint32_t s = 0; s < slabs; ++s) waiting[s].store(schedule.waits_for[s], std::memory_order_relaxed);
  // Declared before the group, so that the group (destroyed first) has waited for every task that calls it, even
  // when a run() throws.
  std::function<void(std::uint32_t)> run_slab;
  tbb::task_group group;
  run_slab = [&](std::uint32_t slab) {
    for (const std::uint32_t zeroed : schedule.zeroes[slab])
      for (std::uint32_t n = contacts.slab_offsets[zeroed]; n < contacts.slab_offsets[zeroed + 1]; ++n) {
        sums.force[contacts.slab_grains[n]] = Vec3::Zero();
        sums.torque[contacts.slab_grains[n]] = Vec3::Zero();
      }
    const std::uint32_t begin = contacts.slab_offsets[slab], end = contacts.slab_offsets[slab + 1];
    slab_contact_forces(contacts.slab_grains.data() + begin, end - begin, grains, properties, neighbours, walls,
                        contacts, law, rolling, dt, sums);
    for (const std::uint32_t next : schedule.after[slab])
      if (waiting[next].fetch_sub(1, std::memory_order_acq_rel) == 1) group.run([&run_slab, next] { run_slab(next); });
  };
  for (std::uint32_t s = 0; s < slabs; ++s)
    if (schedule.waits_for[s] == 0) group.run([&run_slab, s] { run_slab(s); });
  group.wait();
}
}  // namespace

void SolidContactForces::run(SystemContext& context) {
  const GrainState& grains = context.read<GrainState>();
  const GrainProperties& properties = context.read<GrainProperties>();
  const Walls& walls = context.read<Walls>();
  Contacts& contacts = context.write<Contacts>();
  GrainContactForce& contact = context.write<GrainContactForce>();
  const auto slabs = static_cast<std::uint32_t>(contacts.slab_offsets.empty() ? 0 : contacts.slab_offsets.size() - 1);
  if (slabs != schedule_slabs_ || contacts.slab_periodic != schedule_periodic_) {
    schedule_ = contact_slab_schedule(slabs, contacts.slab_periodic);
    schedule_slabs_ = slabs;
    schedule_periodic_ = contacts.slab_periodic;
  }
  // A periodic box: the second grain of a pair may be a ghost (solid_neighbours built and exchanged the halo).
  if (contacts.ranks.active) {
    // Over MPI ranks: the other ranks' grains as seconds, and their share of the forces sent back to them (a pair
    // apart this sub-step is not evaluated, so every share starts at zero).
    for (const std::uint32_t k : contacts.ranks.ghost_pairs) {
      contacts.ranks.pair_force_on_ghost[k] = Vec3::Zero();
      contacts.ranks.pair_torque_on_ghost[k] = Vec3::Zero();
    }
    contact_forces(grains, properties, RankNeighbours(grains, properties, contacts), walls, contacts,
                   context.model.contact, context.dt, contact, schedule_);
    return_rank_ghost_forces(contacts, contact.contact_force, contact.contact_torque);
  } else if (contacts.halo.valid)
    contact_forces(grains, properties, GhostedNeighbours(grains, properties, contacts), walls, contacts,
                   context.model.contact, context.dt, contact, schedule_);
  else
    contact_forces(grains, properties, RealNeighbours(grains, properties), walls, contacts, context.model.contact,
                   context.dt, contact, schedule_);
  context.count_items(grains.size());
}

}  // namespace riffle
