#pragma once
// What a grain reads from the mean-flow column besides the mean velocity at its centre (docs/cases/bedload.md,
// "Lift and velocity fluctuations"): the shear lift of the velocity difference across it, and a stochastic velocity
// fluctuation of the turbulence around it. Pure functions; systems/coupling/mean_flow_grains calls them.
#include <cstdint>

#include "components/mean_flow.hpp"
#include "components/vec.hpp"
#include "systems/physics/mean_flow/column.hpp"

namespace riffle {

/// [N] The shear lift on a sphere in the velocity gradient over a bed (Wiberg & Smith 1985, "A theoretical model for
/// saltating grains in water", J. Geophys. Res. 90(C4); Wiberg & Smith 1987, Water Resour. Res. 23, with C_L = 0.2
/// after Chepil 1958's measurements on hemispheres), upward:
///   F_L = 1/2 rho C_L pi r^2 (|u_top - v|^2 - |u_bottom - v|^2),
/// u_top and u_bottom the water's horizontal velocity at the sphere's top and bottom, v the sphere's (the relative
/// velocities, as YADE's HydroForceEngine takes them; only their horizontal parts count).
double shear_lift(double density, double lift_coefficient, double radius, const Vec3& top_relative,
                  const Vec3& bottom_relative);

/// The water's turbulent shear at one height: the kinematic Reynolds stress nu_t dU/dz and the shear rate |dU/dz|
/// (U the horizontal velocity), linear between the column's faces.
struct TurbulentShear {
  double stress_x = 0.0;    ///< [m^2/s^2] nu_t du/dz: the Reynolds stress -<u'w'> along x
  double stress_y = 0.0;    ///< [m^2/s^2] nu_t dv/dz
  double shear_rate = 0.0;  ///< [1/s] |dU/dz|
  /// [m/s] the local friction velocity sqrt(|tau_t| / rho)
  double friction_velocity() const;
};
TurbulentShear turbulent_shear_at(const ColumnGrid& grid, const MeanFlowColumn& column, const ColumnEnds& ends_x,
                                  const ColumnEnds& ends_y, double z);

/// The turbulence intensities of the open-channel log layer over the local friction velocity (Nezu & Nakagawa 1993,
/// "Turbulence in Open-Channel Flows", IAHR Monograph, Eq. 4.6 near the bed: u'/u* = 2.30, v'/u* = 1.63,
/// w'/u* = 1.27). With -<u'w'> = u*^2 they fix the correlation of u' and w' at -1 / (2.30 x 1.27) = -0.34.
struct TurbulenceIntensities {
  double streamwise = 2.30;
  double spanwise = 1.63;
  double vertical = 1.27;
};

/// [s] The Lagrangian integral time of the vertical velocity, T_L = 2 sigma_w^2 / (C0 eps) (Thomson 1987, J. Fluid
/// Mech. 180; Wilson & Sawford 1996, Boundary-Layer Meteorol. 78), with the local equilibrium dissipation eps =
/// u*^3 / l (l the mixing length, u* = l |dU/dz|): T_L = 2 c_w^2 / (C0 |dU/dz|); 0.33 z / u* in the log layer at
/// C0 = 4. Infinite (the state held) where the water is not sheared.
double lagrangian_time_scale(double shear_rate, double c0, const TurbulenceIntensities& intensities);

/// The Langevin state one step of dt later: each component an Ornstein-Uhlenbeck process of unit variance and time
/// scale `time_scale`, advanced exactly, eta' = a eta + sqrt(1 - a^2) xi with a = exp(-dt / T) and xi `normals`
/// (standard normal), so the statistics do not depend on dt.
Vec3 advance_langevin(const Vec3& state, double dt, double time_scale, const Vec3& normals);

/// [m/s] The velocity fluctuation of the Langevin state `state` (unit-variance components: along the shear, across
/// it, vertical) in the turbulence `shear`: w' = sigma_w eta_z; along the shear's direction s,
/// u'_s = sigma_u (rho eta_z + sqrt(1 - rho^2) eta_x) with rho = -1 / (c_u c_w), so that -<u'_s w'> = u*^2, the
/// Reynolds stress the closure carries; across it v' = sigma_v eta_y. sigma = c u*, u* the local friction velocity:
/// zero where the closure carries no stress (in a packed bed, in a laminar column).
Vec3 fluctuation_velocity(const Vec3& state, const TurbulentShear& shear, const TurbulenceIntensities& intensities);

}  // namespace riffle
