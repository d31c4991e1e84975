#pragma once
// Probes: CSV files written while the run goes, declared in the scene as [[output.probes]] (docs/SCENES.md).
//
//   kind = "grains"       chosen grains by id: position, velocity, angular velocity, the total contact force
//                         (Solids::contact_force), then the voidage, the undisturbed fluid velocity the drag used
//                         and each fluid force by source (drag, pressure gradient, added mass, history,
//                         lubrication): kGrainProbeColumns, 31 columns per grain, the first 12 as before;
//   kind = "wall_forces"  the reaction force on each wall, minus the sum of its grain-wall contact forces,
//                         3 columns per wall, named after it;
//   kind = "fluid_pressure", "wave_gauge", "surge_front", "fluid_totals"  the MPS fluid (need [fluid]): pressure
//                         at sensors fixed to the tank, surface height at gauges, the surge front, FluidSummary;
//   kind = "pressure_transducer"  the pressure averaged over discs on the tank's walls (0 in air), optionally
//                         averaged over a time window ending at each row (the only probe that reads between rows);
//   kind = "moving_fraction", "packing_density", "bedload_flux", "velocity_profile", "bed_shear_stress"  the
//                         bed-load measures of systems/physics/measures/bedload_probes.hpp (velocity_profile in long format:
//                         one line per time and layer).
//
// Each file starts with "time_s,step", then the probe's columns; one row on the first output of a fresh run
// (t = 0), then one per `interval` (IntervalSchedule). On resume, the rows after the checkpoint's time are dropped
// and the series continues (CsvSeries); a transducer's time window restarts at the resume (no probe keeps state in
// checkpoints), so the rows after it average only the steps since. Grains are named by their stable id; their
// slots change when grains are reordered, so the writer keeps an id -> slot map and rebuilds it when a slot no
// longer holds its id.
#include <array>
#include <cstddef>
#include <deque>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "components/model.hpp"
#include "systems/physics/measures/bedload_probes.hpp"
#include "engine/output/output_series.hpp"
#include "components/world.hpp"

namespace riffle {

/// The columns of a "grains" probe for each grain, after "grain<id>_". The first 12 are the original ones (tools
/// that read them by position still work); the contact force keeps its name fx_N.
inline constexpr std::array<const char*, 31> kGrainProbeColumns = {
    "x_m",           "y_m",           "z_m",           "vx_m_s",         "vy_m_s",         "vz_m_s",
    "wx_rad_s",      "wy_rad_s",      "wz_rad_s",      "fx_N",           "fy_N",           "fz_N",
    "voidage_1",     "ux_m_s",        "uy_m_s",        "uz_m_s",         "drag_fx_N",      "drag_fy_N",
    "drag_fz_N",     "pressure_fx_N", "pressure_fy_N", "pressure_fz_N",  "added_mass_fx_N", "added_mass_fy_N",
    "added_mass_fz_N", "history_fx_N", "history_fy_N", "history_fz_N",  "lubrication_fx_N", "lubrication_fy_N",
    "lubrication_fz_N"};

/// The slots of chosen grain ids, kept up to date across reorderings: refresh() checks each cached slot still
/// holds its id and rebuilds the whole map with one pass over the grains only when one does not.
class GrainSlotMap {
 public:
  explicit GrainSlotMap(std::vector<EntityId> ids);
  /// Returns true if the map had to be rebuilt. Ids no grain has get kNone.
  bool refresh(const Solids& solids);
  /// Slot of ids[k] (after refresh), or kNone.
  std::size_t slot(std::size_t k) const { return slots_[k]; }
  static constexpr std::size_t kNone = static_cast<std::size_t>(-1);

 private:
  std::vector<EntityId> ids_;
  std::vector<std::size_t> slots_;
};

/// [N] reaction force on each wall slot: minus the sum of the grain-wall contact forces on the grains (the force
/// each grain exerts on the wall), summed in slot order. Empty if the contact list is not built yet.
std::vector<Vec3> wall_reaction_forces(const Contacts& contacts, std::size_t wall_count);

/// What the fluid probes need from [fluid], [run] and [tank].
struct FluidProbeSettings {
  double spacing = 0.0;                   ///< [m] l0
  double effective_radius = 0.0;          ///< [m] r_e: support of a pressure sensor
  double density = 0.0;                   ///< [kg/m^3] rho
  Vec3 gravity = Vec3::Zero();            ///< [m/s^2] g
  double reference_number_density = 0.0; ///< [1] n0 of the initial lattice (lattice_constants(3, l0, r_e))
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

/// The header line of a probe's file (without the newline). Per-class columns follow the size classes of
/// world.solids, ascending.
std::string probe_header(const ProbeModel& probe, const World& world);

/// One probe's CSV file.
class ProbeWriter {
 public:
  /// Opens out_dir/probe.file; on a resume (fresh_run false) keeps the rows up to world.time.
  ProbeWriter(const Model& model, const ProbeModel& probe, const std::filesystem::path& out_dir, const World& world,
              bool fresh_run);
  /// Writes a row for the current state.
  void write(const World& world);
  /// Called after every step: a time-averaged transducer takes the step's reading; then writes a row if one is due
  /// after the step that ended at world.time.
  void write_if_due(const World& world) {
    if (window_) take_reading(world);
    if (schedule_.take(world.time)) write(world);
  }

 private:
  /// The transducers' readings now, one per disc; empty without fluid particles.
  std::vector<double> transducer_readings(const World& world) const;
  /// Adds the current readings to the time window (once per time).
  void take_reading(const World& world);

  /// The bed-load probes' part of a row (after time and step); the velocity profile's whole rows (several lines).
  std::string bedload_fields(const World& world);

  const Model* model_;
  ProbeModel probe_;
  GrainClasses classes_;      ///< bed-load probes: the size classes at the start (none come or go)
  RunningMean flux_mean_;     ///< bedload_flux: the running time mean of its rows
  ShearSettings shear_;       ///< bed_shear_stress
  std::size_t profile_layers_ = 0;  ///< velocity_profile: layers covering the tank height
  std::optional<WindowMean> window_;  ///< pressure_transducer with average_window > 0
  FluidProbeSettings fluid_;  ///< fluid probes only
  GrainSlotMap slots_;
  IntervalSchedule schedule_;
  CsvSeries file_;
};

}  // namespace riffle
