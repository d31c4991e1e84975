#include "systems/mps/fluid_predict.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "systems/physics/math/deterministic_sum.hpp"
#include "systems/physics/mps/driven_flow.hpp"
#include "systems/physics/mps/fluid_pair_batch.hpp"
#include "systems/physics/mps/mps_operators.hpp"
#include "systems/physics/geometry/tank_kinematics.hpp"
#include "systems/physics/ranks/fluid_ranks.hpp"

namespace riffle {

void FluidPredict::run(SystemContext& context) {
  ParticleState& particles = context.write<ParticleState>();
  ParticlePrediction& prediction = context.write<ParticlePrediction>();
  ParticleDragReaction& reaction = context.write<ParticleDragReaction>();
  const FluidNeighbours& neighbours = context.read<FluidNeighbours>();
  const std::size_t fluid_count = fluid_slot_count(particles);
  const WendlandKernel kernel = kernel_;
  const double radius_squared = kernel.effective_radius * kernel.effective_radius;
  const double n0 = constants_.reference_density;
  // nu <lap u>_i = nu 2D / (lambda0 n0) sum_j (u_j - u_i) w_ij  (numerics 1.4, D = 3)
  const double viscous_factor =
      fluid_.kinematic_viscosity * 6.0 / (constants_.laplacian_lambda * constants_.reference_density);
  const bool error_compensation = fluid_.schemes.error_compensating_source;
  Vec3 gravity = context.model.gravity;
  if (fluid_.body_force.kind != BodyForceModel::Kind::kNone) gravity.x() += body_force(context, particles, fluid_count);
  acceleration_.resize(fluid_count);
  // Neighbour slots beyond the reals are a periodic tank's ghosts (fluid_neighbours exchanged r^k, u^k, kinds).
  const Ghosted<Vec3> position_of = fluid_ghosted(particles.position, neighbours.ghosts.position, neighbours);
  const Ghosted<Vec3> velocity_of = fluid_ghosted(particles.velocity, neighbours.ghosts.velocity, neighbours);
  const Ghosted<std::int32_t> kind_of = fluid_ghosted(particles.kind, neighbours.ghosts.kind, neighbours);
  // The body force joins gravity; eddy viscosity and lids take their own loop, so this one keeps main's bits.
  if (fluid_.turbulence == FluidModel::Turbulence::kSps || fluid_.scatter_viscosity > 0.0 || fluid_.has_lids())
    driven_viscous_loop(context, gravity);
  else
  for_each_particle(fluid_count, [&](std::size_t i) {
    Vec3 viscous = Vec3::Zero();
    double density = 0.0, rate = 0.0;
    if (viscous_factor > 0.0 || error_compensation) {
      const Vec3 position = particles.position[i];
      const Vec3 velocity = particles.velocity[i];
      FluidPairBatch batch;
      for_each_pair_within(
          neighbours_of(neighbours, i), radius_squared, kernel, batch,
          [&](std::uint32_t j) -> Vec3 { return position_of[j] - position; },
          [&](const FluidPairBatch& pair, std::size_t k) {
            const std::uint32_t j = pair.slot[k];
            const double weight = pair.weight[k];
            const Vec3 relative_velocity = velocity_of[j] - velocity;
            viscous += weight * relative_velocity;
            if (error_compensation) {
              density += weight;
              const double derivative_over_distance = kernel.derivative_over_distance(pair.distance[k]);
              rate += density_rate_term(kind_of[j] == kFluidKind, derivative_over_distance, pair.offset(k),
                                        relative_velocity);
            }
          });
    }
    acceleration_[i] = viscous_factor * viscous + gravity;
    if (error_compensation) {
      const double error = (density - n0) / n0;
      prediction.density_rate[i] = std::abs(error) * rate + std::abs(rate) * error;
    }
  });
  const double dt = context.dt;
  const double inverse_density = 1.0 / fluid_.density;
  // The stress divergence over rho, for the grains' viscous stress force ([coupling] viscous_stress), sampled the
  // next step: the acceleration less the body acceleration (gravity and the body force), before the drag reaction.
  if (context.model.coupling.viscous_stress)
    for_each_particle(fluid_count, [&](std::size_t i) { prediction.viscous_acceleration[i] = acceleration_[i] - gravity; });
  for_each_particle(fluid_count, [&](std::size_t i) {
    // The grains' drag from the last step comes back as an impulse per volume (fluid_drag_reaction).
    particles.velocity[i] += dt * acceleration_[i] + inverse_density * reaction.drag_reaction[i];
    reaction.drag_reaction[i] = Vec3::Zero();
    prediction.predicted_position[i] = particles.position[i] + dt * particles.velocity[i];
  });
  context.count_items(fluid_count);
}

double FluidPredict::body_force(SystemContext& context, const ParticleState& particles, std::size_t fluid_count) {
  const BodyForceModel& model = fluid_.body_force;
  FluidSummary& summary = context.write<FluidSummary>();
  if (model.kind != BodyForceModel::Kind::kBulkVelocity) {
    summary.body_force = prescribed_body_force(model, context.time);
    return summary.body_force;
  }
  // The bulk velocity: the mean of the fluid particles' u_x at the step start (each stands for the volume l0^3).
  double sum = deterministic_sum(fluid_count, [&](std::size_t i) { return particles.velocity[i].x(); });
  double count = static_cast<double>(fluid_count);
  if (context.read<FluidNeighbours>().ranks.active) {  // over MPI ranks: the mean over all the water
    const std::vector<double> totals = ranks::sum_in_rank_order({sum, count});
    sum = totals[0];
    count = totals[1];
  }
  summary.bulk_velocity = count > 0.0 ? sum / count : 0.0;
  BulkVelocityController controller{summary.body_force_integral, 0.0};
  summary.body_force = controller.step(model, summary.bulk_velocity, context.dt);
  summary.body_force_integral = controller.integral;
  return summary.body_force;
}

void FluidPredict::driven_viscous_loop(SystemContext& context, const Vec3& body_acceleration) {
  ParticleState& particles = context.write<ParticleState>();
  ParticlePrediction& prediction = context.write<ParticlePrediction>();
  const FluidNeighbours& neighbours = context.read<FluidNeighbours>();
  const std::size_t fluid_count = fluid_slot_count(particles);
  const WendlandKernel kernel = kernel_;
  const double radius_squared = kernel.effective_radius * kernel.effective_radius;
  const double n0 = constants_.reference_density;
  const bool error_compensation = fluid_.schemes.error_compensating_source;
  // The particles' eddy viscosity: the SPS closure's and the particle-scale one's, either or both.
  const EddyViscosityConstants closures{
      fluid_.turbulence == FluidModel::Turbulence::kSps ? fluid_.smagorinsky_constant : 0.0, fluid_.scatter_viscosity,
      0.1 * fluid_.spacing * fluid_.spacing / context.dt};
  const bool eddy = closures.smagorinsky > 0.0 || closures.scatter > 0.0;
  const double nu = fluid_.kinematic_viscosity;
  // nu <lap u> of run() with the pair viscosity in place of nu: 2D / (lambda0 n0) sum_j nu_ij (u_j - u_i) w_ij.
  const double laplacian_factor = 6.0 / (constants_.laplacian_lambda * n0);

  // The lids: which slot belongs to which lid box, from its rest position (ids and rest positions never change;
  // slots do, at every sort).
  std::vector<std::size_t> lid_boxes;
  for (std::size_t b = 0; b < fluid_.wall_boxes.size(); ++b)
    if (fluid_.wall_boxes[b].lid) lid_boxes.push_back(b);
  const std::size_t lid_count = lid_boxes.size();
  const std::size_t real_count = particles.size();
  const bool spread = neighbours.ranks.active;
  lid_of_.assign(real_count + neighbours.halo.size() + (spread ? neighbours.ranks.ghost_count() : 0), -1);
  if (lid_count > 0) {
    const double tolerance = 1e-9 * std::max(1.0, context.model.tank.size.maxCoeff());
    for_each_particle(particles.size() - fluid_count, [&](std::size_t k) {
      const std::size_t j = fluid_count + k;
      const Vec3& rest = particles.rest_position[j];
      for (std::size_t l = 0; l < lid_count; ++l) {
        const ParticleBoxModel& box = fluid_.wall_boxes[lid_boxes[l]];
        if ((rest.array() >= box.low.array() - tolerance).all() && (rest.array() <= box.high.array() + tolerance).all()) {
          lid_of_[j] = static_cast<std::int32_t>(l);
          break;
        }
      }
    });
    // A periodic tank's ghost slots belong to their owner's lid; over MPI ranks, to the lid their owner sends.
    for (std::size_t g = 0; g < neighbours.halo.size(); ++g)
      lid_of_[real_count + g] = lid_of_[neighbours.halo.owner[g]];
    if (spread) {
      real_lid_.assign(lid_of_.begin(), lid_of_.begin() + static_cast<std::ptrdiff_t>(real_count));
      exchange_fluid_ghost_field(real_lid_, neighbours.ranks, ghost_lid_);
      std::copy(ghost_lid_.begin(), ghost_lid_.end(), lid_of_.begin() + static_cast<std::ptrdiff_t>(real_count));
    }
  }
  std::vector<bool> free_slip(lid_count);
  std::vector<double> plane_low(lid_count), plane_high(lid_count);
  const double tank_z = tank_kinematics(context.model.tank.motion, context.time).displacement.z();
  for (std::size_t l = 0; l < lid_count; ++l) {
    const ParticleBoxModel& box = fluid_.wall_boxes[lid_boxes[l]];
    free_slip[l] = box.lid_free_slip;
    plane_low[l] = box.lid_plane_low + tank_z;
    plane_high[l] = box.lid_plane_high + tank_z;
  }
  // No-slip lids: the lid particle j stands for the velocity extrapolated linearly from the fluid particle i through
  // the lid's value at its plane, u_j' = U - (d_j / d_i)(u_i - U), d the distances to the plane (Morris, Fox & Zhu
  // 1997, J. Comput. Phys. 136, Eq. 30): u_j' - u_i = beta (U - u_i), beta = 1 + d_j / d_i, at most kMaxBeta. With
  // the lid's own velocity instead (beta = 1, as the tank's walls do) a lid 3 layers thick passes 0.48 of the
  // continuum shear stress to a water in linear shear (the sum worked out on the lattice: docs/FLUID.md), a slip.
  // The cap keeps a fluid particle that comes close to the plane from an unbounded weight; 3 leaves the sum within
  // 0.3 % of the uncapped one on the lattice.
  constexpr double kMaxBeta = 3.0;
  const auto extrapolation = [&](std::size_t lid, double z_fluid, double z_lid) {
    double fluid_distance = 0.0, lid_distance = 0.0;
    if (z_fluid <= plane_low[lid]) {
      fluid_distance = plane_low[lid] - z_fluid;
      lid_distance = z_lid - plane_low[lid];
    } else if (z_fluid >= plane_high[lid]) {
      fluid_distance = z_fluid - plane_high[lid];
      lid_distance = plane_high[lid] - z_lid;
    } else {
      return 1.0;  // beside the lid, not under or over it
    }
    if (!(fluid_distance > 0.0)) return kMaxBeta;
    return std::clamp(1.0 + lid_distance / fluid_distance, 1.0, kMaxBeta);
  };

  // nu_t of each fluid particle from the GC-corrected velocity gradient at u^k (wall and lid particles enter with
  // their velocities): grad u_a = A^-1 (1/n0) sum_j (u_a,j - u_a,i) (w_ij / r_ij^2) r_ij, exact for a linear field
  // wherever A is well conditioned (seed Eqs. 8-9, numerics 2.6).
  eddy_viscosity_.assign(eddy ? fluid_count : 0, 0.0);
  if (eddy) particle_eddy_viscosity(particles, neighbours, fluid_count, constants_, closures, eddy_viscosity_);
  // nu_t of a neighbour slot: a fluid slot's own, a periodic ghost's owner's (the exchange of nu_t: it lives and
  // dies within this system), over MPI ranks a ghost's as its owner sends it; 0 for walls.
  if (eddy && spread) {
    real_eddy_.assign(real_count, 0.0);
    std::copy(eddy_viscosity_.begin(), eddy_viscosity_.end(), real_eddy_.begin());
    exchange_fluid_ghost_field(real_eddy_, neighbours.ranks, ghost_eddy_);
  }
  const auto eddy_of = [&](std::uint32_t j) {
    if (spread && j >= real_count) return ghost_eddy_[j - real_count];
    const std::uint32_t owner = j < real_count ? j : neighbours.halo.owner[j - real_count];
    return owner < fluid_count ? eddy_viscosity_[owner] : 0.0;
  };
  const Ghosted<Vec3> position_of = fluid_ghosted(particles.position, neighbours.ghosts.position, neighbours);
  const Ghosted<Vec3> velocity_of = fluid_ghosted(particles.velocity, neighbours.ghosts.velocity, neighbours);
  const Ghosted<std::int32_t> kind_of = fluid_ghosted(particles.kind, neighbours.ghosts.kind, neighbours);

  lid_force_.assign(fluid_count * lid_count, Vec3::Zero());
  const double particle_mass = fluid_.density * fluid_.spacing * fluid_.spacing * fluid_.spacing;
  for_each_particle(fluid_count, [&](std::size_t i) {
    const Vec3 position = particles.position[i];
    const Vec3 velocity = particles.velocity[i];
    const double own_eddy = eddy ? eddy_viscosity_[i] : 0.0;
    Vec3 viscous = Vec3::Zero();
    double density = 0.0, rate = 0.0;
    FluidPairBatch batch;
    for_each_pair_within(
        neighbours_of(neighbours, i), radius_squared, kernel, batch,
        [&](std::uint32_t j) -> Vec3 { return position_of[j] - position; },
        [&](const FluidPairBatch& pair, std::size_t k) {
          const std::uint32_t j = pair.slot[k];
          const double weight = pair.weight[k];
          const Vec3 relative_velocity = velocity_of[j] - velocity;
          const bool fluid_partner = kind_of[j] == kFluidKind;
          const std::int32_t lid = fluid_partner ? -1 : lid_of_[j];
          // A free-slip lid exerts no shear: it is left out of the viscous sum (not of the density terms).
          if (lid < 0 || !free_slip[static_cast<std::size_t>(lid)]) {
            // Pair viscosity nu + (nu_t,i + nu_t,j)/2 (a wall's nu_t is 0): symmetric, so the fluid's momentum is
            // exchanged in pairs (a periodic ghost's nu_t is its owner's).
            const double pair_viscosity = nu + 0.5 * (own_eddy + (eddy && fluid_partner ? eddy_of(j) : 0.0));
            const double beta = lid >= 0 ? extrapolation(static_cast<std::size_t>(lid), position.z(),
                                                         position_of[j].z())
                                         : 1.0;
            const Vec3 term = (laplacian_factor * pair_viscosity * weight * beta) * relative_velocity;
            viscous += term;
            if (lid >= 0) lid_force_[i * lid_count + static_cast<std::size_t>(lid)] += particle_mass * term;
          }
          if (error_compensation) {
            density += weight;
            const double derivative_over_distance = kernel.derivative_over_distance(pair.distance[k]);
            rate += density_rate_term(fluid_partner, derivative_over_distance, pair.offset(k), relative_velocity);
          }
        });
    acceleration_[i] = viscous + body_acceleration;
    if (error_compensation) {
      const double error = (density - n0) / n0;
      prediction.density_rate[i] = std::abs(error) * rate + std::abs(rate) * error;
    }
  });
  if (lid_count > 0) {
    FluidSummary& summary = context.write<FluidSummary>();
    summary.lid_force.assign(lid_count, Vec3::Zero());
    for (std::size_t l = 0; l < lid_count; ++l) {
      const std::array<double, 3> total = deterministic_sums<3>(fluid_count, [&](std::size_t i) {
        const Vec3& force = lid_force_[i * lid_count + l];
        return std::array<double, 3>{force.x(), force.y(), force.z()};
      });
      summary.lid_force[l] = Vec3(total[0], total[1], total[2]);
    }
    if (spread) {  // over MPI ranks: every rank's share, added in rank order
      std::vector<double> shares;
      for (const Vec3& force : summary.lid_force) shares.insert(shares.end(), {force.x(), force.y(), force.z()});
      const std::vector<double> totals = ranks::sum_in_rank_order(shares);
      for (std::size_t l = 0; l < lid_count; ++l)
        summary.lid_force[l] = Vec3(totals[3 * l], totals[3 * l + 1], totals[3 * l + 2]);
    }
  }
}

}  // namespace riffle
