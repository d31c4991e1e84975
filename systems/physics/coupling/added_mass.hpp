#pragma once
// The added-mass and history (Basset) forces of the water on a grain (docs/COUPLING.md, "Added mass and history
// force"): pure functions, used by the grains' kicks (systems/dem/solid_integrate.cpp) and by
// solid_history_force (systems/coupling).
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

#include "components/model.hpp"
#include "components/vec.hpp"

namespace riffle {

/// [1] The added-mass coefficient of a sphere among others at voidage eps (Zuber 1964, Chem. Eng. Sci. 19, 897):
/// C_a = 1/2 (1 + 2 phi) / (1 - phi) with the solid fraction phi = 1 - eps; 1/2 for a lone sphere. eps is
/// clipped to (0, 1]: a voidage above 1 is a lone grain.
double added_mass_coefficient(double voidage);

/// [1] The added-mass coefficient the grains use: Zuber's, capped where the water could not take its reaction
/// stably. The reaction m_a (a_f dt - dv) goes to the water explicitly, one step later, and a_f is the water's own
/// acceleration: per volume of mixture the water (mass rho, or eps rho in the mixture reading, which hands it the
/// impulse over eps) takes back C_a phi rho times its own last acceleration. Where C_a phi (pore) or C_a phi / eps
/// (mixture) nears 1 that feedback grows from step to step (measured: the quick seed scene, phi = 0.6 in the bed,
/// blew up in 110 steps). The cap keeps it at half the receiving water's inertia: C_a <= 1/2 eps / phi (pore),
/// 1/2 eps^2 / phi (mixture). It binds above phi = 0.33 (pore) and 0.25 (mixture); a lone grain is never capped.
double stable_added_mass_coefficient(double voidage, CouplingModel::FluidVelocity reading);

/// One half kick of a grain with added mass m_a, done implicitly (docs/COUPLING.md): the grain obeys
///   (m + m_a) dv/dt = F + m g + m_a a_f,
/// so the added-mass force actually applied is m_a (a_f - dv/dt) = m_a (m a_f - F - m g) / (m + m_a), finite for
/// any m_a / m (an explicit force from the last acceleration is unstable for m_a > m).
struct AddedMassKick {
  Vec3 velocity_change;  ///< [m/s] dv over the half kick
  Vec3 force;            ///< [N] the added-mass force m_a (a_f - dv/dt) over it
};
inline AddedMassKick added_mass_kick(const Vec3& force, double mass, double added_mass, const Vec3& gravity,
                                     const Vec3& fluid_acceleration, double half_dt) {
  const Vec3 acceleration = (force + mass * gravity + added_mass * fluid_acceleration) / (mass + added_mass);
  return {half_dt * acceleration, added_mass * (fluid_acceleration - acceleration)};
}

/// The Basset kernel (t - tau)^(-1/2), windowed, as a sum of decaying exponentials
///   K(t) = sum_k weight_k exp(-rate_k t),
/// the trapezoidal rule in x = ln s of t^(-1/2) = pi^(-1/2) int exp(x/2 - e^x t) dx (the approach of the
/// exponential-sum kernels of Beylkin & Monzon 2005, Appl. Comput. Harmon. Anal. 19, 17, which van Hinsberg, ten
/// Thije Boonkkamp & Clercx 2011, J. Comput. Phys. 230, 1465 use for the history tail). Nodes from rate 1/window
/// up: beyond the window the kernel decays like exp(-t / window) instead of t^(-1/2) (a windowed kernel, as
/// Dorgan & Loth 2007, Int. J. Multiphase Flow 33, 833, argue for finite Reynolds numbers): the integral over the
/// nodes left out below 1/window, 2 (s_0 / pi)^(1/2), goes to the lowest mode, so for t << window the sum is still
/// t^(-1/2) and beyond the window it decays like exp(-t / window). The node spacing h spans 1/window to
/// 20/shortest with kCount nodes, at most 1.5 (the trapezoidal error is about 2 exp(-pi^2 / h), 1e-3 at h = 1.5).
struct BassetModes {
  static constexpr std::size_t kCount = 8;
  std::array<double, kCount> rate{};    ///< [1/s]
  std::array<double, kCount> weight{};  ///< [1/s^(1/2)]
  /// Modes for a window [s] and the shortest time the kernel must resolve [s] (the update interval): the rates
  /// run from 1/window up in steps of e (h = 1), at most kCount of them, the top one at least 1/shortest if the
  /// count allows.
  static BassetModes make(double window, double shortest);
};

/// The finite-Reynolds-number history kernel of Mei & Adrian (1992, J. Fluid Mech. 237, 323; in the form of Dorgan &
/// Loth 2007, Int. J. Multiphase Flow 33, 833, and Loth & Dorgan 2009, Environ. Fluid Mech. 9, 187):
///   K(t) = { (4 pi nu t / d^2)^(1/(2 c1)) + (pi |w|^3 t^2 / (d nu f_H^3))^(1/c1) }^(-c1),  f_H = 0.75 + c2 Re,
/// c1 = 2, c2 = 0.105 (Mei & Adrian's constants), Re = |w| d / nu. In the units of the Basset kernel t^(-1/2) it is
///   K(t) = t^(-1/2) (1 + (t / t_H)^(3 / (2 c1)))^(-c1),  t_H = (4 / pi)^(1/3) nu f_H^2 / |w|^2:
/// Basset's t^(-1/2) for t << t_H (the viscous diffusion from the surface, exact at any Re at short times) and
/// t^(-2) beyond (the wake convects the vorticity away: the memory a grain at Re ~ 1-100 keeps is finite). t_H does
/// not depend on d; at Re -> 0 it grows without bound and Basset's kernel returns. The slip's current magnitude
/// sets t_H, as Mei & Adrian's and Dorgan & Loth's time-domain use.
struct MeiAdrianKernel {
  static constexpr double kExponent = 2.0;           ///< c1
  static constexpr double kReynoldsSlope = 0.105;    ///< c2 in f_H = 0.75 + c2 Re
  /// [s] t_H for a slip speed [m/s] of a grain of diameter d [m] in water of kinematic viscosity nu [m^2/s];
  /// infinite for a grain at rest in the water.
  static double time_scale(double slip_speed, double diameter, double kinematic_viscosity);
  /// [1] K(t) t^(1/2): the factor on Basset's kernel at time t [s] for the time scale t_H [s].
  static double basset_factor(double t, double time_scale);
};

/// The Mei & Adrian kernel on the windowed Basset kernel's modes (BassetModes): the modes' states do not depend on
/// the kernel's weights, so each grain weights the same states by its own t_H, each step. The weights w_k c_k(t_H)
/// are fitted once, by least squares, to the windowed Basset kernel times MeiAdrianKernel::basset_factor at 160
/// times log-spaced from the shortest time to the window, the error measured against the Basset kernel there (so
/// that the t^(-2) tail, small, is not over-weighted), with a small pull of each c_k toward the factor at 1/rate_k
/// that keeps the fastest modes (barely seen at t >= shortest) near 1; tabulated every quarter e-fold of t_H from
/// shortest / 30 (no memory left) to 1000 windows (Basset's), read by linear interpolation in ln t_H. The kernel
/// so weighted stays within 3 % of Basset's magnitude of the target (tested).
class MeiAdrianModeWeights {
 public:
  MeiAdrianModeWeights() = default;
  explicit MeiAdrianModeWeights(const BassetModes& modes);
  /// The modes' weights [1/s^(1/2)] for the time scale t_H [s] (infinite: the windowed Basset kernel's).
  std::array<double, BassetModes::kCount> weights(double time_scale) const;

 private:
  BassetModes modes_;
  double first_log_ = 0.0;  ///< ln t_H of the table's first entry
  double log_step_ = 0.25;  ///< the table's spacing in ln t_H
  std::vector<std::array<double, BassetModes::kCount>> table_;  ///< w_k c_k per entry
};

/// The history force F_H = 3/2 d^2 sqrt(pi rho mu) int K(t - tau) dw/dtau dtau over the modes' states z_k:
/// F_H = 3/2 d^2 sqrt(pi rho mu) sum_k weight_k z_k, with z_k = int exp(-rate_k (t - tau)) dw/dtau dtau.
/// Advancing z_k over an interval dt in which the relative velocity w = u - v changed by dw at a constant rate is
/// exact: z_k <- exp(-rate_k dt) z_k + dw (1 - exp(-rate_k dt)) / (rate_k dt).
/// One mode's step: z <- decay z + gain dw, decay = exp(-rate dt), gain = (1 - decay) / (rate dt).
struct BassetModeStep {
  double decay;
  double gain;
};
inline BassetModeStep basset_mode_step(double rate, double dt) {
  const double x = rate * dt;
  const double decay = std::exp(-x);
  return {decay, x > 1e-8 ? (1.0 - decay) / x : 1.0 - 0.5 * x};
}
inline void advance_basset_mode(Vec3& state, double rate, double dt, const Vec3& relative_velocity_change) {
  const BassetModeStep step = basset_mode_step(rate, dt);
  state = step.decay * state + step.gain * relative_velocity_change;
}

/// [kg / s^(1/2)] 3/2 d^2 sqrt(pi rho mu), the history force's prefactor.
double basset_prefactor(double diameter, double density, double viscosity);

}  // namespace riffle
