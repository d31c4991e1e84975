#include "systems/mps/fluid_correct.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "systems/physics/fluid_pair_batch.hpp"
#include "systems/physics/tank_kinematics.hpp"

namespace riffle {

Eigen::Matrix3d gradient_correction_matrix(const Eigen::Matrix3d& moment, double density, double reference_density) {
  // B = D A is the identity in the lattice interior; near a void it is nearly singular and its inverse would
  // amplify noise, so fall back to the uncorrected gradient there.
  const Eigen::Matrix3d scaled = (3.0 / reference_density) * moment;
  if (density < 0.5 * reference_density || scaled.determinant() < 0.05) return Eigen::Matrix3d::Identity();
  // Gershgorin's bound settles lambda_min >= 0.2 for most particles without the eigen-solver.
  double gershgorin = scaled(0, 0) - std::abs(scaled(0, 1)) - std::abs(scaled(0, 2));
  gershgorin = std::min(gershgorin, scaled(1, 1) - std::abs(scaled(1, 0)) - std::abs(scaled(1, 2)));
  gershgorin = std::min(gershgorin, scaled(2, 2) - std::abs(scaled(2, 0)) - std::abs(scaled(2, 1)));
  if (gershgorin >= 0.2) return scaled.inverse();
  const double smallest =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scaled, Eigen::EigenvaluesOnly).eigenvalues()[0];
  if (smallest < 0.2) return Eigen::Matrix3d::Identity();
  return scaled.inverse();
}

void FluidCorrect::run(SystemContext& context) {
  ParticleState& particles = context.write<ParticleState>();
  const ParticlePrediction& prediction = context.read<ParticlePrediction>();
  ParticlePressure& pressures = context.write<ParticlePressure>();
  const FluidNeighbours& neighbours = context.read<FluidNeighbours>();
  const std::size_t fluid_count = fluid_slot_count(particles);
  const FluidSchemes& schemes = fluid_.schemes;
  const WendlandKernel kernel = constants_.kernel;
  const double radius_squared = kernel.effective_radius * kernel.effective_radius;
  const double n0 = constants_.reference_density;
  const double dt = context.dt;
  const double rho = fluid_.density;
  const double stabilisation_distance = fluid_.stabilisation_distance();
  // Wall and dummy pressure seen from fluid particle i: hydrostatic in the tank frame (amendment 1), so GC is exact
  // for hydrostatics and the contact line sees p ~ 0.
  const Vec3 body_acceleration =
      context.model.gravity - tank_kinematics(context.model.tank.motion, context.time + dt).acceleration;
  const Vec3 wall_pressure_gradient = rho * body_acceleration;

  for_each_particle(fluid_count, [&](std::size_t i) {
    const Vec3 position = prediction.predicted_position[i];
    const double pressure = pressures.pressure[i];
    const auto partner_pressure = [&](std::uint32_t j, const Vec3& offset) {
      return particles.kind[j] == kFluidKind ? pressures.pressure[j] : pressure + wall_pressure_gradient.dot(offset);
    };
    // Classic gradient (GC off): p_j - min p over the support, which keeps the pressure force repulsive.
    double base_pressure = pressure;
    if (!schemes.gradient_correction) {
      for (const std::uint32_t j : near_neighbours_of(neighbours, i)) {
        const Vec3 offset = prediction.predicted_position[j] - position;
        if (offset.squaredNorm() < radius_squared) base_pressure = std::min(base_pressure, partner_pressure(j, offset));
      }
    }
    Vec3 gradient_sum = Vec3::Zero(), stabilisation = Vec3::Zero();
    double moment_xx = 0.0, moment_xy = 0.0, moment_xz = 0.0, moment_yy = 0.0, moment_yz = 0.0, moment_zz = 0.0;
    double density = 0.0;
    FluidPairBatch batch;
    for_each_near_pair(
        near_neighbours_of(neighbours, i), kernel, batch,
        [&](std::uint32_t j) -> Vec3 { return prediction.predicted_position[j] - position; },
        [&](const FluidPairBatch& pair, std::size_t k) {
          if (pair.distance_squared[k] == 0.0) return;
          const std::uint32_t j = pair.slot[k];
          const Vec3 offset = pair.offset(k);
          const double distance = pair.distance[k];
          const double weight = pair.weight[k];
          const double weight_over_squared = weight * pair.inverse_squared[k];
          gradient_sum += ((partner_pressure(j, offset) - base_pressure) * weight_over_squared) * offset;
          if (schemes.gradient_correction) {
            const Vec3 scaled = weight_over_squared * offset;
            moment_xx += scaled[0] * offset[0];
            moment_xy += scaled[0] * offset[1];
            moment_xz += scaled[0] * offset[2];
            moment_yy += scaled[1] * offset[1];
            moment_yz += scaled[1] * offset[2];
            moment_zz += scaled[2] * offset[2];
            density += weight;
          }
          if (schemes.dynamic_stabilisation && distance < stabilisation_distance) {
            // rho_j / (rho_i + rho_j): 1/2 between fluid particles, 1 against an (infinitely heavy) wall.
            const double partner_share = particles.kind[j] == kFluidKind ? 0.5 : 1.0;
            stabilisation -=
                (partner_share * (stabilisation_distance - distance) * weight_over_squared * distance) * offset;
          }
        });
    Vec3 gradient = (3.0 / n0) * gradient_sum;
    if (schemes.gradient_correction) {
      Eigen::Matrix3d moment;
      moment << moment_xx, moment_xy, moment_xz, moment_xy, moment_yy, moment_yz, moment_xz, moment_yz, moment_zz;
      gradient = gradient_correction_matrix(moment, density, n0) * gradient;
    }
    pressures.pressure_gradient[i] = gradient;  // sampled by the grains (solid_fluid_sampling)
    const Vec3 change = -dt / rho * gradient + stabilisation / (n0 * dt);
    particles.velocity[i] += change;
    particles.position[i] = position + dt * change;
  });
  context.count_items(fluid_count);
}

}  // namespace riffle
