#pragma once
// Probes: CSV files written while the run goes, declared in the scene as [[output.probes]] (docs/SCENES.md).
//
//   kind = "grains"       chosen grains by id: position, velocity, angular velocity and the total contact force
//                         (Solids::contact_force), 12 columns per grain;
//   kind = "wall_forces"  the reaction force on each wall, minus the sum of its grain-wall contact forces,
//                         3 columns per wall, named after it.
//
// Each file starts with "time_s,step", then the probe's columns; one row on the first output of a fresh run
// (t = 0), then one per `interval` (IntervalSchedule). On resume, the rows after the checkpoint's time are dropped
// and the series continues (CsvSeries). Grains are named by their stable id; their slots change when grains are
// reordered, so the writer keeps an id -> slot map and rebuilds it when a slot no longer holds its id.
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/model.hpp"
#include "engine/output_series.hpp"
#include "engine/scene_reader.hpp"
#include "engine/world.hpp"

namespace riffle {

/// Output files the run writes itself: a probe's `file` may not be one of them.
const std::vector<std::string>& reserved_output_files();

/// Reads every [[output.probes]] table of the [output] reader into model.output.probes. The grains and the
/// contact model must be read already (ids are checked against the grains the run starts with: those of
/// [solids] initial_state, then model.solids.spheres; wall forces need [contact]).
/// Problems go through the reader (file:line:column: key: message).
void read_probes(TableReader& output, Model& model);

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

/// The header line of a probe's file (without the newline).
std::string probe_header(const ProbeModel& probe, const World& world);

/// One probe's CSV file.
class ProbeWriter {
 public:
  /// Opens out_dir/probe.file; on a resume (fresh_run false) keeps the rows up to world.time.
  ProbeWriter(const ProbeModel& probe, const std::filesystem::path& out_dir, const World& world, double dt,
              bool fresh_run);
  /// Writes a row for the current state.
  void write(const World& world);
  /// Writes a row if one is due after the step that ended at world.time.
  void write_if_due(const World& world) {
    if (schedule_.take(world.time)) write(world);
  }

 private:
  ProbeModel probe_;
  GrainSlotMap slots_;
  IntervalSchedule schedule_;
  CsvSeries file_;
};

}  // namespace riffle
