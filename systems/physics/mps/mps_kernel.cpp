#include "systems/physics/mps/mps_kernel.hpp"

#include <cmath>
#include <stdexcept>

namespace riffle {

LatticeConstants lattice_constants(int dimension, double spacing, double effective_radius) {
  if (dimension != 2 && dimension != 3) throw std::invalid_argument("lattice_constants: dimension must be 2 or 3");
  if (!(spacing > 0.0) || !(effective_radius > 0.0))
    throw std::invalid_argument("lattice_constants: spacing and effective radius must be positive");
  const WendlandKernel kernel{effective_radius};
  const auto reach = static_cast<std::int64_t>(std::ceil(effective_radius / spacing));
  const std::int64_t z_reach = dimension == 3 ? reach : 0;
  LatticeConstants constants;
  double weighted_square_sum = 0.0, derivative_sum = 0.0;
  for (std::int64_t i = -reach; i <= reach; ++i)
    for (std::int64_t j = -reach; j <= reach; ++j)
      for (std::int64_t k = -z_reach; k <= z_reach; ++k) {
        if (i == 0 && j == 0 && k == 0) continue;
        const double distance =
            spacing * std::sqrt(static_cast<double>(i * i + j * j + k * k));
        const double weight = kernel.weight(distance);
        if (weight <= 0.0) continue;
        constants.number_density += weight;
        ++constants.neighbour_count;
        weighted_square_sum += distance * distance * weight;
        derivative_sum += kernel.derivative(distance) * distance;
      }
  constants.laplacian_lambda = weighted_square_sum / constants.number_density;
  constants.operator_bias = -derivative_sum / (constants.number_density * dimension);
  return constants;
}

}  // namespace riffle
