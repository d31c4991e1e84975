#include "systems/mps/fluid_shift.hpp"

#include "systems/physics/ranks/fluid_ranks.hpp"

#include <cmath>

#include "systems/physics/mps/mps_operators.hpp"
#include "systems/physics/mps/particle_shifting.hpp"
#include "systems/physics/geometry/periodic_box.hpp"

namespace riffle {

void FluidShift::run(SystemContext& context) {
  ParticleState& particles = context.write<ParticleState>();
  const ParticlePrediction& prediction = context.read<ParticlePrediction>();
  const ParticleDensity& densities = context.read<ParticleDensity>();
  const FluidNeighbours& neighbours = context.read<FluidNeighbours>();
  const std::size_t fluid_count = fluid_slot_count(particles);
  const WendlandKernel kernel = kernel_;
  const double radius_squared = kernel.effective_radius * kernel.effective_radius;
  const double n0 = constants_.reference_density;
  const double dt = context.dt;
  const double smoothing_length = 0.5 * kernel.effective_radius;  // Wendland C2: support 2 h
  const double max_length = fluid_.shifting_max_ratio * fluid_.spacing;
  const double stabilisation_distance = fluid_.stabilisation_distance();
  const ShiftingLaw law = fluid_.shifting_diffusivity == FluidModel::ShiftingDiffusivity::kConstant
                              ? ShiftingLaw::kConstant
                              : ShiftingLaw::kVelocity;
  const bool carry_velocity = fluid_.shifting_velocity_correction;
  const PeriodicBox box = periodic_box(context.model);
  const bool periodic = box.any();
  // Every neighbour slot is read at r^{k+1}: its r* (the ghosts' from the search at r*) plus the correction's small
  // displacement of its owner, taken from the reals (the correction wrapped r^{k+1} into the period, r* may lie
  // outside it). Walls and dummies: r* is r^{k+1} already (fluid_wall_motion).
  const Ghosted<Vec3> predicted_of =
      fluid_ghosted(prediction.predicted_position, neighbours.ghosts.predicted_position, neighbours);
  const auto displacement = [&](std::uint32_t owner) {
    const Vec3 step = particles.position[owner] - prediction.predicted_position[owner];
    return periodic ? nearest_image_difference(box, step) : step;
  };
  shift_.assign(fluid_count, Vec3::Zero());
  velocity_.resize(fluid_count);
  // A neighbour slot's owner's displacement, velocity, kind and free-surface flag: the real's (a periodic ghost's
  // owner's), or over MPI ranks a ghost's as its owner sent them.
  const bool spread = neighbours.ranks.active;
  const std::uint32_t reals = static_cast<std::uint32_t>(particles.id.size());
  if (spread) {
    displacement_.resize(reals);
    for_each_particle(reals, [&](std::size_t i) { displacement_[i] = displacement(static_cast<std::uint32_t>(i)); });
    exchange_fluid_ghost_field(displacement_, neighbours.ranks, ghost_displacement_);
    exchange_fluid_ghost_field(particles.velocity, neighbours.ranks, ghost_velocity_);
    exchange_fluid_ghost_field(densities.free_surface, neighbours.ranks, ghost_free_surface_);
  }
  const auto displacement_of = [&](std::uint32_t j) {
    return spread && j >= reals ? ghost_displacement_[j - reals] : displacement(fluid_owner_of(neighbours, j));
  };
  const auto velocity_of = [&](std::uint32_t j) -> const Vec3& {
    return spread && j >= reals ? ghost_velocity_[j - reals] : particles.velocity[fluid_owner_of(neighbours, j)];
  };
  const auto fluid_at = [&](std::uint32_t j) {
    return (spread && j >= reals ? neighbours.ghosts.kind[j - reals] : particles.kind[fluid_owner_of(neighbours, j)]) ==
           kFluidKind;
  };
  const auto surface_at = [&](std::uint32_t j) {
    return (spread && j >= reals ? ghost_free_surface_[j - reals]
                                 : densities.free_surface[fluid_owner_of(neighbours, j)]) != 0;
  };

  for_each_particle(fluid_count, [&](std::size_t i) {
    const Vec3 position = prediction.predicted_position[i] + displacement(static_cast<std::uint32_t>(i));
    const Vec3 velocity = particles.velocity[i];
    Vec3 concentration_gradient = Vec3::Zero(), outward = Vec3::Zero();
    Eigen::Matrix3d velocity_sum = Eigen::Matrix3d::Zero();
    GradientMoment moment;
    bool near_surface = densities.free_surface[i] != 0;
    for (const std::uint32_t j : neighbours_of(neighbours, i)) {
      const Vec3 offset = predicted_of[j] + displacement_of(j) - position;
      const double distance_squared = offset.squaredNorm();
      if (distance_squared >= radius_squared || distance_squared == 0.0) continue;
      const double distance = std::sqrt(distance_squared);
      const double weight = kernel.weight(distance);
      concentration_gradient += concentration_gradient_term(kernel.derivative_over_distance(distance), offset);
      outward -= weight * offset;
      const bool fluid_partner = fluid_at(j);
      if (fluid_partner && surface_at(j)) near_surface = true;
      if (carry_velocity) {
        const double weight_over_squared = weight / distance_squared;
        velocity_sum += (weight_over_squared * (velocity_of(j) - velocity)) * offset.transpose();
        moment.add(weight, weight_over_squared, offset);
      }
    }
    concentration_gradient /= n0;
    const double diffusivity =
        shifting_diffusivity(law, fluid_.shifting_coefficient, smoothing_length, velocity.norm(), dt);
    Vec3 shift = fickian_shift(diffusivity, concentration_gradient, max_length);
    if (near_surface) {
      const double length = outward.norm();
      shift = length > 0.0 ? tangential_shift(shift, outward / length) : Vec3::Zero();
    }
    // Walls: no shift toward a wall or dummy particle within the DS distance plus the cap (the nearest a particle
    // may come to one), so that a shift never carries water into a wall, whatever grad C says there.
    const double guard_squared = std::pow(stabilisation_distance + max_length, 2);
    for (const std::uint32_t j : neighbours_of(neighbours, i)) {
      if (fluid_at(j)) continue;
      const Vec3 offset = predicted_of[j] - position;  // walls and dummies: r* is r^{k+1}
      if (offset.squaredNorm() >= guard_squared) continue;
      shift = shift_off_wall(shift, offset);
    }
    shift_[i] = shift;
    velocity_[i] = velocity;
    if (carry_velocity) {
      // The GC gradient (seed Eqs. 8-9) of the velocity, d u_a / d x_b: exact for a linear field on any arrangement.
      const Eigen::Matrix3d gradient = (3.0 / n0) * velocity_sum * gradient_correction_matrix(moment, n0);
      velocity_[i] = shifted_velocity(velocity, gradient, shift);
    }
  });
  for_each_particle(fluid_count, [&](std::size_t i) {
    const Vec3 moved = particles.position[i] + shift_[i];
    particles.position[i] = periodic ? box.wrap(moved) : moved;
    particles.velocity[i] = velocity_[i];
  });
  context.count_items(fluid_count);
}

}  // namespace riffle
