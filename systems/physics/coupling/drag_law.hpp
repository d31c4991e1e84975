#pragma once
// The drag law of seed 000 Eqs. 20-25 (numerics.md 5.1): F = beta V / (1 - eps) (u_fluid - u_grain), with Ergun's
// beta for eps <= 0.8 and Wen & Yu's above ([coupling] dense_drag = "wen_yu": Wen & Yu's at every voidage). Written
// as the drag per unit grain volume and slip velocity, k = beta / (1 - eps), which stays finite as eps -> 1 (a
// single sphere: k = 3/4 C_D rho |du| / d).
#include <cmath>

#include "components/model.hpp"

namespace riffle {

/// [m^3] Volume of a grain of `radius` as the voidage and the pressure force -V <grad p> count it.
inline double grain_volume(double radius) { return 4.0 / 3.0 * 3.14159265358979323846 * std::pow(radius, 3); }

/// C_D Re_p for a sphere: 24 (1 + 0.15 Re^0.687) up to Re_p = 1000, then C_D,Newton Re_p (finite as Re_p -> 0).
double drag_coefficient_times_reynolds(double reynolds, double newton_drag_coefficient);

/// k = beta / (1 - eps) [kg / (m^3 s)] for a grain of `diameter` at voidage `voidage` with slip speed `slip`, in a
/// fluid of density `density` and dynamic viscosity `viscosity`.
double drag_per_volume(double voidage, double diameter, double slip, double density, double viscosity,
                       const CouplingModel& coupling);

}  // namespace riffle
