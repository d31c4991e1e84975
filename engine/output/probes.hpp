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
#include <cmath>
#include <cstddef>
#include <deque>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "components/model.hpp"
#include "systems/physics/measures/bedload_probes.hpp"
#include "systems/physics/measures/bedload_transport.hpp"
#include "systems/physics/measures/probe_measures.hpp"
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

/// The header line of a probe's file (without the newline). Per-class columns follow the size classes of
/// world.solids, ascending.
std::string probe_header(const ProbeModel& probe, const World& world);

/// The means of a bedload_transport probe's rows over the run's second half (the run prints them at its end).
struct TransportMean {
  std::size_t rows = 0;
  double shields = 0.0, flux_star = 0.0, moving_fraction = 0.0;
  double moving_speed = 0.0;    ///< sum of u_p / u* over rows with moving grains
  double moving_height = 0.0;   ///< sum of h_p / d over rows with moving grains
  std::size_t moving_rows = 0;  ///< rows with moving grains
  double above_speed = 0.0;     ///< sum of u_p / u* of the moving grains above the bed, over rows with any
  std::size_t above_rows = 0;   ///< rows with moving grains above the bed
  void add(const BedloadTransport& row, double speed_over_u_star, double height_over_d, double above_over_u_star) {
    ++rows;
    if (row.moving_above_bed > 0 && std::isfinite(above_over_u_star)) {
      ++above_rows;
      above_speed += above_over_u_star;
    }
    shields += row.shields;
    flux_star += row.flux_star;
    moving_fraction += row.moving_fraction;
    if (row.moving > 0 && std::isfinite(speed_over_u_star)) {
      ++moving_rows;
      moving_speed += speed_over_u_star;
      moving_height += height_over_d;
    }
  }
};

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
  /// True if write_if_due would write a row after the step that ended at `time` (a run over ranks gathers the grains
  /// for it first).
  bool due(double time) const { return schedule_.due(time); }
  /// True if the probe reads every step (a time-averaged transducer), not only when a row is due.
  bool reads_every_step() const { return window_.has_value(); }
  /// A line for the run's end, or empty: a bedload_transport probe's means over the rows of the run's second half.
  std::string summary() const;
  /// The probe's file (CsvSeries::set_aside: where a resume copied an earlier file of other columns).
  const CsvSeries& series() const { return file_; }

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
  ShieldsGrain shields_grain_;  ///< bedload_transport: the grain of its dimensionless numbers
  TransportMean transport_mean_;  ///< bedload_transport: its rows' means over the run's second half
  std::size_t profile_layers_ = 0;  ///< velocity_profile: layers covering the tank height
  std::optional<WindowMean> window_;  ///< pressure_transducer with average_window > 0
  FluidProbeSettings fluid_;  ///< fluid probes only
  GrainSlotMap slots_;
  IntervalSchedule schedule_;
  CsvSeries file_;
};

}  // namespace riffle
