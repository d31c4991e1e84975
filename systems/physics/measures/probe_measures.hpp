#pragma once
// What the probes of engine/output/probes.hpp measure, as pure functions of the state (no I/O): the grains' force
// on each wall, the water's pressure at a sensor and over a transducer's disc, a time window's mean, the free
// surface's height at a gauge and the surge front. The tests set particles directly and check the answers.
#include <cstddef>
#include <deque>
#include <vector>

#include "components/contacts.hpp"
#include "components/fluid.hpp"
#include "components/model.hpp"
#include "components/tank_motion.hpp"
#include "components/vec.hpp"

namespace riffle {

/// [N] reaction force on each wall slot: minus the sum of the grain-wall contact forces on the grains (the force
/// each grain exerts on the wall), summed in slot order. Empty if the contact list is not built yet.
std::vector<Vec3> wall_reaction_forces(const Contacts& contacts, std::size_t wall_count);

/// What the fluid probes need from [fluid], [run] and [tank].
struct FluidProbeSettings {
  double spacing = 0.0;                   ///< [m] l0
  double effective_radius = 0.0;          ///< [m] r_e: support of a pressure sensor
  double density = 0.0;                   ///< [kg/m^3] rho
  Vec3 gravity = Vec3::Zero();            ///< [m/s^2] g
  double reference_number_density = 0.0; ///< [1] n0 of the initial lattice (MpsConstants)
  double floor_height = 0.0;              ///< [m] z of the tank's inner floor at rest
  bool allow_tension = false;             ///< !fluid.clamp_negative_pressure: a sensor may read p < 0
  /// [m] per axis: the period of a periodic tank axis ([tank] periodic), 0 otherwise. The sensors, gauges and
  /// densities take the nearest image of each particle along a periodic axis, so they read across the seam.
  Vec3 period = Vec3::Zero();
};
/// The settings of model.fluid (which must be enabled, with l0 > 0).
FluidProbeSettings fluid_probe_settings(const Model& model);

/// [Pa] Pressure at a sensor at `point` (tank frame): the Shepard average, with Wendland weights w(|x_s - x_j|),
/// over the fluid particles j within r_e of the sensor's lab position x_s = point + displacement of
/// p_j + rho (g - a_tank) . (x_s - x_j), i.e. each p_j carried hydrostatically to the sensor (numerics.md amendment
/// 1), so a sensor on a wall, l0/2 beyond the last fluid layer, reads the wall pressure. NaN if no fluid particle is
/// within r_e (a dry sensor). In air it reads 0 (sensor_pressure, systems/physics/measures/pressure_sensor.hpp): where the
/// wetted fraction of its support is below a quarter (spray only), and where the extrapolation is negative (the
/// sensor lies above the water it extrapolates from) unless the fluid may hold tension.
double fluid_pressure_at(const FluidParticles& particles, const FluidProbeSettings& settings, const TankMotion& tank,
                         const Vec3& point);

/// [Pa] What a pressure transducer reads: the pressure averaged over a disc of `diameter` centred on `point` (tank
/// frame, on a wall's inner face) normal to `normal`, i.e. the force on the disc over its area. The disc is
/// integrated with disc_quadrature (points about min(l0, diameter/2)/4 apart, at most 16 rings); each quadrature
/// point reads as fluid_pressure_at does, except that a point with no fluid within r_e contributes 0 (its area is
/// dry), so the transducer reads 0 in air, never NaN, and never less than 0 unless the fluid may hold tension.
/// Exact for a hydrostatic field: the disc's mean of a linear field is its value at the centre.
double pressure_transducer_reading(const FluidParticles& particles, const FluidProbeSettings& settings,
                                   const TankMotion& tank, const Vec3& point, const Vec3& normal, double diameter);

/// The time average of a probe's readings over a window of time ending at the latest: the signal holds each reading
/// (the state at the end of a step) over that step, (t_prev, t_k], and the mean is its integral over (t - window, t]
/// divided by the time of that interval it covers, i.e. the window, or less after a start or a resume. A step that
/// straddles the window's start counts with the part inside it, so the mean does not jump with rounding of times.
class WindowMean {
 public:
  explicit WindowMean(double window) : window_(window) {}
  /// Adds the readings at `time`, held since the previous reading (from `time` itself for the first); drops those
  /// wholly before time - window.
  void add(double time, std::vector<double> values);
  /// The mean of each column over the window; the latest values if the readings cover no time (a fresh run's
  /// t = 0); empty if nothing was added.
  std::vector<double> mean() const;
  /// Time of the latest reading (NaN if none).
  double latest_time() const;

 private:
  struct Reading {
    double start;  ///< [s] the previous reading's time
    double time;   ///< [s]
    std::vector<double> values;
  };
  double window_;
  std::deque<Reading> readings_;  ///< oldest first
};

/// [m] Height (tank-frame z) of the free surface above the gauge at `point` (x, y in the tank frame): the largest
/// z_j + l0/2 of the fluid particles within horizontal distance `radius` of the gauge that are not isolated
/// (n_j >= 0.5 n0, n_j computed at the current positions over fluid, wall and dummy particles: a drop of spray
/// above the surface must not make a spike). NaN if there is none.
double wave_gauge_height(const FluidParticles& particles, const FluidProbeSettings& settings, const TankMotion& tank,
                         const Vec3& point, double radius);

/// [m] Position of the surge front along the horizontal unit `direction`, in the tank frame: the largest
/// x_j . direction + l0/2 over the fluid particles less than `below` above the tank floor that have another fluid
/// particle within 1.5 l0 (lone drops ahead of the front do not count), minus the tank displacement along
/// `direction`. NaN if no particle qualifies.
double surge_front_position(const FluidParticles& particles, const FluidProbeSettings& settings,
                            const TankMotion& tank, const Vec3& direction, double below);

}  // namespace riffle
