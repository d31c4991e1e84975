#include "systems/physics/mps/driven_flow.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "systems/physics/mps/fluid_pair_batch.hpp"
#include "systems/physics/mps/mps_operators.hpp"

namespace riffle {

double prescribed_body_force(const BodyForceModel& model, double time) { return model.prescribed(time); }

double BulkVelocityController::step(const BodyForceModel& model, double bulk, double dt) {
  const double error = model.target_velocity - bulk;
  force = model.proportional_gain * error + model.integral_gain * integral;
  integral += error * dt;
  return force;
}

PiGains pi_gains(double plant_time, double response_time, double damping_ratio) {
  if (!(plant_time > 0.0) || !(response_time > 0.0) || !(damping_ratio > 0.0))
    throw std::invalid_argument("pi_gains: the times and the damping ratio must be positive");
  const double omega = 1.0 / response_time;
  return {std::max(0.0, 2.0 * damping_ratio * omega - 1.0 / plant_time), omega * omega};
}

double lid_particle_x(double rest_x, double start, double period, double velocity, double time) {
  const double travelled = rest_x - start + velocity * time;
  return start + (travelled - period * std::floor(travelled / period));
}

double strain_rate_magnitude(const Eigen::Matrix3d& velocity_gradient) {
  const Eigen::Matrix3d strain = 0.5 * (velocity_gradient + velocity_gradient.transpose());
  return std::sqrt(2.0 * strain.cwiseAbs2().sum());
}

double smagorinsky_viscosity(double constant, double filter_width, const Eigen::Matrix3d& velocity_gradient) {
  const double length = constant * filter_width;
  return length * length * strain_rate_magnitude(velocity_gradient);
}

void particle_eddy_viscosity(const ParticleState& particles, const FluidNeighbours& neighbours, std::size_t fluid_count,
                             const MpsConstants& constants, const EddyViscosityConstants& closures,
                             std::vector<double>& out) {
  const WendlandKernel kernel{constants.effective_radius};
  const double radius_squared = kernel.effective_radius * kernel.effective_radius;
  const double n0 = constants.reference_density;
  out.resize(fluid_count);
  // Slots beyond the reals are a periodic tank's ghosts (FluidNeighbours::halo).
  const Ghosted<Vec3> position_of = fluid_ghosted(particles.position, neighbours.ghosts.position, neighbours);
  const Ghosted<Vec3> velocity_of = fluid_ghosted(particles.velocity, neighbours.ghosts.velocity, neighbours);
  for_each_particle(fluid_count, [&](std::size_t i) {
    const Vec3 position = particles.position[i];
    const Vec3 velocity = particles.velocity[i];
    Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();  // sum_j (w / r^2) r_ij (u_j - u_i)^T
    Vec3 difference = Vec3::Zero(), first_moment = Vec3::Zero();  // sum_j w (u_j - u_i), sum_j w r_ij
    GradientMoment moment;
    FluidPairBatch batch;
    for_each_pair_within(
        neighbours_of(neighbours, i), radius_squared, kernel, batch,
        [&](std::uint32_t j) -> Vec3 { return position_of[j] - position; },
        [&](const FluidPairBatch& pair, std::size_t k) {
          if (pair.distance_squared[k] == 0.0) return;
          const Vec3 offset = pair.offset(k);
          const double weight_over_squared = pair.weight[k] * pair.inverse_squared[k];
          const Vec3 relative_velocity = velocity_of[pair.slot[k]] - velocity;
          sum += (weight_over_squared * offset) * relative_velocity.transpose();
          if (closures.scatter > 0.0) {
            difference += pair.weight[k] * relative_velocity;
            first_moment += pair.weight[k] * offset;
          }
          moment.add(pair.weight[k], weight_over_squared, offset);
        });
    // Column a of (D/n0) C sum is grad u_a; the transpose puts d u_a / d x_b at [a][b].
    const Eigen::Matrix3d gradient = ((3.0 / n0) * gradient_correction_matrix(moment, n0) * sum).transpose();
    double viscosity = closures.smagorinsky > 0.0
                           ? smagorinsky_viscosity(closures.smagorinsky, constants.spacing, gradient)
                           : 0.0;
    if (closures.scatter > 0.0 && moment.density > 0.0) {
      // sum_j w (u_j - u_i - grad u r_ij) = sum_j w (u_j - u_i) - grad u sum_j w r_ij
      const double scatter = (difference - gradient * first_moment).norm() / moment.density;
      viscosity += std::min(scatter_viscosity(closures.scatter, constants.spacing, scatter), closures.scatter_ceiling);
    }
    out[i] = viscosity;
  });
}

}  // namespace riffle
