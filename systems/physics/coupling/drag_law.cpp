#include "systems/physics/coupling/drag_law.hpp"

#include <cmath>

namespace riffle {

double drag_coefficient_times_reynolds(double reynolds, double newton_drag_coefficient) {
  if (reynolds <= 1000.0) return 24.0 * (1.0 + 0.15 * std::pow(reynolds, 0.687));
  return newton_drag_coefficient * reynolds;
}

ErgunDrag ergun_drag(double voidage, double diameter, double density, double viscosity, const CouplingModel& coupling) {
  // beta = eps^2 mu / K + F_ch eps^3 rho |du| / sqrt(K), K = eps^3 d^2 / (150 (1 - eps)^2); k = beta / (1 - eps)
  const double eps = voidage;
  const double solid = 1.0 - eps;
  const double permeability = eps * eps * eps * diameter * diameter / (150.0 * solid * solid);
  const double eps_power = coupling.ergun_inertial_exponent == 1.5 ? eps * std::sqrt(eps)  // the default, cheaply
                                                                   : std::pow(eps, coupling.ergun_inertial_exponent);
  const double forchheimer = 1.75 / (std::sqrt(150.0) * eps_power);
  return {eps * eps * viscosity / (permeability * solid),
          forchheimer * eps * eps * eps * density / (std::sqrt(permeability) * solid)};
}

double drag_per_volume(double voidage, double diameter, double slip, double density, double viscosity,
                       const CouplingModel& coupling) {
  const double eps = voidage;
  if (ergun_applies(eps, coupling)) {
    const ErgunDrag ergun = ergun_drag(eps, diameter, density, viscosity, coupling);
    return ergun.viscous + ergun.inertial * slip;
  }
  // Wen & Yu: beta = 3/4 (C_D Re_p) (1 - eps) eps^-2.65 mu / d^2, Re_p = eps rho d |du| / mu
  const double reynolds = eps * density * diameter * slip / viscosity;
  return 0.75 * drag_coefficient_times_reynolds(reynolds, coupling.newton_drag_coefficient) *
         std::pow(eps, -2.65) * viscosity / (diameter * diameter);
}

}  // namespace riffle
