#include "systems/physics/mps/mps_operators.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace riffle {

Eigen::Matrix3d gradient_correction_matrix(const GradientMoment& moment, double reference_density) {
  // B = D A is the identity in the lattice interior; near a void it is nearly singular and its inverse would
  // amplify noise, so fall back to the uncorrected gradient there.
  const Eigen::Matrix3d scaled = (3.0 / reference_density) * moment.matrix();
  if (moment.density < 0.5 * reference_density || scaled.determinant() < 0.05) return Eigen::Matrix3d::Identity();
  // Gershgorin's bound settles lambda_min >= 0.2 for most particles without the eigen-solver.
  double gershgorin = scaled(0, 0) - std::abs(scaled(0, 1)) - std::abs(scaled(0, 2));
  gershgorin = std::min(gershgorin, scaled(1, 1) - std::abs(scaled(1, 0)) - std::abs(scaled(1, 2)));
  gershgorin = std::min(gershgorin, scaled(2, 2) - std::abs(scaled(2, 0)) - std::abs(scaled(2, 1)));
  if (gershgorin >= 0.2) return scaled.inverse();
  const double smallest =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scaled, Eigen::EigenvaluesOnly).eigenvalues()[0];
  if (smallest < 0.2) return Eigen::Matrix3d::Identity();
  return scaled.inverse();  // C = (1/D) A^{-1} = (D A)^{-1}
}

}  // namespace riffle
