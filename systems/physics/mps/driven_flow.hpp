#pragma once
// Driven flows and the sub-particle-scale eddy viscosity (docs/FLUID.md, "Driven flows" and "Turbulence"): the body
// force along x that stands for a mean pressure gradient (constant, sinusoidal, or held at a target bulk velocity by
// a PI controller), the moving lid's wrap, and the Smagorinsky viscosity of the SPS closure (Gotoh, Shibahara &
// Sakai 2001, Coastal Eng. J. 43; Shao & Gotoh 2005, Coastal Eng. J. 47). Pure functions: the systems call them and
// the unit tests call the same ones.
#include <Eigen/Core>

#include <cstddef>
#include <limits>
#include <vector>

#include "components/fluid.hpp"
#include "components/model.hpp"
#include "systems/physics/mps/mps_common.hpp"

namespace riffle {

/// f(t) [m/s^2] of a constant or sinusoidal body force: f, or F sin(2 pi t / T + phase); 0 for kNone. A bulk-velocity
/// controller's force is its state (BulkVelocityController), not a function of time: refused here.
double prescribed_body_force(const BodyForceModel& model, double time);

/// The PI controller of the bulk velocity: f = K_p e + K_i I, e = U - U_bulk, I = int_0^t e dt (the integral is
/// advanced by the rectangle rule with the error at the step start, so f of a step depends on the past only).
struct BulkVelocityController {
  double integral = 0.0;  ///< [m] I
  double force = 0.0;     ///< [m/s^2] the last f applied

  /// The force for a step of length dt that starts with bulk velocity `bulk`; advances I by e dt.
  double step(const BodyForceModel& model, double bulk, double dt);
};

/// Gains from the channel's time scales. Near the target the bulk velocity obeys the first-order plant
/// dU/dt = f - U / tau: the water's inertia (the 1) and the walls' viscous drag, tau the time on which it takes the
/// momentum out (a laminar channel of height H: the steady Poiseuille drag f = 12 nu U / H^2 gives tau = H^2 / (12 nu);
/// its slowest viscous mode decays on H^2 / (pi^2 nu), the same order; tau = infinity: the inertia alone, the
/// conservative choice when the drag is not known, e.g. turbulent). With f = K_p e + K_i int e the closed loop is
/// s^2 + (K_p + 1/tau) s + K_i = 0; asking for natural frequency omega = 1 / response_time and damping ratio zeta
/// gives K_i = omega^2, K_p = 2 zeta omega - 1/tau (not below 0). A step in the target is then followed with the
/// second-order response of (zeta, omega) and no steady error (the integral term).
struct PiGains {
  double proportional = 0.0;  ///< [1/s]
  double integral = 0.0;      ///< [1/s^2]
};
/// plant_time may be infinite (inertia alone).
PiGains pi_gains(double plant_time, double response_time, double damping_ratio);

/// x of a lid particle at time t: it moves at `velocity` from `rest_x` and wraps into [start, start + period).
double lid_particle_x(double rest_x, double start, double period, double velocity, double time);

/// |S| = sqrt(2 S_ij S_ij), S = (grad u + grad u^T) / 2, of a velocity gradient grad[a][b] = d u_a / d x_b.
double strain_rate_magnitude(const Eigen::Matrix3d& velocity_gradient);

/// The Smagorinsky eddy viscosity nu_t = (C_s Delta)^2 |S| [m^2/s] (Gotoh et al. 2001, Eq. 13; Delta = l0).
double smagorinsky_viscosity(double constant, double filter_width, const Eigen::Matrix3d& velocity_gradient);

/// The particle-scale viscosity nu_p = C_p l0 s [m^2/s] of a particle whose velocity scatters by s [m/s] about the
/// linear fit through its neighbours (docs/FLUID.md, "Disordered water's particle-scale noise").
inline double scatter_viscosity(double constant, double spacing, double scatter) { return constant * spacing * scatter; }

/// The two particle eddy viscosities fluid_predict adds to nu in its pair form, each 0 when its constant is.
struct EddyViscosityConstants {
  double smagorinsky = 0.0;  ///< C_s of the SPS closure ([fluid] turbulence = "sps")
  double scatter = 0.0;      ///< C_p of the particle-scale viscosity ([fluid] scatter_viscosity)
  /// [m^2/s] the particle-scale viscosity's ceiling (the explicit viscous term's stability: fluid_predict gives
  /// 0.1 l0^2 / dt), so that a violent splash's scatter cannot make the step unstable
  double scatter_ceiling = std::numeric_limits<double>::infinity();
};

/// nu_t of fluid slots [0, fluid_count) into `out` (sized fluid_count), from the particles' current positions and
/// velocities (wall and lid particles enter with theirs) and the GC-corrected velocity gradient
/// grad u_a = A^-1 (1/n0) sum_j (u_a,j - u_a,i) (w_ij / r_ij^2) r_ij (seed 000 Eqs. 8-9 with the inversion safety of
/// numerics 2.6), exact for a linear field wherever A is well conditioned (whatever the scene's GC switch says: the
/// closures need the gradient, not the pressure scheme): the Smagorinsky viscosity with Delta = l0 plus the
/// particle-scale viscosity of the scatter s_i = |sum_j w_ij (u_j - u_i - grad u r_ij)| / sum_j w_ij, the particle's
/// distance from the linear field its neighbours and its gradient describe (0 for any linear field, O(l0^2 lap u)
/// for a resolved curved one). `neighbours`: lists at least r_e wide.
void particle_eddy_viscosity(const ParticleState& particles, const FluidNeighbours& neighbours, std::size_t fluid_count,
                             const MpsConstants& constants, const EddyViscosityConstants& closures,
                             std::vector<double>& out);

}  // namespace riffle
