#include "systems/physics/mps_operators.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace riffle {

double number_density(const Vec3& position, const std::vector<Vec3>& positions, NeighbourSpan neighbours,
                      const WendlandKernel& kernel) {
  double sum = 0.0;
  for (const std::uint32_t* j = neighbours.begin; j != neighbours.end; ++j)
    sum += kernel.weight((positions[*j] - position).norm());
  return sum;
}

double number_density_rate(const Vec3& position, const Vec3& velocity, const std::vector<Vec3>& positions,
                           const std::vector<Vec3>& velocities, NeighbourSpan neighbours,
                           const WendlandKernel& kernel) {
  double sum = 0.0;
  for (const std::uint32_t* j = neighbours.begin; j != neighbours.end; ++j) {
    const Vec3 offset = positions[*j] - position;
    sum += kernel.derivative_over_distance(offset.norm()) * offset.dot(velocities[*j] - velocity);
  }
  return sum;
}

double laplacian(const Vec3& position, double value, const std::vector<Vec3>& positions,
                 const std::vector<double>& values, NeighbourSpan neighbours, const WendlandKernel& kernel,
                 double reference_density) {
  double sum = 0.0;
  for (const std::uint32_t* j = neighbours.begin; j != neighbours.end; ++j) {
    const double coefficient = -2.0 * kernel.derivative_over_distance((positions[*j] - position).norm());
    sum += coefficient * (values[*j] - value);
  }
  return sum / reference_density;
}

Eigen::Matrix3d gradient_correction(const Vec3& position, const std::vector<Vec3>& positions, NeighbourSpan neighbours,
                                    const WendlandKernel& kernel, double reference_density) {
  constexpr double kDimension = 3.0;
  Eigen::Matrix3d moment = Eigen::Matrix3d::Zero();
  double density = 0.0;
  for (const std::uint32_t* j = neighbours.begin; j != neighbours.end; ++j) {
    const Vec3 offset = positions[*j] - position;
    const double distance_squared = offset.squaredNorm();
    const double weight = kernel.weight(std::sqrt(distance_squared));
    if (weight <= 0.0 || distance_squared == 0.0) continue;
    density += weight;
    moment += (weight / distance_squared) * offset * offset.transpose();
  }
  // B = D A is the identity in the lattice interior; fall back to no correction where B is nearly singular.
  const Eigen::Matrix3d scaled = (kDimension / reference_density) * moment;
  if (density < 0.5 * reference_density || scaled.determinant() < 0.05) return Eigen::Matrix3d::Identity();
  const double smallest = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scaled, Eigen::EigenvaluesOnly).eigenvalues()[0];
  if (smallest < 0.2) return Eigen::Matrix3d::Identity();
  return scaled.inverse();  // C = (1/D) A^{-1} = (D A)^{-1}
}

Vec3 corrected_gradient(const Vec3& position, double value, const Eigen::Matrix3d& correction,
                        const std::vector<Vec3>& positions, const std::vector<double>& values,
                        NeighbourSpan neighbours, const WendlandKernel& kernel, double reference_density) {
  constexpr double kDimension = 3.0;
  Vec3 sum = Vec3::Zero();
  for (const std::uint32_t* j = neighbours.begin; j != neighbours.end; ++j) {
    const Vec3 offset = positions[*j] - position;
    const double distance_squared = offset.squaredNorm();
    if (distance_squared == 0.0) continue;
    sum += ((values[*j] - value) / distance_squared * kernel.weight(std::sqrt(distance_squared))) * offset;
  }
  return (kDimension / reference_density) * (correction * sum);
}

Vec3 stabilisation_velocity(const Vec3& position, const std::vector<Vec3>& positions, NeighbourSpan neighbours,
                            const WendlandKernel& kernel, double reference_density, double stabilisation_distance,
                            double partner_share, double dt) {
  Vec3 correction = Vec3::Zero();
  for (const std::uint32_t* j = neighbours.begin; j != neighbours.end; ++j) {
    const Vec3 offset = positions[*j] - position;
    const double distance = offset.norm();
    if (distance >= stabilisation_distance || distance == 0.0) continue;
    const double missing = stabilisation_distance - distance;
    correction -= (partner_share * missing / dt * kernel.weight(distance) / distance) * offset;
  }
  return correction / reference_density;
}

}  // namespace riffle
