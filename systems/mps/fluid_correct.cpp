#include "systems/mps/fluid_correct.hpp"

#include "systems/physics/ranks/rank_comm.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "systems/physics/mps/driven_flow.hpp"
#include "systems/physics/mps/fluid_pair_batch.hpp"
#include "systems/physics/mps/hydrostatic.hpp"
#include "systems/physics/mps/mps_operators.hpp"
#include "systems/physics/geometry/periodic_box.hpp"
#include "systems/physics/geometry/tank_kinematics.hpp"

namespace riffle {

void FluidCorrect::run(SystemContext& context) {
  ParticleState& particles = context.write<ParticleState>();
  const ParticlePrediction& prediction = context.read<ParticlePrediction>();
  ParticlePressure& pressures = context.write<ParticlePressure>();
  const FluidNeighbours& neighbours = context.read<FluidNeighbours>();
  const std::size_t fluid_count = fluid_slot_count(particles);
  const FluidSchemes& schemes = fluid_.schemes;
  const WendlandKernel kernel = kernel_;
  const double radius_squared = kernel.effective_radius * kernel.effective_radius;
  const double n0 = constants_.reference_density;
  const double dt = context.dt;
  const double rho = fluid_.density;
  const double stabilisation_distance = fluid_.stabilisation_distance();
  // Wall and dummy pressure seen from fluid particle i: hydrostatic in the tank frame (amendment 1), so GC is exact
  // for hydrostatics and the contact line sees p ~ 0.
  // A body force f along x joins gravity (it is one: the fluid at rest under it has grad p = rho (g + f e_x - a)).
  Vec3 body_acceleration = context.model.gravity;
  if (fluid_.body_force.kind == BodyForceModel::Kind::kBulkVelocity)
    body_acceleration.x() += context.read<FluidSummary>().body_force;
  else if (fluid_.body_force.kind != BodyForceModel::Kind::kNone)
    body_acceleration.x() += prescribed_body_force(fluid_.body_force, context.time);
  const Vec3 wall_pressure_gradient = hydrostatic_gradient(
      rho, body_acceleration, tank_kinematics(context.model.tank.motion, context.time + dt).acceleration);

  // Slots beyond the reals are a periodic tank's ghosts (r* and kinds from fluid_neighbours_predicted, p^{k+1} from
  // fluid_pressure).
  const Ghosted<Vec3> predicted_of =
      fluid_ghosted(prediction.predicted_position, neighbours.ghosts.predicted_position, neighbours);
  const Ghosted<std::int32_t> kind_of = fluid_ghosted(particles.kind, neighbours.ghosts.kind, neighbours);
  // The ghosts' p^{k+1} come from fluid_pressure's exchange, which runs only if that solve was built periodic (it
  // takes the model, as the searches' box does): a pipeline whose searches built a halo but whose solve did not
  // exchange would read past the ghost pressures. Refuse it by name rather than read garbage.
  if (neighbours.ranks.active && neighbours.ghosts.pressure.size() != neighbours.ranks.ghost_count())
    throw std::logic_error("fluid_correct: the neighbour lists hold " + std::to_string(neighbours.ranks.ghost_count()) +
                           " ghosts from other ranks but fluid_pressure sent " +
                           std::to_string(neighbours.ghosts.pressure.size()) + " ghost pressures");
  if (neighbours.halo.valid && neighbours.ghosts.pressure.size() != neighbours.halo.size())
    throw std::logic_error("fluid_correct: the neighbour lists hold " + std::to_string(neighbours.halo.size()) +
                           " periodic ghosts but fluid_pressure exchanged " +
                           std::to_string(neighbours.ghosts.pressure.size()) +
                           " ghost pressures: the pressure solve and the searches disagree on the periodic box "
                           "(build FluidPressureSolve from the same model as the searches' periodic_box)");
  const Ghosted<double> pressure_of = fluid_ghosted(pressures.pressure, neighbours.ghosts.pressure, neighbours);
  // A particle that leaves the period comes back through the other face: the jump of one period uses up the
  // neighbour lists' skin, so the next search rebuilds them (and the halo).
  const PeriodicBox box = periodic_box(context.model);
  const bool periodic = box.any();

  // The conservative gradient ([fluid.schemes] conservative_gradient; docs/FLUID.md, "A momentum-conserving
  // gradient"): <grad p>_i = G + (3/n0) sum_j (q_i + q_j) (w_ij / r_ij^2) r_ij with q = p - G . r - min(p - G . r),
  // G the hydrostatic gradient. The bracket is the same seen from either end of a pair and r_ij changes sign, so the
  // fluid pairs' pressure forces cancel (the water's momentum changes only through G, which has no component along
  // a periodic axis, and the walls). G is taken out first so that still water is exact (q constant: the sum
  // vanishes) and only the dynamic pressure carries the sum form's error 2 q_i m_i (m_i the first moment of i's
  // neighbourhood); the global min keeps every fluid pair's bracket >= 0 (repulsive, as the classic p_j - min p).
  const bool conservative = schemes.conservative_gradient;
  Vec3 split_gradient = wall_pressure_gradient;
  double reduced_minimum = 0.0;
  if (conservative) {
    // Along a periodic axis the water's pressure has no mean gradient, and a ghost's G . r must differ from its
    // owner's by nothing, or the pair's two brackets would differ by G . shift.
    for (int axis = 0; axis < 3; ++axis)
      if (box.periodic[axis]) split_gradient[axis] = 0.0;
    reduced_minimum = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < fluid_count; ++i)
      reduced_minimum =
          std::min(reduced_minimum, pressures.pressure[i] - split_gradient.dot(prediction.predicted_position[i]));
    // Over MPI ranks the minimum over all the water (a min is exact in any order).
    if (neighbours.ranks.active) reduced_minimum = -ranks::max(-reduced_minimum);
  }

  for_each_particle(fluid_count, [&](std::size_t i) {
    const Vec3 position = prediction.predicted_position[i];
    const double pressure = pressures.pressure[i];
    // Walls: extrapolated as for GC in either form, so under a body force along a periodic axis a wall partner's q
    // is q_i + rho f r_x (extrapolating with the split G instead, q_wall = q_i, raised the Poiseuille channel's error
    // from 1.06 % to 1.75 %: docs/FLUID.md).
    const auto partner_pressure = [&](std::uint32_t j, const Vec3& offset) {
      return kind_of[j] == kFluidKind ? pressure_of[j]
                                      : hydrostatic_extrapolation(pressure, wall_pressure_gradient, offset);
    };
    // Classic gradient (GC off): p_j - min p over the support, which keeps the pressure force repulsive.
    double base_pressure = pressure;
    if (!schemes.gradient_correction && !conservative) {
      for (const std::uint32_t j : near_neighbours_of(neighbours, i)) {
        const Vec3 offset = predicted_of[j] - position;
        if (offset.squaredNorm() < radius_squared) base_pressure = std::min(base_pressure, partner_pressure(j, offset));
      }
    }
    // q_i, and a partner's q_j from its own p and r* (a wall's from its extrapolated p at r_i + r_ij).
    const double reduced = pressure - split_gradient.dot(position) - reduced_minimum;
    const auto pressure_difference = [&](std::uint32_t j, const Vec3& offset) {
      if (!conservative) return partner_pressure(j, offset) - base_pressure;
      const Vec3 partner_position = kind_of[j] == kFluidKind ? predicted_of[j] : Vec3(position + offset);
      return reduced + (partner_pressure(j, offset) - split_gradient.dot(partner_position) - reduced_minimum);
    };
    // What the grains sample ([fluid.schemes] grain_gradient): the gradient that moves the water, or with
    // "corrected" GC's gradient of the same p^{k+1} (sampled_sum, through the moment). The sum form's error
    // 2 q_i m_i carries shear stress through sheared water (a repulsion between disordered particles): the applied
    // gradient gives the grains their share of it, as of every stress the water carries; GC's is blind to it, so a
    // sheared bed then takes less than the lid's drag (docs/FLUID.md, "What the grains sample").
    const bool sample_corrected = conservative && schemes.grain_gradient == FluidSchemes::GrainGradient::kCorrected;
    const bool gc_moment = schemes.gradient_correction || sample_corrected;
    Vec3 gradient_sum = Vec3::Zero(), sampled_sum = Vec3::Zero(), stabilisation = Vec3::Zero();
    GradientMoment moment;
    FluidPairBatch batch;
    for_each_near_pair(
        near_neighbours_of(neighbours, i), kernel, batch,
        [&](std::uint32_t j) -> Vec3 { return predicted_of[j] - position; },
        [&](const FluidPairBatch& pair, std::size_t k) {
          if (pair.distance_squared[k] == 0.0) return;
          const std::uint32_t j = pair.slot[k];
          const Vec3 offset = pair.offset(k);
          const double distance = pair.distance[k];
          const double weight = pair.weight[k];
          const double weight_over_squared = weight * pair.inverse_squared[k];
          gradient_sum += gradient_term(pressure_difference(j, offset), weight_over_squared, offset);
          if (sample_corrected)
            sampled_sum += gradient_term(partner_pressure(j, offset) - pressure, weight_over_squared, offset);
          if (gc_moment) moment.add(weight, weight_over_squared, offset);
          if (schemes.dynamic_stabilisation && distance < stabilisation_distance) {
            // rho_j / (rho_i + rho_j): 1/2 between fluid particles, 1 against an (infinitely heavy) wall.
            const double partner_share = kind_of[j] == kFluidKind ? 0.5 : 1.0;
            stabilisation +=
                stabilisation_term(partner_share, stabilisation_distance, distance, weight_over_squared, offset);
          }
        });
    Vec3 gradient = (3.0 / n0) * gradient_sum;
    if (schemes.gradient_correction) gradient = gradient_correction_matrix(moment, n0) * gradient;
    if (conservative) gradient += split_gradient;
    pressures.applied_pressure_gradient[i] = gradient;
    // Sampled by the grains (solid_fluid_sampling).
    pressures.pressure_gradient[i] =
        sample_corrected ? Vec3(gradient_correction_matrix(moment, n0) * ((3.0 / n0) * sampled_sum)) : gradient;
    const Vec3 change = -dt / rho * gradient + stabilisation / (n0 * dt);
    particles.velocity[i] += change;
    particles.position[i] = periodic ? box.wrap(position + dt * change) : position + dt * change;
  });
  context.count_items(fluid_count);
}

}  // namespace riffle
