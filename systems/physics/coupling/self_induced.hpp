#pragma once
// The grain's own disturbance of the water it samples (docs/COUPLING.md, "The undisturbed fluid velocity").
//
// The drag reaction -F is spread over the water with the grain's sampling kernel (the Wendland kernel on
// R = d/2 + r_e, normalised), the water answers it, and the grain samples the water with the same kernel. In the
// linearised (Stokes/Oseen) response of the water to a regularised force, the velocity the grain samples is
// u_self = -F <1/r> / (6 pi mu) phi(Re_R) psi(t) (Balachandar, Liu & Lakhote 2019, J. Comput. Phys. 376:
// regularised Stokeslet sampled by the same filter; Oseen reduction at finite Reynolds number; Evrard, Chandran,
// Cortez & van Wachem 2024 for its transient build-up), and the pressure gradient it samples gains the
// irrotational part of the force density, -F <rho_s rho_w> / 3 at the centre of an isotropic blob.
// Everything here is for riffle's kernel, evaluated once (in Fourier space, 1-D integrals over the kernel's
// transform), in the dimensionless forms below; the lengths scale with R.
#include <algorithm>
#include <array>

#include "components/vec.hpp"

namespace riffle {

/// R <1/|x - y|> for x and y drawn from two normalised Wendland kernels on radius R: the steady Stokes self-induced
/// velocity is F <1/r> / (6 pi mu) (the isotropic average of the Oseen tensor, 4/3 / (8 pi mu r)).
double self_induced_inverse_distance();

/// R^3 <rho_s rho_w> = R^3 int w^2 / (int w)^2 for the normalised Wendland kernel on R: the grain's sampled pressure
/// gradient gains -F <rho_s rho_w> / 3 from its own spread force (the irrotational third of an isotropic blob).
double self_induced_overlap();

/// phi(Re_R), Re_R = |slip| R / nu: the steady Oseen self-induced velocity along the slip over the Stokes one
/// (1 at Re_R = 0, about 3.5 / Re_R for Re_R >> 1). Interpolated in a table built on first use.
double self_induced_oseen_factor(double reynolds_r);

/// The share of a grain's own disturbance that the water it samples in a settling suspension holds beyond the
/// suspension's mean flow: the hard-sphere structure factor at zero wavenumber (Carnahan & Starling 1969's
/// compressibility), S(0) = (1 - phi)^4 / (1 + 4 phi + 4 phi^2 - 4 phi^3 + phi^4), 1 for a lone grain. The grains carry
/// fixed forces (their weights), so the water at a grain holds its own disturbance and its neighbours' less the
/// suspension's backflow; uniform neighbours cancel the backflow but for those the grain excludes (none within a
/// diameter: 8 phi of the own term to first order, Batchelor 1972), and their pair correlation beyond contact gives
/// part of that back. Over a kernel wider than the pair correlation the sum is S(0) of the own term. `solid_fraction`
/// is clamped to [0, 0.74].
double self_induced_suspension_share(double solid_fraction);

/// s(R / l_B): the steady self-induced velocity in a suspension over the one in clear water. The other grains resist
/// the water's motion (Brinkman 1947: mu lap u - (mu / l_B^2) u, l_B^2 the suspension's permeability), which
/// screens the Stokeslet beyond l_B: the Stokes symbol 1 / (mu k^2) becomes 1 / (mu (k^2 + l_B^-2)), so
/// s = int W^2 kappa^2 / (kappa^2 + (R / l_B)^2) d kappa / int W^2 d kappa (1 for a lone grain, falling as the
/// suspension thickens or the kernel widens). Interpolated in a table built with the Oseen one. This is the screening
/// by grains that resist the water (a fixed array); grains that settle carry fixed forces and do not screen it (the
/// correction in a settling suspension takes self_induced_suspension_share instead).
double self_induced_brinkman_factor(double kernel_over_screening);

/// The build-up of the Stokes disturbance after a force switched on at t = 0, psi(nu t / R^2), fitted by
/// 1 - sum_m a_m exp(-nu t / (T_m R^2)) (within 0.04 of the exact integral for every t). A force that varies feeds
/// one first-order lag per mode; the Oseen reduction shortens every T_m by phi (the early growth is Stokes').
struct SelfInducedModes {
  static constexpr int kCount = 3;
  static constexpr std::array<double, kCount> amplitude = {0.11338565, 0.60890101, 0.27771334};  ///< a_m, sum 1
  static constexpr std::array<double, kCount> time = {0.03, 0.2, 8.0};  ///< T_m [nu t / R^2]
};

/// psi(T), T = nu t / R^2, by quadrature of the kernel's transform (for the tests of the mode fit).
double self_induced_buildup(double time);

/// The same build-up with the water passing the spread force at Re_R = |u_undisturbed - v| R / nu (the linearised
/// Oseen response, unsteady): psi(T, Re_R), tending to phi(Re_R). Its rate has a closed angular integral,
/// d psi / dT = int W^2 kappa^2 exp(-kappa^2 T) 3 j(Re_R kappa T) d kappa / int W^2, j(b) = (sin b - b cos b) / b^3
/// (the Oseen symbol's decaying oscillation averaged over the directions, with the projector's weight 1 - c^2),
/// integrated in T by the trapezoidal rule on a fine logarithmic grid.
double self_induced_oseen_buildup(double time, double reynolds_r);

/// Each mode's time at Re_R, T_m / (1 + T_m Re_R) in nu t / R^2: convection ends the build-up of every mode within
/// about the time the water takes to pass the kernel.
double self_induced_mode_time(int mode, double reynolds_r);

/// The modes' amplitudes at Re_R: b_m >= 0 with sum phi(Re_R), so that sum_m b_m (1 - exp(-T / T_m(Re_R))) is the
/// least-squares fit of psi(T, Re_R) over T = 1e-3 to 100 (logarithmic points). At Re_R = 0 it is the Stokes fit
/// (SelfInducedModes' amplitudes, to the fit's rounding); at large Re_R the fast modes carry what is left: a
/// uniform phi on every mode, as the Stokes fit scaled, builds the screened disturbance too slowly (by up to a
/// tenth of it at Re_R = 10). Tabulated in log Re_R on first use, interpolated.
std::array<double, SelfInducedModes::kCount> self_induced_mode_amplitudes(double reynolds_r);

/// The modes' amplitudes with the water passing at two speeds: the fast and middle modes (the kernel's own scale,
/// where the Lagrangian water moves with the disturbance) at Re_near = |u_sampled - v| R / nu, the slow one (the far
/// field) at Re_R = |u_undisturbed - v| R / nu. The steady disturbance is the far field's Oseen one, phi(Re_R): the
/// slow mode carries what the near modes leave of it, max(0, phi(Re_R) - b_fast(Re_near) - b_middle(Re_near)).
/// Taking the slow mode's own fit at Re_R instead added up to more than either speed's phi (at Re_near 0.6, Re_R
/// 1.65: 0.88 against phi 0.77, above even the Stokes build-up from nu t / R^2 = 1), and a grain that fell for long
/// read the water moving up past it (docs/cases/settling.md, "After a long fall").
std::array<double, SelfInducedModes::kCount> self_induced_two_speed_amplitudes(double reynolds_near, double reynolds_r);

/// The build-up of a point Stokeslet's velocity at distance r after its force switched on at t = 0, averaged over
/// the directions along the force: erfc(1 / (2 sqrt(T))), T = nu t / r^2 (the transform of 1 - exp(-nu k^2 t) over
/// mu k^2 with the projector's weight 2/3, (2/pi) int sin q / q (1 - exp(-q^2 T)) dq). A wall's reflection of the
/// grain's disturbance reaches the grain from its image, 2h away, along this curve: half of it after T = 1.099.
double stokeslet_point_buildup(double time);

/// The lag time, in nu t / r^2, of the one first-order lag that a wall's reflection feeds: the point build-up's
/// half-rise time over ln 2 (1.5856), so that the lag is half built when the reflection is; the Oseen reduction
/// shortens it as the modes' times, T / (1 + T Re_r), Re_r = |u - v| r / nu.
inline constexpr double kStokesletHalfRiseTime = 1.0990;  ///< T with erfc(1 / (2 sqrt(T))) = 1/2
double self_induced_wall_time(double reynolds_r);

/// The steady self-induced velocity next to one no-slip plane over the free one, along the plane's normal and
/// along the plane, for a grain whose centre is `height_over_radius` = h / R from it. The kernel-spread force's
/// Stokeslet with Blake's (1971, Proc. Camb. Phil. Soc. 70) image system, sampled by the same kernel; both kernels
/// lose the part behind the plane (the grain reads and pushes only the water) and are renormalised. Far from the
/// plane it tends to the reflection of Lorentz (1907) and Faxen: 1 - (9/8 along the normal, 9/16 along the plane)
/// (4/3 <1/r> R)^-1 (R/h) (sphere mobilities 1 - 9a/8h, 1 - 9a/16h, a -> R<1/r>). Tabulated on first use by
/// quasi-random quadrature (Halton points) over the two kernels; beyond the table the reflection's 1/h tail.
struct SelfInducedWallFactors {
  double normal = 1.0;
  double tangential = 1.0;
};
SelfInducedWallFactors self_induced_wall_factors(double height_over_radius);

/// The same integral evaluated directly with `samples` Halton pairs (the table's entries; for the tests).
SelfInducedWallFactors self_induced_wall_quadrature(double height_over_radius, int samples);


/// The root of `residual` between `low` (residual <= 0) and `high` (>= 0) by safeguarded secant (Illinois) steps.
template <class Residual>
double illinois_root(double low, double high, Residual&& residual) {
  double f_low = residual(low);
  if (f_low >= 0.0) return low;
  double f_high = residual(high);
  int side = 0;
  for (int iteration = 0; iteration < 60; ++iteration) {
    const double x = (low * f_high - high * f_low) / (f_high - f_low);
    const double f = residual(x);
    if (f == 0.0 || (high - low) <= 1e-13 * high) return x;
    if (f < 0.0) {
      low = x;
      f_low = f;
      if (side == -1) f_high *= 0.5;  // Illinois: the end kept twice is halved
      side = -1;
    } else {
      high = x;
      f_high = f;
      if (side == 1) f_low *= 0.5;
      side = 1;
    }
  }
  return 0.5 * (low + high);
}

/// The drag and its self-induced velocity solved together along one grain's slip, for one sub-step.
/// Unknown w = u_sampled - u_self - v (the slip the drag sees); the modes' lags make
/// u_self = carried - gain(|w|) w, so w (1 - gain(|w|)) = u_sampled - v - carried: w lies along the right-hand
/// side and its length solves a scalar equation, bracketed and solved by safeguarded secant (Illinois) steps.
/// `gain(x)` is dimensionless, below 1 for every physical grain (d <1/r> / 2 < 1), and is clipped at 0.95.
/// Returns the slip length x.
template <class Gain>
double solve_self_induced_slip(double rhs_length, Gain&& gain) {
  if (!(rhs_length > 0.0)) return 0.0;
  // At x = rhs the residual is <= 0 (gain >= 0); at rhs / 0.05 it is >= 0 (the gain is clipped at 0.95).
  return illinois_root(rhs_length, rhs_length / 0.05,
                       [&](double x) { return x * (1.0 - std::min(gain(x), 0.95)) - rhs_length; });
}

/// The same with a gain per component (next to walls the disturbance differs along and across them):
/// w_i (1 - gain_i(|w|)) = rhs_i, each gain clipped at 0.95. Returns w. With equal gains it is the solve above.
template <class Gains>
Vec3 solve_self_induced_slip(const Vec3& rhs, Gains&& gains) {
  const double rhs_length = rhs.norm();
  if (!(rhs_length > 0.0)) return Vec3::Zero();
  const auto slip_at = [&](double x) {
    const Vec3 gain = gains(x);
    return Vec3(rhs.x() / (1.0 - std::min(gain.x(), 0.95)), rhs.y() / (1.0 - std::min(gain.y(), 0.95)),
                rhs.z() / (1.0 - std::min(gain.z(), 0.95)));
  };
  // |w(x)| lies between |rhs| and |rhs| / 0.05, so x - |w(x)| changes sign over that bracket.
  const double length = illinois_root(rhs_length, rhs_length / 0.05, [&](double x) { return x - slip_at(x).norm(); });
  return slip_at(length);
}

}  // namespace riffle
