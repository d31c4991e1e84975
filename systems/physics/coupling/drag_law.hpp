#pragma once
// The drag law of seed 000 Eqs. 20-25 (numerics.md 5.1): F = beta V / (1 - eps) (u_fluid - u_grain), with Ergun's
// beta for eps <= 0.8 and Wen & Yu's above ([coupling] dense_drag = "wen_yu": Wen & Yu's at every voidage). Written
// as the drag per unit grain volume and slip velocity, k = beta / (1 - eps), which stays finite as eps -> 1 (a
// single sphere: k = 3/4 C_D rho |du| / d).
#include <cmath>

#include "components/model.hpp"

namespace riffle {

/// [1] What the water's velocity u stands for inside the bed, as a share of the volume: the voidage eps in the
/// mixture reading (u is the mixture's volume flux, so the pore water moves relative to a grain at (u - v) / eps and
/// the water takes the grains' drag per volume over eps), 1 in the pore reading (u is the pore water's velocity).
/// Every place the reading changes (the drag's slip, its reaction, the history force's slip, the added mass's
/// stability cap, the drag's step limit, the sampled flux) divides or multiplies by this.
inline double flux_share(CouplingModel::FluidVelocity reading, double voidage) {
  return reading == CouplingModel::FluidVelocity::kMixture ? voidage : 1.0;
}

/// [m^3] Volume of a grain of `radius` as the voidage and the pressure force -V <grad p> count it.
inline double grain_volume(double radius) { return 4.0 / 3.0 * 3.14159265358979323846 * std::pow(radius, 3); }

/// C_D Re_p for a sphere: 24 (1 + 0.15 Re^0.687) up to Re_p = 1000, then C_D,Newton Re_p (finite as Re_p -> 0).
double drag_coefficient_times_reynolds(double reynolds, double newton_drag_coefficient);

/// Whether drag_per_volume takes Ergun's law at `voidage` (else Wen & Yu's).
inline bool ergun_applies(double voidage, const CouplingModel& coupling) {
  return voidage <= 0.8 && coupling.dense_drag == CouplingModel::DenseDrag::kErgun;
}

/// Ergun's k = beta / (1 - eps) split by its dependence on the slip speed |w|: k = viscous + inertial |w|. A grain's
/// voidage holds over a fluid step, so its sub-steps need only |w| (solid_drag_law sets the two once a step).
struct ErgunDrag {
  double viscous = 0.0;   ///< [kg/(m^3 s)] eps^2 mu / (K (1 - eps)), K = eps^3 d^2 / (150 (1 - eps)^2)
  double inertial = 0.0;  ///< [kg/m^4] F_ch eps^3 rho / (sqrt(K) (1 - eps)), F_ch = 1.75 / (sqrt(150) eps^n)
};
/// Ergun's two terms for a grain of `diameter` at `voidage` (<= 0.8) in a fluid of `density` and dynamic `viscosity`,
/// with the inertial term's voidage exponent n = coupling.ergun_inertial_exponent.
ErgunDrag ergun_drag(double voidage, double diameter, double density, double viscosity, const CouplingModel& coupling);

/// k = beta / (1 - eps) [kg / (m^3 s)] for a grain of `diameter` at voidage `voidage` with slip speed `slip`, in a
/// fluid of density `density` and dynamic viscosity `viscosity`.
double drag_per_volume(double voidage, double diameter, double slip, double density, double viscosity,
                       const CouplingModel& coupling);

}  // namespace riffle
