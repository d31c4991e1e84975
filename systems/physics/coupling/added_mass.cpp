#include "systems/physics/coupling/added_mass.hpp"

#include "systems/physics/coupling/drag_law.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace riffle {

namespace {
}

double added_mass_coefficient(double voidage) {
  const double solid_fraction = 1.0 - std::clamp(voidage, 1e-6, 1.0);
  return 0.5 * (1.0 + 2.0 * solid_fraction) / (1.0 - solid_fraction);
}

double stable_added_mass_coefficient(double voidage, CouplingModel::FluidVelocity reading) {
  const double eps = std::clamp(voidage, 1e-6, 1.0);
  const double solid_fraction = 1.0 - eps;
  const double zuber = added_mass_coefficient(eps);
  if (solid_fraction <= 0.0) return zuber;
  const double cap = 0.5 * flux_share(reading, eps) * eps / solid_fraction;
  return std::min(zuber, cap);
}

BassetModes BassetModes::make(double window, double shortest) {
  BassetModes modes;
  const double lowest = std::log(1.0 / window);
  const double highest = std::log(20.0 / shortest);
  const double spacing = std::min(1.5, std::max(1e-3, (highest - lowest) / static_cast<double>(kCount - 1)));
  for (std::size_t k = 0; k < kCount; ++k) {
    const double x = lowest + spacing * static_cast<double>(k);
    modes.rate[k] = std::exp(x);
    modes.weight[k] = spacing * std::exp(0.5 * x) / std::sqrt(std::numbers::pi);
  }
  // Trapezoidal end weights: half a node at each end, and the nodes left out lumped into the end modes. Below
  // 1/window: pi^(-1/2) int_{-inf}^{x_0} e^{x/2} dx = 2 (s_0/pi)^(1/2), into the lowest mode (the window's
  // exponential tail). Above the top rate s_n the left-out modes matter only within 1/s_n = shortest/20 of the
  // present, through their integral over it, pi^(-1/2) int_{x_n}^{inf} e^{-x/2} dx = 2 (pi s_n)^(-1/2): the top mode
  // carries it with an extra weight 2 (s_n/pi)^(1/2).
  const double top = lowest + spacing * static_cast<double>(kCount - 1);
  modes.weight[0] = (0.5 * spacing + 2.0) * std::exp(0.5 * lowest) / std::sqrt(std::numbers::pi);
  modes.weight[kCount - 1] = (0.5 * spacing + 2.0) * std::exp(0.5 * top) / std::sqrt(std::numbers::pi);
  return modes;
}

double basset_prefactor(double diameter, double density, double viscosity) {
  return 1.5 * diameter * diameter * std::sqrt(std::numbers::pi * density * viscosity);
}

}  // namespace riffle
