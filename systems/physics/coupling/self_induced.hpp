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

/// The drag and its self-induced velocity solved together along one grain's slip, for one sub-step.
/// Unknown w = u_sampled - u_self - v (the slip the drag sees); the modes' lags make
/// u_self = carried - gain(|w|) w, so w (1 - gain(|w|)) = u_sampled - v - carried: w lies along the right-hand
/// side and its length solves a scalar equation, bracketed and solved by safeguarded secant (Illinois) steps.
/// `gain(x)` is dimensionless, below 1 for every physical grain (d <1/r> / 2 < 1), and is clipped at 0.95.
/// Returns the slip length x.
template <class Gain>
double solve_self_induced_slip(double rhs_length, Gain&& gain) {
  if (!(rhs_length > 0.0)) return 0.0;
  const auto residual = [&](double x) { return x * (1.0 - std::min(gain(x), 0.95)) - rhs_length; };
  double low = rhs_length, f_low = residual(low);  // <= 0: gain >= 0
  if (f_low >= 0.0) return low;
  double high = rhs_length / 0.05, f_high = residual(high);  // >= 0: the gain is clipped at 0.95
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

}  // namespace riffle
