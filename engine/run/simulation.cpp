#include "engine/run/simulation.hpp"

#include <fcntl.h>
#include <spdlog/sinks/basic_file_sink.h>
#include <unistd.h>
#include <spdlog/spdlog.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <fstream>
#include <new>
#include <sstream>

#include "engine/output/bed_profile_writer.hpp"
#include "engine/output/checkpoint_validation.hpp"
#include "engine/setup/initial_state.hpp"
#include "engine/output/output_lock.hpp"
#include "engine/output/output_series.hpp"
#include "engine/output/probes.hpp"
#include "engine/output/replace_file.hpp"
#include "engine/scene/scene.hpp"
#include "engine/output/vtk_output.hpp"
#include "systems/dem/solid_neighbours.hpp"
#include "systems/physics/geometry/domain.hpp"
#include "systems/physics/geometry/periodic_box.hpp"
#include "systems/physics/mps/hypre_pressure_solver.hpp"
#include "systems/physics/ranks/fluid_ranks.hpp"
#include "systems/physics/ranks/grain_ranks.hpp"
#include "systems/physics/ranks/rank_comm.hpp"
#include "systems/physics/time/time_step.hpp"

namespace riffle {

namespace fs = std::filesystem;

namespace {

std::atomic<int> g_stop_signal{0};
/// [s] How long a step may go on after a stop request before it is abandoned (without a checkpoint of it).
constexpr double kStopGraceSeconds = 2.0;
static_assert(std::atomic<int>::is_always_lock_free, "the stop flag must be usable from a signal handler");

/// What rank 0 of a run over MPI ranks writes when a signal comes from outside. When one rank dies, mpirun ends the
/// others with SIGTERM; they may be waiting for the dead one in an exchange and never reach the step's end, where a
/// stop request is shared, so the handler itself names the last checkpoint written whole, on stderr (which mpirun
/// passes on) and at the end of riffle.log. The text is made ready at each checkpoint in the buffer the handler is
/// not reading, and the handler only reads the other and calls write(2): async-signal-safe.
struct SignalNote {
  static constexpr std::size_t kSize = 1536;
  char text[2][kSize] = {};
  std::size_t length[2] = {0, 0};
  std::atomic<int> ready{-1};       ///< the buffer the handler writes, -1: none (not a run over ranks)
  std::atomic<int> log_file{-1};    ///< riffle.log opened for appending, -1: none
};
SignalNote g_signal_note;
static_assert(std::atomic<int>::is_always_lock_free, "the note's index must be usable from a signal handler");

/// Makes ready the text a signal writes: the last checkpoint written whole (`path`, empty if none yet).
void prepare_signal_note(const std::string& path, double time, std::uint64_t step) {
  const int next = g_signal_note.ready.load() == 0 ? 1 : 0;
  const int written =
      path.empty()
          ? std::snprintf(g_signal_note.text[next], SignalNote::kSize,
                          "riffle: rank 0 of %d ranks received a signal to stop; no checkpoint has been written yet "
                          "by this run\n",
                          ranks::size())
          : std::snprintf(g_signal_note.text[next], SignalNote::kSize,
                          "riffle: rank 0 of %d ranks received a signal to stop; the last checkpoint written whole is "
                          "%s (t = %.9g s, step %llu): resume from it unless the run ends with its own final "
                          "checkpoint (a rank that has died stops them all before that)\n",
                          ranks::size(), path.c_str(), time, static_cast<unsigned long long>(step));
  g_signal_note.length[next] =
      written < 0 ? 0 : std::min(static_cast<std::size_t>(written), SignalNote::kSize - 1);
  g_signal_note.ready.store(next);
}

/// From the signal handler (request_stop): the prepared note, if any, to stderr and riffle.log.
void write_signal_note() {
  const int index = g_signal_note.ready.load();
  if (index < 0) return;
  const char* text = g_signal_note.text[index];
  const std::size_t length = g_signal_note.length[index];
  [[maybe_unused]] ssize_t ignored = ::write(STDERR_FILENO, text, length);
  if (const int log = g_signal_note.log_file.load(); log >= 0) ignored = ::write(log, text, length);
}

std::string format_vec(const Vec3& v) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.6g, %.6g, %.6g)", v[0], v[1], v[2]);
  return text;
}

/// Nine significant digits: a time in a message must name the step exactly.
std::string format_time(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", value);
  return text;
}

std::string format_duration(double seconds) {
  const auto total = static_cast<long long>(seconds + 0.5);
  char text[32];
  std::snprintf(text, sizeof text, "%lld:%02lld:%02lld", total / 3600, (total / 60) % 60, total % 60);
  return text;
}

/// [kg] The fluid removed as escaped so far: every MPS fluid particle has the mass rho l0^3.
double removed_mass(const FluidSummary& fluid, const Model& model) {
  const double l0 = model.fluid.spacing;
  return static_cast<double>(fluid.removed_count()) * model.fluid.density * l0 * l0 * l0;
}

/// One warning per fluid particle fluid_escape removed in the last step, `escaped` (at most kMaxLines a step, then a
/// count), and the removals so far.
void log_escaped(const std::vector<EscapedParticle>& escaped, const World& world, const Model& model) {
  if (!world.fluid_summary || escaped.empty()) return;
  constexpr std::size_t kMaxLines = 20;
  const FluidSummary& fluid = *world.fluid_summary;
  for (std::size_t k = 0; k < escaped.size() && k < kMaxLines; ++k) {
    const EscapedParticle& particle = escaped[k];
    spdlog::warn("step {} (t = {} s): fluid particle id {} removed: {} at position {} m with velocity {} m/s",
                 world.step, format_time(world.time), particle.id,
                 particle.left_domain ? "it left the domain"
                                      : "a lone droplet more than fluid.escape_distance = " +
                                            format_time(model.fluid.escape_distance) + " m outside the tank",
                 format_vec(particle.position), format_vec(particle.velocity));
  }
  if (escaped.size() > kMaxLines)
    spdlog::warn("step {}: {} more fluid particles removed as escaped", world.step, escaped.size() - kMaxLines);
  spdlog::info("removed as escaped so far: {} of {} fluid particles ({} kg; {} left the domain, {} lone droplets)",
               fluid.removed_count(), fluid.initial_fluid_count, removed_mass(fluid, model), fluid.removed_left_domain,
               fluid.removed_lone_droplet);
}

/// A warning when the step's pressure solve stopped short of its tolerance (at solver_max_iterations, or a
/// broken-down iteration): the step went on with that pressure, so the user must know. The 1st, 2nd, 4th, 8th, ...
/// such step of the run is reported, with the count so far, so that a run that never converges does not flood
/// the log. `unconverged` counts them over the run.
void log_unconverged_pressure(const World& world, const Model& model, std::uint64_t& unconverged) {
  if (!world.fluid_summary || world.fluid_summary->solver_converged) return;
  ++unconverged;
  if ((unconverged & (unconverged - 1)) != 0) return;  // not a power of two
  const FluidSummary& fluid = *world.fluid_summary;
  spdlog::warn("step {} (t = {} s): the pressure solve stopped at |r|/|b| = {:.3g} after {} iterations, short of "
               "fluid.solver_tolerance = {:.3g} (fluid.solver_max_iterations = {}); {} such step(s) so far",
               world.step, format_time(world.time), fluid.solver_residual, fluid.solver_iterations,
               model.fluid.solver_tolerance, model.fluid.solver_max_iterations, unconverged);
}

/// "; N fluid particles removed as escaped (M kg, P % of the water)", or "" when none was.
std::string removed_summary(const World& world, const Model& model) {
  if (!world.fluid_summary || world.fluid_summary->removed_count() == 0) return "";
  const FluidSummary& fluid = *world.fluid_summary;
  char text[240];
  std::snprintf(text, sizeof text,
                "; %zu fluid particles removed as escaped (%.6g kg, %.3g %% of the water; %zu left the domain, %zu "
                "lone droplets)",
                fluid.removed_count(), removed_mass(fluid, model),
                100.0 * static_cast<double>(fluid.removed_count()) / static_cast<double>(fluid.initial_fluid_count),
                fluid.removed_left_domain, fluid.removed_lone_droplet);
  return text;
}

/// Frames, series and tables are replaced whole (unique temporary file, rename): a kill never leaves half a file.
void write_text_file(const fs::path& path, const std::string& text) { replace_file(path, text, Durability::kFlush); }

/// diagnostics.csv: one row per `diagnostics_every` steps, flushed as written so a crash loses nothing.
class DiagnosticsWriter {
 public:
  DiagnosticsWriter(const fs::path& path, const World& world, const std::vector<SystemTimer>& timers,
                    bool fresh_run, bool driving)
      : driving_(driving),
        file_(path, header(timers, world.fluid_summary.has_value(), driving),
              // On resume, keep the rows up to the checkpoint's step and continue after them.
              fresh_run ? std::nullopt : std::optional<double>(static_cast<double>(world.step))) {
    for (const SystemTimer& timer : timers) previous_totals_.push_back(timer.total_seconds);
  }

  void row(const World& world, const Model& model, double min_radius, double step_wall_seconds,
           const std::vector<SystemTimer>& timers) {
    char text[512];
    const SolidSummary summary = world.solid_summary.value_or(SolidSummary{});
    // The lengths the step actually used (decide_step_lengths): a Courant-limited step has shorter sub-steps.
    const StepLengths& lengths = world.last_step;
    const double cfl = min_radius > 0.0 ? summary.max_speed * lengths.substep / min_radius : 0.0;
    const Vec3 direction = model.tank.motion.direction;
    std::snprintf(text, sizeof text, "%llu,%.17g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.6g,%.9g,%.9g,%.6g",
                  static_cast<unsigned long long>(world.step), world.time, lengths.dt, lengths.substep,
                  summary.translational_energy, summary.rotational_energy, summary.potential_energy,
                  summary.max_speed, cfl, world.tank_motion->displacement.dot(direction),
                  world.tank_motion->velocity.dot(direction), step_wall_seconds);
    std::string line = text;
    // The grains' neighbour list rebuilds so far (solid_neighbours): what the list's cost in the timings comes from.
    std::snprintf(text, sizeof text, ",%llu",
                  static_cast<unsigned long long>(world.contacts ? world.contacts->rebuilds : 0));
    line += text;
    if (world.fluid_summary) {
      const FluidSummary& fluid = *world.fluid_summary;
      std::snprintf(text, sizeof text, ",%zu,%zu,%.9g,%.9g,%.6g,%.9g,%.9g,%lld,%.3g,%zu", fluid.fluid_count,
                    fluid.surface_count, fluid.kinetic_energy, fluid.max_speed, fluid.courant, fluid.mean_density_ratio,
                    fluid.volume, static_cast<long long>(fluid.solver_iterations), fluid.solver_residual,
                    fluid.solver_unknowns);
      line += text;
      // Escaped particles removed so far (fluid_escape): water + removed = the fluid laid out, exactly; then by
      // reason (left the domain, lone droplets: their sum is the removed count, less any removals before a resume
      // from a format-11 or older checkpoint).
      std::snprintf(text, sizeof text, ",%zu,%.9g,%zu,%zu", fluid.removed_count(), removed_mass(fluid, model),
                    fluid.removed_left_domain, fluid.removed_lone_droplet);
      line += text;
      // How close the grains' drag brings the step to its limit (coupling.drag_number / rate; time_step.hpp).
      std::snprintf(text, sizeof text, ",%.6g", lengths.drag_rate);
      line += text;
      // A scene with a body force (docs/FLUID.md, "Driven flows"): the force applied in the step.
      if (driving_) {
        std::snprintf(text, sizeof text, ",%.9g", fluid.body_force);
        line += text;
      }
    }
    for (std::size_t k = 0; k < timers.size(); ++k) {
      std::snprintf(text, sizeof text, ",%.6g", timers[k].total_seconds - previous_totals_[k]);
      line += text;
      previous_totals_[k] = timers[k].total_seconds;
    }
    file_.write_row(line);
  }

  /// The file (CsvSeries::set_aside: where a resume copied an earlier file of other columns).
  const CsvSeries& series() const { return file_; }

 private:
  static std::string header(const std::vector<SystemTimer>& timers, bool fluid, bool driving) {
    std::string text = "step,time_s,dt_s,solid_dt_s,solid_translational_energy_J,solid_rotational_energy_J,"
                       "solid_potential_energy_J,solid_max_speed_m_s,solid_cfl,tank_displacement_m,"
                       "tank_velocity_m_s,step_wall_s,solid_neighbour_rebuilds";
    if (fluid)
      text += ",fluid_particles,fluid_surface_particles,fluid_kinetic_energy_J,fluid_max_speed_m_s,fluid_courant,"
              "fluid_mean_density_ratio,fluid_volume_m3,ppe_iterations,ppe_relative_residual,ppe_unknowns,"
              "fluid_removed_particles,fluid_removed_mass_kg,fluid_removed_left_domain,fluid_removed_lone_droplets,"
              "drag_rate_1_s";
    if (fluid && driving) text += ",body_force_m_s2";
    for (const SystemTimer& timer : timers) text += ",wall_" + timer.name + "_s";
    return text;
  }

  bool driving_;  ///< the scene has a body force: its column is written
  CsvSeries file_;
  std::vector<double> previous_totals_;
};


/// A resumed run continues each series file whose columns it writes; one with other columns (a resume on another
/// number of ranks, with another probe or system, or by another riffle version) goes on under the new columns and
/// is also kept whole beside them by CsvSeries. Says so, and where.
void report_set_aside_series(const DiagnosticsWriter& diagnostics, const std::vector<ProbeWriter>& probes,
                             const std::optional<BedProfileWriter>& bed_profile, double time) {
  std::vector<const CsvSeries*> series{&diagnostics.series()};
  for (const ProbeWriter& probe : probes) series.push_back(&probe.series());
  if (bed_profile)
    for (const CsvSeries* file : bed_profile->series()) series.push_back(file);
  for (const CsvSeries* file : series) {
    if (!file->set_aside()) continue;
    if (file->rows_carried())
      spdlog::warn("{} had other columns than this run writes: its rows up to the resume (t = {} s) go on under "
                   "this run's columns (one it no longer writes left out, a new one empty before the resume); the "
                   "file as it was is kept in {}",
                   file->path().string(), time, file->set_aside()->string());
    else
      spdlog::warn("{} had other columns than this run writes, and another first column: it starts again at the "
                   "resume (t = {} s); the file as it was is kept in {}",
                   file->path().string(), time, file->set_aside()->string());
  }
}

std::string checkpoint_name(std::uint64_t step) {
  char name[64];
  std::snprintf(name, sizeof name, "step_%010llu.ckpt", static_cast<unsigned long long>(step));
  return name;
}

/// Writes checkpoints into OUT/checkpoints and keeps the newest `keep` interval ones (the list of kept steps lives
/// in OutputState, so it survives a resume).
class CheckpointStore {
 public:
  CheckpointStore(fs::path directory, OutputState& output, std::int64_t keep)
      : directory_(std::move(directory)), output_(output), keep_(static_cast<std::size_t>(keep)) {}

  /// `interval` checkpoints count towards the schedule and the retention; the others (signal, end) do not.
  void save(const Simulation& simulation, bool interval) {
    save(simulation.checkpoint_step(), interval, [&] { return simulation.checkpoint_data(); });
  }
  /// The same with the data from `data()`, asked for after the bookkeeping (which is part of it).
  template <class Data>
  void save(std::uint64_t step, bool interval, Data&& data) {
    std::vector<std::uint64_t> expired;
    if (interval) {
      ++output_.checkpoints_due;
      output_.kept_steps.push_back(step);
      while (output_.kept_steps.size() > keep_) {
        expired.push_back(output_.kept_steps.front());
        output_.kept_steps.erase(output_.kept_steps.begin());
      }
    }
    const fs::path path = directory_ / checkpoint_name(step);
    write_checkpoint(path.string(), data());  // after the bookkeeping: it is part of the state
    last_written_ = path.string();
    for (std::uint64_t old_step : expired) {
      std::error_code ignored;
      if (old_step != step) fs::remove(directory_ / checkpoint_name(old_step), ignored);
    }
    spdlog::debug("checkpoint written: {}", last_written_);
  }

  /// A stable name for the end state, so other scenes can start from it ([solids] initial_state). Copied by way of
  /// a temporary file and a rename: a kill during the copy leaves the previous final.ckpt whole.
  void copy_as_final() const {
    std::ifstream file(last_written_, std::ios::binary);
    std::ostringstream bytes;
    bytes << file.rdbuf();
    if (!file || file.bad()) throw CheckpointError(last_written_ + ": cannot read it back to copy it to final.ckpt");
    try {
      replace_file(directory_ / "final.ckpt", bytes.str(), Durability::kSync);
    } catch (const std::runtime_error& error) {
      throw CheckpointError(error.what());
    }
  }

  const std::string& last_written() const { return last_written_; }
  /// The newest checkpoint on disk: written by this process, or kept from before a resume; empty if none.
  std::string last_good() const {
    if (!last_written_.empty() || output_.kept_steps.empty()) return last_written_;
    return (directory_ / checkpoint_name(output_.kept_steps.back())).string();
  }

 private:
  fs::path directory_;
  OutputState& output_;
  std::size_t keep_;
  std::string last_written_;
};

/// The file of frame k of a phase, "vtk/solids_000004.vtp" for `suffix` ".vtp".
std::string frame_name(const char* phase, std::size_t k, const char* suffix) {
  char name[64];
  std::snprintf(name, sizeof name, "vtk/%s_%06zu%s", phase, k, suffix);
  return name;
}

/// The files a .pvd series lists, in order (empty if there is none).
std::vector<std::string> listed_frames(const fs::path& pvd) {
  std::vector<std::string> files;
  std::ifstream in(pvd);
  std::string line;
  const std::string key = "file=\"";
  while (std::getline(in, line)) {
    const std::size_t at = line.find(key);
    if (at == std::string::npos) continue;
    const std::size_t begin = at + key.size(), end = line.find('"', begin);
    if (end != std::string::npos) files.push_back(line.substr(begin, end - begin));
  }
  return files;
}

/// Which file each VTK frame of an output folder is in, for the .pvd series: the grains' and the water's frame k in
/// pieces (a .pvtp naming one .vtp per rank, written over ranks) or whole (one .vtp); the walls always whole. Known
/// for the frames this run wrote; those of an earlier run (before a resume, maybe on another rank count) are looked
/// up on disk once each. A run resumed into another folder than its checkpoint's (`earlier`) lists the frames before
/// the checkpoint where they are, by a path relative to its own folder, so that its series shows the whole run; a
/// frame a series already listed elsewhere (a folder branched from another, resumed again) keeps that file.
class FrameFiles {
 public:
  explicit FrameFiles(fs::path out, fs::path earlier = {}) : out_(std::move(out)), earlier_(std::move(earlier)) {
    std::error_code error;
    if (!earlier_.empty() && (!fs::is_directory(earlier_, error) || fs::equivalent(earlier_, out_, error)))
      earlier_.clear();
    for (const char* phase : {"solids", "fluid", "walls"}) {
      std::vector<std::string>& listed = listed_[phase];
      listed = listed_frames(out_ / (std::string(phase) + ".pvd"));
      if (earlier_.empty()) continue;
      // The earlier folder's series, as paths from this folder: where this folder's own series says nothing.
      const std::vector<std::string> before = listed_frames(earlier_ / (std::string(phase) + ".pvd"));
      for (std::size_t k = 0; k < before.size(); ++k) {
        const fs::path relative = fs::relative(earlier_ / before[k], out_, error);
        if (error || relative.empty()) continue;
        if (listed.size() <= k) listed.resize(k + 1);
        if (listed[k].empty() || !fs::exists(out_ / listed[k], error)) listed[k] = relative.generic_string();
      }
    }
  }

  void written(std::size_t k, bool pieces) {
    in_pieces(k);
    pieces_[k] = pieces;
    if (written_.size() <= k) written_.resize(k + 1, false);
    written_[k] = true;
  }

  /// Relative to the output folder, as the .pvd lists it.
  std::string name(const char* phase, std::size_t k) {
    const bool pieces = std::strcmp(phase, "walls") != 0 && in_pieces(k);
    const std::string name = frame_name(phase, k, pieces ? ".pvtp" : ".vtp");
    if (k < written_.size() && written_[k]) return name;
    // A frame of an earlier run: looked up on disk once (the series is rewritten at every frame).
    std::vector<std::string>& found = found_[phase];
    if (k < found.size() && !found[k].empty()) return found[k];
    if (found.size() <= k) found.resize(k + 1);
    found[k] = name;
    std::error_code error;
    if (!fs::exists(out_ / name, error)) {
      // Not in this folder: the file a series listed for it (this folder's, or the earlier folder's), if it is there.
      const std::vector<std::string>& listed = listed_[phase];
      if (k < listed.size() && !listed[k].empty() && fs::exists(out_ / listed[k], error)) found[k] = listed[k];
    }
    return found[k];
  }

  /// Rewrites a phase's .pvd series listing every frame so far.
  void write_series(const char* phase, const std::vector<double>& frame_times) {
    std::vector<std::string> files;
    for (std::size_t k = 0; k < frame_times.size(); ++k) files.push_back(name(phase, k));
    write_text_file(out_ / (std::string(phase) + ".pvd"), pvd_collection(frame_times, files));
  }

 private:
  bool in_pieces(std::size_t k) {
    while (pieces_.size() <= k) {
      const std::size_t j = pieces_.size();
      pieces_.push_back(fs::exists(out_ / frame_name("solids", j, ".pvtp")) ||
                        fs::exists(out_ / frame_name("fluid", j, ".pvtp")));
    }
    return pieces_[k];
  }

  fs::path out_;
  fs::path earlier_;  ///< the checkpoint's run folder, when this run resumed into another; else empty
  std::vector<bool> pieces_;
  std::vector<bool> written_;  ///< the frames this run wrote (always in out_)
  std::map<std::string, std::vector<std::string>> listed_;  ///< per phase, the files the existing series list
  std::map<std::string, std::vector<std::string>> found_;   ///< per phase, the earlier frames' files once looked up
};

/// The grains where a run failed: the scene's encoding, in double precision (a diagnosis may turn on overlaps of
/// 1e-9 m).
VtkFormat failure_frame_format(const Model& model) {
  VtkFormat format = vtk_format(model.output);
  format.single_precision = false;
  return format;
}

/// Appends a VTK frame of every phase, one .vtp each, and rewrites the .pvd series that list all frames so far. A
/// .pvtp of the same frame left by an earlier run over ranks is removed, so that the series names this frame.
void write_vtk_frame(const fs::path& out, const World& world, const Model& model, OutputState& output,
                     FrameFiles& files) {
  const std::size_t index = output.frame_times.size();
  output.frame_times.push_back(world.time);
  files.written(index, false);
  const auto write = [&](const char* phase, const std::string& text) {
    fs::remove(out / frame_name(phase, index, ".pvtp"));
    write_text_file(out / frame_name(phase, index, ".vtp"), text);
    files.write_series(phase, output.frame_times);
  };
  const VtkFormat format = vtk_format(model.output);
  if (world.solids) write("solids", solids_vtp(*world.solids, periodic_box(model), format));
  if (world.walls) write("walls", walls_vtp(*world.walls, format));
  if (world.fluid) write("fluid", fluid_vtp(*world.fluid, format));
}

}  // namespace

/// The one-line diagnosis of a failed step.
std::string diagnosis(const World& world, const Model& model) {
  const StepStatus& status = world.step_status;
  // The box the failing check used: the grains' is open by a period either side along periodic axes.
  const DomainBox domain = status.phase == "solids" ? grain_domain_box(model) : domain_box(model);
  const std::string when = "run stopped at step " + std::to_string(world.step) + " (t = " + std::to_string(world.time) + " s): ";
  if (status.problem == StepProblem::kTimeStepCollapse) {
    // The limit that set the step names the cause: the grains' drag, or the flow itself.
    const std::string collapse = when + "the step's " + step_limit_name(world.last_step.limit) + " limit gave dt = " +
                                 std::to_string(world.last_step.dt) + " s, below fluid.min_dt = " +
                                 std::to_string(model.fluid.min_dt) + " s: ";
    if (world.last_step.limit == StepLimit::kDrag)
      return collapse + "the grains' drag relaxes the water around them at " +
             std::to_string(world.last_step.drag_rate) +
             " 1/s (coupling.drag_number / rate; docs/COUPLING.md, \"The drag's step limit\"): a bed packed "
             "beyond its voidage floor, or grains far faster than the water; fastest fluid particle id " +
             std::to_string(status.entity) + " at " + format_vec(status.position) + " m";
    return collapse + "the flow blew up; fastest fluid particle id " + std::to_string(status.entity) +
           " at position " + format_vec(status.position) + " m with velocity " + format_vec(status.velocity) +
           " m/s";
  }
  if (status.problem == StepProblem::kTooManyEscaped) {
    const FluidSummary& fluid = *world.fluid_summary;
    char text[256];
    std::snprintf(text, sizeof text,
                  "%zu of the %zu fluid particles laid out (%.3g %%) have been removed as escaped, more than "
                  "fluid.escape_fraction_limit = %g allows: the water has left the tank",
                  fluid.removed_count(), fluid.initial_fluid_count,
                  100.0 * static_cast<double>(fluid.removed_count()) / static_cast<double>(fluid.initial_fluid_count),
                  model.fluid.escape_fraction_limit);
    return when + text;
  }
  if (status.problem == StepProblem::kSurfaceWithConservativeGradient)
    return when + "fluid particle id " + std::to_string(status.entity) + " at " + format_vec(status.position) +
           " m is flagged as free surface (" +
           std::to_string(world.fluid_summary ? world.fluid_summary->surface_count : 0) +
           " flagged in this step), but [fluid.schemes] conservative_gradient is for water without a free "
           "surface (a sealed box full of water; docs/FLUID.md, \"A momentum-conserving gradient\"): use the default "
           "gradient (GC), or fill the box and lower fluid.surface_threshold";
  if (status.problem == StepProblem::kSolverFailed)
    return when + "the pressure solve diverged (non-finite residual after " +
           std::to_string(world.fluid_summary ? world.fluid_summary->solver_iterations : 0) + " iterations)";
  return "run stopped at step " + std::to_string(world.step) + " (t = " + std::to_string(world.time) +
         " s): " + status.phase + " particle id " + std::to_string(status.entity) +
         (status.problem == StepProblem::kNonFinite
              ? " has a non-finite state"
              : " left the domain " + format_vec(domain.low) + " - " + format_vec(domain.high) + " m") +
         " at position " + format_vec(status.position) + " m with velocity " + format_vec(status.velocity) + " m/s";
}

namespace {

/// Progress: a line on the terminal at most once a second, or a log line every 30 s when not on a terminal.
class ProgressReporter {
 public:
  ProgressReporter(bool terminal, std::uint64_t first_step, double end_time, double dt)
      : terminal_(terminal), first_step_(first_step), end_time_(end_time), dt_(dt) {}
  ~ProgressReporter() {
    if (terminal_ && printed_) std::fprintf(stderr, "\n");
  }

  void tick(const World& world) {
    const auto now = Clock::now();
    if (std::chrono::duration<double>(now - last_report_).count() < (terminal_ ? 1.0 : 30.0)) return;
    last_report_ = now;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double steps_per_second = static_cast<double>(world.step - first_step_) / elapsed;
    const double eta = steps_per_second > 0.0 ? (end_time_ - world.time) / dt_ / steps_per_second : 0.0;
    if (terminal_) {
      std::fprintf(stderr, "\r  t = %.4f / %.4f s   step %llu   %.1f steps/s   ETA %s   ", world.time, end_time_,
                   static_cast<unsigned long long>(world.step), steps_per_second, format_duration(eta).c_str());
      std::fflush(stderr);
      printed_ = true;
    } else {
      spdlog::info("t = {:.4f} / {:.4f} s, step {}, {:.1f} steps/s, ETA {}", world.time, end_time_, world.step,
                   steps_per_second, format_duration(eta));
    }
  }

 private:
  bool terminal_;
  std::uint64_t first_step_;
  double end_time_, dt_;
  Clock::time_point start_ = Clock::now();
  Clock::time_point last_report_ = start_;
  bool printed_ = false;
};

}  // namespace

void request_stop(int signal_number) {
  const bool first = g_stop_signal.exchange(signal_number) == 0;
  if (first) write_signal_note();  // a run over ranks (rank 0) only; once
}
int stop_requested() { return g_stop_signal.load(); }

Simulation::Simulation(Model model, World world, OutputState output)
    : model_(std::make_unique<const Model>(std::move(model))),
      world_(std::move(world)),
      output_(std::move(output)),
      stepper_(std::make_unique<Stepper>(build_pipeline(*model_), world_, *model_)) {}

std::unique_ptr<Simulation> Simulation::from_model(Model model) {
  World world = initial_world(model);
  auto simulation = std::unique_ptr<Simulation>(new Simulation(std::move(model), std::move(world), OutputState{}));
  simulation->stepper_->compute_initial_forces();
  return simulation;
}

std::unique_ptr<Simulation> Simulation::from_scene_file(const std::string& path, const SceneLimits& limits,
                                                        const std::vector<std::string>& overrides) {
  return from_model(load_scene_file(path, limits, overrides));
}

std::filesystem::path checkpoint_run_directory(const std::string& checkpoint_path) {
  auto run_dir = (std::filesystem::path(checkpoint_path).parent_path() / "..").lexically_normal();
  if (!run_dir.has_filename()) run_dir = run_dir.parent_path();  // "A/" -> "A"
  return run_dir;
}

std::unique_ptr<Simulation> Simulation::from_checkpoint(const std::string& path, const SceneLimits& limits) {
  std::unique_ptr<Simulation> simulation = from_checkpoint_data(read_checkpoint(path), path, limits);
  // Only a checkpoint in a run's checkpoints/ folder says which run it is of: one copied elsewhere (or a link to
  // one) carries nothing rather than another folder's series.
  std::error_code error;
  const fs::path located = fs::weakly_canonical(fs::path(path), error);
  if (!error && located.parent_path().filename() == "checkpoints")
    simulation->checkpoint_run_dir_ = located.parent_path().parent_path();
  return simulation;
}

void Simulation::carry_series_into(const std::filesystem::path& out) const {
  // The series a run writes (their writers keep the rows up to the checkpoint): diagnostics, probes, bed profile.
  std::vector<std::string> names{"diagnostics.csv"};
  for (const ProbeModel& probe : model_->output.probes) names.push_back(probe.file);
  if (model_->output.bed_profile_interval > 0.0 && world_.solids) {
    names.push_back("bed_profile.csv");
    names.push_back("class_centroids.csv");
  }
  const std::vector<std::string> carried = carry_earlier_series(checkpoint_run_dir_, out, names);
  if (!carried.empty()) {
    std::string list;
    for (const std::string& name : carried) list += (list.empty() ? "" : ", ") + name;
    spdlog::info("the rows before t = {} s carried from {} (a resume into another folder keeps the whole run's "
                 "series): {}",
                 world_.time, checkpoint_run_dir_.string(), list);
  }
}

std::unique_ptr<Simulation> Simulation::from_checkpoint_data(CheckpointData data, const std::string& name,
                                                             const SceneLimits& limits) {
  Model model = parse_scene(data.scene_text, data.scene_file, limits);
  // The bulk-velocity controller's integral (FluidSummary::body_force_integral) is in checkpoints from format 12: a
  // resume from an older file would restart it from 0 and differ from the straight run, so it is refused rather
  // than done silently wrong.
  if (model.fluid.enabled && model.fluid.body_force.kind == BodyForceModel::Kind::kBulkVelocity &&
      data.format < FluidSummary::kFirstFormatWithRemovalReasons)
    throw CheckpointError(name + ": cannot resume a run whose [fluid.body_force] kind is \"bulk_velocity\" from a "
                          "checkpoint of format " + std::to_string(data.format) +
                          ": the controller's integral is stored from format 12 on; rerun it from the scene");
  // Components the scene enables but that hold no persistent state are rebuilt; the rest come from the file, once
  // checked against what this scene builds (engine/output/checkpoint_validation.hpp).
  World world = initial_world(model);
  validate_checkpoint(data, model, world, name);
  world.time = data.world.time;
  world.step = data.world.step;
  world.solids = std::move(data.world.solids);
  world.walls = std::move(data.world.walls);
  world.tank_motion = std::move(data.world.tank_motion);
  world.contacts = std::move(data.world.contacts);
  world.fluid = std::move(data.world.fluid);  // fluid_neighbours stays as initial_world made it: rebuilt
  world.mean_flow = std::move(data.world.mean_flow);
  if (world.fluid_summary) {
    // The particles the scene lays out, which the removed count is measured from, are not stored: they are the scene's.
    const std::size_t initial_fluid_count = world.fluid_summary->initial_fluid_count;
    world.fluid_summary = std::move(data.world.fluid_summary);
    world.fluid_summary->initial_fluid_count = initial_fluid_count;
  }
  return std::unique_ptr<Simulation>(new Simulation(std::move(model), std::move(world), std::move(data.output)));
}

CheckpointData Simulation::checkpoint_data() const { return checkpoint_data_of(world_); }

CheckpointData Simulation::checkpoint_data_of(const World& world) const {
  CheckpointData data;
  // Absolute, as the run's working directory sees it: a resume from another directory then finds the files the
  // scene names relative to itself ([solids] initial_state, a motion table).
  std::error_code error;
  const std::filesystem::path scene_file = std::filesystem::absolute(model_->scene_file, error);
  data.scene_file = error ? model_->scene_file : scene_file.lexically_normal().string();
  data.scene_text = model_->scene_text;
  data.world.time = world.time;
  data.world.step = world.step;
  // Every persistent part (World::kParts), so a new component cannot be left out of the checkpoint.
  std::apply(
      [&](auto... members) {
        (
            [&] {
              using Stored = typename detail::member_of<decltype(members)>::type;
              if constexpr (Stored::kPersistent) data.world.*members = world.*members;
            }(),
            ...);
      },
      World::kParts);
  data.output = output_;
  return data;
}

std::string Simulation::over_ranks_problem(const Model& model) {
  if (model.fluid.enabled && !hypre_available())
    return "MPS water over ranks solves its pressure with hypre, and this build has no hypre";
  if (model.fluid.enabled && !model.solids.enabled) return "";  // water alone
  // Grains, dry, under the mean-flow water or in MPS water (coupling_ranks.hpp): spread by their contacts.
  if (!model.solids.enabled || !model.contact.enabled)
    return "a scene without grains in contact: only the grains' contacts are decomposed over ranks";
  return "";
}

void Simulation::split_over_ranks() {
  const PeriodicBox box = periodic_box(*model_);
  // Along a periodic axis the boxes tile the period itself (a particle or grain past a face is wrapped first, and the
  // images across the faces come as ghosts).
  const auto over_the_period = [&](DomainBox domain) {
    for (int axis = 0; axis < 3; ++axis)
      if (box.periodic[static_cast<std::size_t>(axis)]) {
        domain.low[axis] = box.low[axis];
        domain.high[axis] = box.low[axis] + box.length[axis];
      }
    return domain;
  };
  if (world_.fluid) {
    const DomainBox domain = over_the_period(domain_box(*model_));
    if (box.any())
      for (Vec3& position : world_.fluid->position) position = box.wrap(position);
    const double reach = model_->fluid.effective_radius() + model_->fluid.neighbour_skin_ratio * model_->fluid.spacing;
    split_fluid_over_ranks(*world_.fluid, world_.fluid_neighbours->ranks, domain.low, domain.high, reach);
  }
  if (!world_.solids || !world_.contacts) return;
  const DomainBox domain = over_the_period(grain_domain_box(*model_));
  // A list read from a checkpoint names periodic ghosts by slot: the halo says whose they are.
  restore_halo_and_slabs(*world_.solids, *world_.contacts, *model_);
  if (box.any())
    for (Vec3& position : world_.solids->position) position = box.wrap(position);
  split_grains_over_ranks(*world_.solids, *world_.contacts, domain.low, domain.high);
  if (world_.solid_summary) world_.solid_summary->over_ranks = true;
  if (world_.mean_flow) world_.mean_flow->over_ranks = true;
}

World Simulation::gathered_world(bool pairs) const {
  // Gathers are collective: every rank takes part, rank 0 alone keeps the result.
  std::optional<FluidParticles> fluid;
  if (world_.fluid) fluid = gather_fluid_at_root(*world_.fluid);
  const bool with_grains = world_.solids && world_.contacts;
  std::optional<Solids> solids;
  std::vector<CarriedSpring> pair_springs;
  std::vector<WallContactState> wall_contacts;
  if (with_grains) {
    solids = gather_grains_at_root(*world_.solids);
    gather_contacts_at_root(*world_.solids, *world_.contacts, pair_springs, wall_contacts);
  }
  if (ranks::rank() != 0) return World{};
  World whole;
  whole.time = world_.time;
  whole.step = world_.step;
  whole.last_step = world_.last_step;
  whole.walls = world_.walls;
  whole.tank_motion = world_.tank_motion;
  whole.mean_flow = world_.mean_flow;  // the same column on every rank
  if (whole.mean_flow) whole.mean_flow->over_ranks = false;
  whole.solid_summary = world_.solid_summary;
  if (whole.solid_summary) whole.solid_summary->over_ranks = false;
  whole.step_status = world_.step_status;
  if (fluid) {
    // The water ordered by id with its fluid first (as every table keeps it); the summary's totals are the water's
    // already (fluid_checks sums them over the ranks).
    put_fluid_first(*fluid);
    fluid->next_id = world_.fluid->next_id;
    whole.fluid = std::move(fluid);
    whole.fluid_summary = world_.fluid_summary;
    if (world_.fluid_neighbours) whole.fluid_neighbours.emplace();
    if (world_.fluid_sample) whole.fluid_sample.emplace();
  }
  if (!with_grains) {
    whole.solids = world_.solids;
    return whole;
  }
  whole.solids = std::move(*solids);
  std::sort(wall_contacts.begin(), wall_contacts.end(), [](const WallContactState& a, const WallContactState& b) {
    return a.grain != b.grain ? a.grain < b.grain : a.wall < b.wall;
  });
  Contacts contacts;
  if (!pairs) {
    // The touching wall contacts alone, grain by grain in the gathered (id) order.
    const Solids& grains = *whole.solids;
    contacts.pair_offsets.assign(grains.size() + 1, 0);
    contacts.wall_pair_offsets.assign(grains.size() + 1, 0);
    std::size_t next = 0;
    for (std::size_t i = 0; i < grains.size(); ++i) {
      for (; next < wall_contacts.size() && wall_contacts[next].grain == grains.id[i]; ++next) {
        const WallContactState& wall = wall_contacts[next];
        contacts.wall_pair_wall.push_back(wall.wall);
        contacts.wall_pair_spring.push_back(wall.spring);
        contacts.wall_pair_rolling_spring.push_back(wall.rolling);
        contacts.wall_pair_force.push_back(wall.force);
        contacts.wall_pair_torque.push_back(wall.torque);
        contacts.wall_pair_overlap.push_back(wall.overlap);
      }
      contacts.wall_pair_offsets[i + 1] = static_cast<std::uint32_t>(contacts.wall_pair_wall.size());
    }
    contacts.valid = true;
    whole.contacts = std::move(contacts);
    return whole;
  }
  // A one-rank neighbour list over the whole bed, with every touching pair's and wall's spring: what a checkpoint of
  // a one-rank run holds, so the file resumes on any number of ranks.
  contacts.ranks.carried_pair_springs = std::move(pair_springs);
  for (const WallContactState& wall : wall_contacts)
    contacts.ranks.carried_wall_springs.push_back({wall.grain, wall.wall, wall.spring, wall.rolling});
  rebuild_neighbour_list(*whole.solids, contacts, *whole.walls, *whole.tank_motion, *model_, false);
  contacts.rebuilds = world_.contacts->rebuilds;
  // The touching pairs' overlaps, as the contact pass left them on the ranks: a resume (and a split) reads a pair with
  // an overlap as touching, with its spring.
  // In a periodic tank a pair's second slot may be an image across a face (a ghost, after the reals).
  const Solids& grains = *whole.solids;
  const auto reals = static_cast<std::uint32_t>(grains.size());  // a closed tank has no halo (real_count 0)
  const Ghosted<Vec3> position{grains.position.data(), contacts.ghosts.position.data(), reals};
  const Ghosted<double> radius{grains.radius.data(), contacts.ghosts.radius.data(), reals};
  for (std::size_t i = 0; i < grains.size(); ++i)
    for (std::uint32_t k = contacts.pair_offsets[i]; k < contacts.pair_offsets[i + 1]; ++k) {
      const std::uint32_t j = contacts.pair_second[k];
      const double gap = (position[j] - grains.position[i]).norm() - grains.radius[i] - radius[j];
      if (gap < 0.0) contacts.pair_overlap[k] = -gap;
    }
  // The wall contacts' forces as the ranks had them (the wall probes read them).
  for (std::size_t i = 0; i < whole.solids->size(); ++i)
    for (std::uint32_t k = contacts.wall_pair_offsets[i]; k < contacts.wall_pair_offsets[i + 1]; ++k) {
      WallContactState probe;
      probe.grain = whole.solids->id[i];
      probe.wall = contacts.wall_pair_wall[k];
      const auto it = std::lower_bound(wall_contacts.begin(), wall_contacts.end(), probe,
                                       [](const WallContactState& a, const WallContactState& b) {
                                         return a.grain != b.grain ? a.grain < b.grain : a.wall < b.wall;
                                       });
      if (it == wall_contacts.end() || it->grain != probe.grain || it->wall != probe.wall) continue;
      contacts.wall_pair_force[k] = it->force;
      contacts.wall_pair_torque[k] = it->torque;
      contacts.wall_pair_overlap[k] = it->overlap;
    }
  whole.contacts = std::move(contacts);
  return whole;
}

RunOutcome Simulation::run(const RunOptions& options) {
  if (over_ranks()) return run_over_ranks(options);
  const fs::path out = options.out_dir;
  const fs::path vtk_dir = out / "vtk";
  const fs::path checkpoint_dir = out / "checkpoints";
  RunOutcome outcome;
  // An error here is printed at once: the log file is not open yet.
  const auto refuse = [](const std::string& message) {
    spdlog::error("{}", message);
    return RunOutcome{kExitIoError, message, ""};
  };
  try {
    fs::create_directories(out);
  } catch (const std::exception& error) {
    return refuse("cannot create the output directory '" + out.string() + "': " + error.what());
  }
  // Before anything is written into the folder: a second run into it is refused, not interleaved with this one.
  std::optional<OutputLock> lock;
  try {
    lock.emplace(out);
  } catch (const OutputLockError& error) {
    return refuse(error.what());
  }
  try {
    fs::create_directories(vtk_dir);
    fs::create_directories(checkpoint_dir);
  } catch (const std::exception& error) {
    return refuse("cannot create the output directory '" + out.string() + "': " + error.what());
  }
  // What a killed run was writing when it died (it held the lock, so nobody is writing these now).
  for (const fs::path& directory : {out, vtk_dir, checkpoint_dir})
    if (const std::size_t removed = remove_stale_temporaries(directory))
      spdlog::info("removed {} temporary file(s) a killed run left in {}", removed, directory.string());

  std::shared_ptr<spdlog::sinks::basic_file_sink_mt> file_sink;
  try {
    file_sink = std::make_shared<spdlog::sinks::basic_file_sink_mt>((out / "riffle.log").string(), false);
  } catch (const std::exception& error) {  // spdlog::spdlog_ex: a directory in the way, no permission
    return refuse((out / "riffle.log").string() + ": cannot open the log file: " + error.what());
  }
  auto logger = spdlog::default_logger();
  logger->sinks().push_back(file_sink);
  struct SinkGuard {
    std::shared_ptr<spdlog::logger> logger;
    ~SinkGuard() { logger->sinks().pop_back(); }
  } sink_guard{logger};
  // The scene as this run reads it, --set overrides applied (the text its checkpoints hold): what a later look at the
  // folder (a plot, a post-processing tool) must read, not the scene file, which the command line may have changed.
  // Relative paths in it are relative to the scene file's folder, as in the file.
  try {
    replace_file(out / kSceneAsRunFile, model_->scene_text, Durability::kFlush);
  } catch (const std::exception& error) {
    return refuse(error.what());
  }

  const int threads = options.threads > 0 ? options.threads : tbb::info::default_concurrency();
  tbb::global_control thread_limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  const double end_time = options.until.value_or(model_->end_time);
  const bool fresh_run = world_.step == 0 && output_.frame_times.empty();
  spdlog::info("{} '{}' from {}: t = {} s to {} s, dt = {} s, {} solid sub-steps, {} grains, {} threads",
               fresh_run ? "starting" : "resuming", model_->name, model_->scene_file, world_.time, end_time,
               model_->dt, model_->solid_substeps, world_.solids ? world_.solids->size() : 0, threads);
  if (world_.solids) {
    const auto fixed = std::count(world_.solids->fixed.begin(), world_.solids->fixed.end(), 1);
    if (fixed > 0) spdlog::info("{} of the grains are fixed for the whole run (a rough floor)", fixed);
    else if (!std::isnan(model_->solids.fixed_below))
      spdlog::warn("[solids] fixed_below = {} m fixes no grain: no centre lies below it at the start",
                   model_->solids.fixed_below);
  }

  double min_radius = 0.0;
  if (world_.solids && world_.solids->size())
    min_radius = *std::min_element(world_.solids->radius.begin(), world_.solids->radius.end());
  CheckpointStore checkpoints(checkpoint_dir, output_, model_->output.checkpoint_keep);
  const double dt = model_->dt;
  auto due = [&](double interval, std::size_t done) {
    return interval > 0.0 && world_.time >= static_cast<double>(done) * interval - 0.5 * dt;
  };

  // A stop request ends even a step of millions of sub-steps: after kStopGraceSeconds the step is abandoned.
  stepper_->set_stop_flag(&g_stop_signal, kStopGraceSeconds);
  const auto abandoned_step_outcome = [&](const std::string& last_good) {
    const int signal_number = stop_requested();
    const char* name = signal_number == SIGINT ? "SIGINT" : "SIGTERM";
    const std::string grace = format_time(kStopGraceSeconds);
    RunOutcome abandoned;
    abandoned.exit_code = signal_number == SIGINT ? kExitInterrupted : kExitTerminated;
    abandoned.message = std::string("stopped by ") + name + " during step " + std::to_string(world_.step + 1) +
                        " (from t = " + format_time(world_.time) + " s), which did not finish within " + grace +
                        " s of the request: the step was abandoned and no checkpoint of it written; last good "
                        "checkpoint: " +
                        (last_good.empty() ? std::string("none written yet (set output.checkpoint_interval)")
                                           : last_good);
    abandoned.last_checkpoint = last_good;
    return abandoned;
  };

  double stepping_seconds = 0.0;
  std::uint64_t unconverged_pressure_steps = 0;
  FrameFiles frame_files(out, fresh_run ? fs::path() : checkpoint_run_dir_);
  try {
    if (!fresh_run) carry_series_into(out);
    DiagnosticsWriter diagnostics(out / "diagnostics.csv", world_, stepper_->timers(), fresh_run,
                                  model_->fluid.body_force.kind != BodyForceModel::Kind::kNone);
    // Probes and the bed profile keep no state in checkpoints: their schedules depend on the time only.
    std::vector<ProbeWriter> probes;
    for (const ProbeModel& probe : model_->output.probes) probes.emplace_back(*model_, probe, out, world_, fresh_run);
    std::optional<BedProfileWriter> bed_profile;
    if (model_->output.bed_profile_interval > 0.0 && world_.solids)
      bed_profile.emplace(*model_, out, world_, fresh_run);
    report_set_aside_series(diagnostics, probes, bed_profile, world_.time);
    if (fresh_run && due(model_->output.vtk_interval, output_.frame_times.size()))
      write_vtk_frame(out, world_, *model_, output_, frame_files);
    if (fresh_run) {
      for (ProbeWriter& probe : probes) probe.write(world_);
      if (bed_profile) bed_profile->write(world_);
    }

    ProgressReporter progress(options.progress, world_.step, end_time, dt);
    while (world_.time < end_time - 0.5 * dt) {
      if (const int signal_number = stop_requested()) {
        checkpoints.save(*this, false);
        outcome.exit_code = signal_number == SIGINT ? kExitInterrupted : kExitTerminated;
        outcome.message = std::string("stopped by ") + (signal_number == SIGINT ? "SIGINT" : "SIGTERM") +
                          " at t = " + std::to_string(world_.time) + " s; checkpoint: " + checkpoints.last_written();
        outcome.last_checkpoint = checkpoints.last_written();
        break;
      }
      const auto step_start = Clock::now();
      try {
        stepper_->step();
      } catch (const std::bad_alloc&) {
        outcome.exit_code = kExitUnstable;
        outcome.message = "out of memory in step " + std::to_string(world_.step + 1) + " (std::bad_alloc)";
        break;
      } catch (const std::exception& error) {
        outcome.exit_code = kExitUnstable;
        outcome.message = "internal error in step " + std::to_string(world_.step + 1) + ": " + error.what();
        break;
      }
      if (stepper_->last_step_abandoned()) {
        outcome = abandoned_step_outcome(checkpoints.last_good());
        break;
      }
      const double step_seconds = seconds_since(step_start);
      stepping_seconds += step_seconds;
      if (world_.fluid_summary) log_escaped(world_.fluid_summary->escaped, world_, *model_);
      log_unconverged_pressure(world_, *model_, unconverged_pressure_steps);

      if (!world_.step_status.ok()) {
        outcome.exit_code = kExitUnstable;
        outcome.message = diagnosis(world_, *model_);
        diagnostics.row(world_, *model_, min_radius, step_seconds, stepper_->timers());
        if (world_.solids)
          write_text_file(vtk_dir / "solids_failed.vtp",
                          solids_vtp(*world_.solids, periodic_box(*model_), failure_frame_format(*model_)));
        break;
      }
      if (world_.step % static_cast<std::uint64_t>(model_->output.diagnostics_every) == 0)
        diagnostics.row(world_, *model_, min_radius, step_seconds, stepper_->timers());
      if (due(model_->output.vtk_interval, output_.frame_times.size()))
        write_vtk_frame(out, world_, *model_, output_, frame_files);
      for (ProbeWriter& probe : probes) probe.write_if_due(world_);
      if (bed_profile) bed_profile->write_if_due(world_);
      if (due(model_->output.checkpoint_interval, output_.checkpoints_due + 1)) checkpoints.save(*this, true);
      progress.tick(world_);
    }
    for (const ProbeWriter& probe : probes)
      if (const std::string line = probe.summary(); !line.empty()) spdlog::info("{}", line);
  } catch (const CheckpointError& error) {
    outcome = {kExitIoError, error.what(), checkpoints.last_written()};
  } catch (const std::bad_alloc&) {  // not an output problem: exit 3, like a failing step
    outcome = {kExitUnstable, "out of memory while writing the outputs (std::bad_alloc)", checkpoints.last_written()};
  } catch (const std::exception& error) {
    outcome = {kExitIoError, std::string("output failed: ") + error.what(), checkpoints.last_written()};
  }

  try {
    if (outcome.exit_code == kExitOk) {
      checkpoints.save(*this, false);
      checkpoints.copy_as_final();
      outcome.last_checkpoint = checkpoints.last_written();
      outcome.message = "finished at t = " + std::to_string(world_.time) + " s after " +
                        std::to_string(world_.step) + " steps" + removed_summary(world_, *model_) +
                        (unconverged_pressure_steps > 0
                             ? "; " + std::to_string(unconverged_pressure_steps) +
                                   " step(s) went on with a pressure solve short of its tolerance"
                             : std::string()) +
                        "; final checkpoint: " + outcome.last_checkpoint;
    } else if (outcome.exit_code == kExitUnstable) {
      outcome.last_checkpoint = checkpoints.last_good();
      // (A stop for too much escaped water has said how much already.)
      if (world_.step_status.problem != StepProblem::kTooManyEscaped)
        outcome.message += removed_summary(world_, *model_);
      outcome.message += "; last good checkpoint: " +
                         (outcome.last_checkpoint.empty()
                              ? std::string("none written yet (set output.checkpoint_interval)")
                              : outcome.last_checkpoint + " (the run can go on from there: riffle resume " +
                                    outcome.last_checkpoint + ")");
    }
  } catch (const std::exception& error) {
    outcome = {kExitIoError, std::string("final checkpoint failed: ") + error.what(), checkpoints.last_written()};
  }

  std::vector<SystemTimer> timers = stepper_->timers();
  for (const SystemTimer& branch : stepper_->branch_timers())
    if (branch.calls > 0) timers.push_back(branch);
  try {
    write_text_file(out / "timings.csv", format_timing_csv(timers, stepping_seconds));
  } catch (const std::exception& error) {
    spdlog::error("{}", error.what());
  }
  spdlog::info("per-system timings ({} threads{}):\n{}", threads,
               stepper_->concurrent_branches() ? "; the fluid step graph runs beside the grains' branch" : "",
               format_timing_table(timers, stepping_seconds));
  if (outcome.exit_code == kExitOk)
    spdlog::info("{}", outcome.message);
  else
    spdlog::error("{}", outcome.message);
  return outcome;
}

namespace {

/// The first non-empty of the ranks' `message`s, in rank order, at rank 0 (empty elsewhere). Collective.
std::string first_message_at_root(const std::string& message) {
  std::vector<std::byte> bytes(message.size());
  std::memcpy(bytes.data(), message.data(), message.size());
  const std::vector<std::vector<std::byte>> all = ranks::gather_at_root(bytes);
  for (std::size_t r = 0; r < all.size(); ++r)
    if (!all[r].empty()) {
      std::string text(all[r].size(), ' ');
      std::memcpy(text.data(), all[r].data(), all[r].size());
      return (all.size() > 1 ? "rank " + std::to_string(r) + ": " : std::string()) + text;
    }
  return "";
}

/// Over MPI ranks, a VTK frame in pieces (`output.vtk_pieces = "per_rank"`): every rank writes the grains and the
/// water it owns (vtk/solids_000004_R.vtp for rank R), nothing gathered; once every piece is on disk, rank 0 writes
/// the walls (the same on every rank), a .pvtp per phase naming the pieces and the .pvd series. Collective: every
/// rank calls it for the same frame. Returns the first failing rank's error at rank 0 ("" when all wrote; on the
/// other ranks, "" or "failed").
std::string write_vtk_pieces(const fs::path& out, const World& mine, const Model& model, OutputState& output,
                             FrameFiles& files) {
  const std::size_t index = output.frame_times.size();
  output.frame_times.push_back(mine.time);
  const int rank_count = ranks::size();
  const VtkFormat format = vtk_format(model.output);
  const auto piece = [&](const char* phase, int rank) {
    char name[64];
    std::snprintf(name, sizeof name, "%s_%06zu_%d.vtp", phase, index, rank);
    return std::string(name);
  };
  std::string problem;
  try {
    if (mine.solids)
      write_text_file(out / "vtk" / piece("solids", ranks::rank()), solids_vtp(*mine.solids, periodic_box(model), format));
    if (mine.fluid) write_text_file(out / "vtk" / piece("fluid", ranks::rank()), fluid_vtp(*mine.fluid, format));
  } catch (const std::exception& error) {
    problem = error.what();
  }
  if (ranks::any(!problem.empty())) {
    const std::string first = first_message_at_root(problem);
    return ranks::rank() == 0 ? first : "failed";
  }
  if (ranks::rank() != 0) return "";
  files.written(index, true);
  try {
    const auto parallel = [&](const char* phase,
                              std::string (*pvtp)(const std::vector<std::string>&, const VtkFormat&)) {
      std::vector<std::string> pieces;
      for (int rank = 0; rank < rank_count; ++rank) pieces.push_back(piece(phase, rank));
      write_text_file(out / frame_name(phase, index, ".pvtp"), pvtp(pieces, format));
      fs::remove(out / frame_name(phase, index, ".vtp"));
      files.write_series(phase, output.frame_times);
    };
    if (mine.solids) parallel("solids", solids_pvtp);
    if (mine.walls) {
      write_text_file(out / frame_name("walls", index, ".vtp"), walls_vtp(*mine.walls, format));
      files.write_series("walls", output.frame_times);
    }
    if (mine.fluid) parallel("fluid", fluid_pvtp);
  } catch (const std::exception& error) {
    return error.what();
  }
  return "";
}

/// Every rank's particles removed as escaped in the last step, at rank 0 in rank order (empty elsewhere). Collective.
std::vector<EscapedParticle> escaped_at_root(const std::vector<EscapedParticle>& mine) {
  constexpr std::size_t kPerParticle = 8;  // id, position, velocity, left_domain
  std::vector<double> packed;
  packed.reserve(kPerParticle * mine.size());
  for (const EscapedParticle& particle : mine)
    packed.insert(packed.end(), {static_cast<double>(particle.id), particle.position.x(), particle.position.y(),
                                 particle.position.z(), particle.velocity.x(), particle.velocity.y(),
                                 particle.velocity.z(), particle.left_domain ? 1.0 : 0.0});
  const std::vector<double> all = ranks::gather_all(packed);
  std::vector<EscapedParticle> escaped;
  if (ranks::rank() != 0) return escaped;
  for (std::size_t k = 0; k + kPerParticle <= all.size(); k += kPerParticle)
    escaped.push_back(EscapedParticle{static_cast<EntityId>(all[k]), Vec3(all[k + 1], all[k + 2], all[k + 3]),
                                      Vec3(all[k + 4], all[k + 5], all[k + 6]), all[k + 7] != 0.0});
  return escaped;
}

/// Every rank's `listed` timers (the same systems, in the same order, on every rank) and stepping time, at rank 0 in
/// rank order (empty elsewhere, and at rank 0 if the ranks' lists differ in length). Collective.
std::vector<RankTimers> gather_rank_timers(const std::vector<SystemTimer>& listed, double stepping_seconds) {
  constexpr std::size_t kPerTimer = 3;  // calls, total seconds, items
  std::vector<double> mine;
  mine.reserve(kPerTimer * listed.size() + 1);
  for (const SystemTimer& timer : listed)
    mine.insert(mine.end(), {static_cast<double>(timer.calls), timer.total_seconds, static_cast<double>(timer.items)});
  mine.push_back(stepping_seconds);
  const std::vector<double> all = ranks::gather_all(mine);
  std::vector<RankTimers> per_rank;
  const auto count = static_cast<std::size_t>(ranks::size());
  if (ranks::rank() != 0 || all.size() != count * mine.size()) return per_rank;
  for (std::size_t r = 0; r < count; ++r) {
    const double* row = &all[r * mine.size()];
    RankTimers rank;
    rank.timers = listed;
    for (std::size_t t = 0; t < listed.size(); ++t) {
      rank.timers[t].calls = static_cast<std::uint64_t>(row[kPerTimer * t]);
      rank.timers[t].total_seconds = row[kPerTimer * t + 1];
      rank.timers[t].items = static_cast<std::uint64_t>(row[kPerTimer * t + 2]);
    }
    rank.stepping_seconds = row[kPerTimer * listed.size()];
    per_rank.push_back(std::move(rank));
  }
  return per_rank;
}

}  // namespace

RunOutcome Simulation::run_over_ranks(const RunOptions& options) {
  const bool root = ranks::rank() == 0;
  const fs::path out = options.out_dir;
  const fs::path vtk_dir = out / "vtk";
  const fs::path checkpoint_dir = out / "checkpoints";
  // Rank 0 alone owns the output folder: it locks it, opens the log, writes every file but the pieces of a frame,
  // which each rank writes for itself. The other ranks follow every decision rank 0 or any rank makes (each is a
  // collective), so they all stop at the same step.
  std::optional<OutputLock> lock;
  std::shared_ptr<spdlog::sinks::basic_file_sink_mt> file_sink;
  std::string set_up_problem;
  if (root) {
    try {
      fs::create_directories(out);
      lock.emplace(out);
      fs::create_directories(vtk_dir);
      fs::create_directories(checkpoint_dir);
      for (const fs::path& directory : {out, vtk_dir, checkpoint_dir}) remove_stale_temporaries(directory);
      file_sink = std::make_shared<spdlog::sinks::basic_file_sink_mt>((out / "riffle.log").string(), false);
      replace_file(out / kSceneAsRunFile, model_->scene_text, Durability::kFlush);
    } catch (const std::exception& error) {
      set_up_problem = "cannot set up the output folder '" + out.string() + "': " + error.what();
    }
  }
  if (ranks::any(!set_up_problem.empty())) {
    if (root) spdlog::error("{}", set_up_problem);
    return RunOutcome{kExitIoError, set_up_problem, ""};
  }
  auto logger = spdlog::default_logger();
  if (file_sink) logger->sinks().push_back(file_sink);
  struct SinkGuard {
    std::shared_ptr<spdlog::logger> logger;
    bool added;
    ~SinkGuard() {
      if (added) logger->sinks().pop_back();
    }
  } sink_guard{logger, file_sink != nullptr};
  // Rank 0 names the last whole checkpoint if a signal ends the ranks from outside (SignalNote).
  struct SignalNoteGuard {
    explicit SignalNoteGuard(const fs::path& log) {
      g_signal_note.log_file.store(::open(log.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC));
      prepare_signal_note("", 0.0, 0);
    }
    ~SignalNoteGuard() {
      g_signal_note.ready.store(-1);
      if (const int log = g_signal_note.log_file.exchange(-1); log >= 0) ::close(log);
    }
  };
  std::optional<SignalNoteGuard> signal_note;
  if (root && file_sink) signal_note.emplace(out / "riffle.log");

  const int threads = options.threads > 0 ? options.threads : tbb::info::default_concurrency();
  tbb::global_control thread_limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  const double end_time = options.until.value_or(model_->end_time);
  const bool fresh_run = world_.step == 0 && output_.frame_times.empty();
  // What each rank holds: its grains, or in a scene of water alone its MPS particles (fluid, walls and dummies).
  const bool grains = world_.solids.has_value();
  const char* held = grains ? "grains" : "MPS particles";
  const auto held_here = [&] { return static_cast<double>(grains ? world_.solids->size() : world_.fluid->size()); };
  const std::vector<double> owned = ranks::gather_all({held_here()});
  if (root) {
    std::string shares;
    for (const double count : owned) shares += (shares.empty() ? "" : ", ") + std::to_string(static_cast<long long>(count));
    spdlog::info("{} '{}' from {}: t = {} s to {} s, dt = {} s, {} solid sub-steps, over {} MPI ranks of {} threads; "
                 "{} per rank: {}",
                 fresh_run ? "starting" : "resuming", model_->name, model_->scene_file, world_.time, end_time,
                 model_->dt, model_->solid_substeps, ranks::size(), threads, held, shares);
  }
  double min_radius = grains && world_.solids->size()
                          ? *std::min_element(world_.solids->radius.begin(), world_.solids->radius.end())
                          : std::numeric_limits<double>::infinity();
  min_radius = -ranks::max(-min_radius);
  CheckpointStore checkpoints(checkpoint_dir, output_, model_->output.checkpoint_keep);
  const double dt = model_->dt;
  auto due = [&](double interval, std::size_t done) {
    return interval > 0.0 && world_.time >= static_cast<double>(done) * interval - 0.5 * dt;
  };
  RunOutcome outcome;
  // Rank 0's output errors end every rank: whether one happened is shared after each write.
  std::string output_problem;
  const auto write_on_root = [&](auto&& write) {
    if (root && output_problem.empty()) {
      try {
        write();
      } catch (const std::exception& error) {
        output_problem = error.what();
      }
    }
    return !ranks::any(!output_problem.empty());
  };
  // The checkpoint bookkeeping (output_) is kept on every rank alike, so every rank's schedule agrees.
  const auto save_checkpoint = [&](bool interval) {
    const World whole = gathered_world();
    if (root) {
      try {
        checkpoints.save(world_.step, interval, [&] { return checkpoint_data_of(whole); });
        prepare_signal_note(checkpoints.last_written(), world_.time, world_.step);
      } catch (const std::exception& error) {
        output_problem = error.what();
      }
    } else if (interval) {
      ++output_.checkpoints_due;
    }
    return !ranks::any(!output_problem.empty());
  };

  // A frame in pieces, each rank its own (no gather), or gathered at rank 0 into one file as one rank writes it.
  FrameFiles frame_files(out, fresh_run ? fs::path() : checkpoint_run_dir_);  // rank 0's: the series it writes
  const bool frame_in_pieces = model_->output.vtk_pieces == OutputModel::VtkPieces::kPerRank && ranks::size() > 1;
  const auto write_pieces = [&] {
    const std::string problem = write_vtk_pieces(out, world_, *model_, output_, frame_files);
    if (root && !problem.empty() && output_problem.empty()) output_problem = problem;
    return !ranks::any(!problem.empty());
  };

  double stepping_seconds = 0.0;
  ranks::CallTimes stepping_calls;  // the MPI calls' share of stepping_seconds
  std::optional<DiagnosticsWriter> diagnostics;
  std::vector<ProbeWriter> probes;
  std::optional<BedProfileWriter> bed_profile;
  bool outputs_ok = true;  // false once rank 0 failed to write (every rank knows: write_on_root shares it)
  {
    const World whole = gathered_world();
    outputs_ok = write_on_root([&] {
      if (!fresh_run) carry_series_into(out);
      // The body force is the same on every rank (prescribed, or the controller's on the bulk velocity of all the
      // water): its column as on one rank, so a run's series keeps its columns when resumed on another rank count.
      diagnostics.emplace(out / "diagnostics.csv", world_, stepper_->timers(), fresh_run,
                          model_->fluid.body_force.kind != BodyForceModel::Kind::kNone);
      for (const ProbeModel& probe : model_->output.probes) probes.emplace_back(*model_, probe, out, whole, fresh_run);
      if (model_->output.bed_profile_interval > 0.0) bed_profile.emplace(*model_, out, whole, fresh_run);
      report_set_aside_series(*diagnostics, probes, bed_profile, world_.time);
      if (!frame_in_pieces && fresh_run && due(model_->output.vtk_interval, output_.frame_times.size()))
        write_vtk_frame(out, whole, *model_, output_, frame_files);
      if (fresh_run) {
        for (ProbeWriter& probe : probes) probe.write(whole);
        if (bed_profile) bed_profile->write(whole);
      }
    });
    if (fresh_run && due(model_->output.vtk_interval, output_.frame_times.size())) {
      if (frame_in_pieces)
        outputs_ok = write_pieces() && outputs_ok;
      else if (!root)
        output_.frame_times.push_back(world_.time);
    }
  }

  ProgressReporter progress(options.progress && root, world_.step, end_time, dt);
  // The water's removals so far (summed over the ranks: the same on every rank), to tell each step whether any rank
  // removed escaped particles; and the steps whose pressure solve stopped short (reported as on one rank).
  std::size_t removed_so_far = world_.fluid_summary ? world_.fluid_summary->removed_count() : 0;
  std::uint64_t unconverged_pressure_steps = 0;
  while (outputs_ok && world_.time < end_time - 0.5 * dt) {
    if (ranks::any(stop_requested() != 0)) {
      const int signal_number = stop_requested() != 0 ? stop_requested() : SIGTERM;
      outputs_ok = save_checkpoint(false);
      outcome.exit_code = signal_number == SIGINT ? kExitInterrupted : kExitTerminated;
      outcome.message = std::string("stopped by ") + (signal_number == SIGINT ? "SIGINT" : "SIGTERM") + " at t = " +
                        std::to_string(world_.time) + " s; checkpoint: " + checkpoints.last_written();
      outcome.last_checkpoint = checkpoints.last_written();
      break;
    }
    const auto step_start = Clock::now();
    const ranks::CallTimes calls_before = ranks::call_times();
    try {
      stepper_->step();
    } catch (const std::exception& error) {
      // The other ranks wait in this step's exchanges for one that has left it: nothing but ending them all helps.
      spdlog::error("rank {}: internal error in step {}: {}; ending every rank", ranks::rank(), world_.step + 1,
                    error.what());
      ranks::abort(kExitUnstable);
    }
    stepping_seconds += seconds_since(step_start);
    const ranks::CallTimes& calls_after = ranks::call_times();
    stepping_calls.exchange_seconds += calls_after.exchange_seconds - calls_before.exchange_seconds;
    stepping_calls.reduce_seconds += calls_after.reduce_seconds - calls_before.reduce_seconds;
    stepping_calls.exchanges += calls_after.exchanges - calls_before.exchanges;
    stepping_calls.reductions += calls_after.reductions - calls_before.reductions;
    if (world_.fluid_summary) {
      // Each rank removed its own escaped particles; rank 0 names them all, as one rank does.
      if (world_.fluid_summary->removed_count() != removed_so_far) {
        const std::vector<EscapedParticle> escaped = escaped_at_root(world_.fluid_summary->escaped);
        if (root) log_escaped(escaped, world_, *model_);
        removed_so_far = world_.fluid_summary->removed_count();
      }
      // The solve is one over all the ranks: its report is the same on each.
      if (root) log_unconverged_pressure(world_, *model_, unconverged_pressure_steps);
    }
    // A grain lost or non-finite on any rank ends the run on every rank, with that rank's diagnosis.
    const bool failed_here = !world_.step_status.ok();
    if (ranks::any(failed_here)) {
      const std::string message = first_message_at_root(failed_here ? diagnosis(world_, *model_) : std::string());
      const World whole = gathered_world();
      outcome.exit_code = kExitUnstable;
      outcome.message = message;
      write_on_root([&] {
        if (whole.solids)
          write_text_file(vtk_dir / "solids_failed.vtp",
                          solids_vtp(*whole.solids, periodic_box(*model_), failure_frame_format(*model_)));
      });
      break;
    }
    if (world_.step % static_cast<std::uint64_t>(model_->output.diagnostics_every) == 0 &&
        !(outputs_ok = write_on_root(
              [&] { diagnostics->row(world_, *model_, min_radius, seconds_since(step_start), stepper_->timers()); })))
      break;
    // Rank 0 knows which outputs are due (the probes keep their own schedules): it tells the others whether to gather,
    // and whether the pairs are wanted (the bed profile counts contacts; a checkpoint holds them).
    const bool checkpoint_due = due(model_->output.checkpoint_interval, output_.checkpoints_due + 1);
    const bool frame = due(model_->output.vtk_interval, output_.frame_times.size());
    if (frame && frame_in_pieces && !(outputs_ok = write_pieces())) break;
    bool gather = frame && !frame_in_pieces;
    bool pairs = false;
    if (root) {
      for (const ProbeWriter& probe : probes) gather = gather || probe.due(world_.time) || probe.reads_every_step();
      pairs = bed_profile && bed_profile->due(world_.time);
    }
    const double wanted = ranks::max(pairs ? 2.0 : gather ? 1.0 : 0.0);  // the same on every rank
    if (wanted > 0.0) {
      const World whole = gathered_world(wanted == 2.0);
      const bool gathered_frame = frame && !frame_in_pieces;
      outputs_ok = write_on_root([&] {
        if (gathered_frame) write_vtk_frame(out, whole, *model_, output_, frame_files);
        for (ProbeWriter& probe : probes) probe.write_if_due(whole);
        if (bed_profile) bed_profile->write_if_due(whole);
      });
      if (!root && gathered_frame) output_.frame_times.push_back(world_.time);
    }
    if (outputs_ok && checkpoint_due) outputs_ok = save_checkpoint(true);
    progress.tick(world_);
  }
  if (!outputs_ok)
    outcome = {kExitIoError, "output failed" + (output_problem.empty() ? std::string(" on rank 0") : ": " + output_problem),
               checkpoints.last_written()};
  write_on_root([&] {
    for (const ProbeWriter& probe : probes)
      if (const std::string line = probe.summary(); !line.empty()) spdlog::info("{}", line);
  });

  if (outcome.exit_code == kExitOk) {
    if (save_checkpoint(false) && write_on_root([&] { checkpoints.copy_as_final(); })) {
      outcome.last_checkpoint = checkpoints.last_written();
      outcome.message = "finished at t = " + std::to_string(world_.time) + " s after " + std::to_string(world_.step) +
                        " steps over " + std::to_string(ranks::size()) + " MPI ranks; final checkpoint: " +
                        outcome.last_checkpoint;
    } else {
      outcome = {kExitIoError, "final checkpoint failed: " + output_problem, checkpoints.last_written()};
    }
  } else if (outcome.exit_code == kExitUnstable) {
    outcome.last_checkpoint = checkpoints.last_good();
    outcome.message += "; last good checkpoint: " +
                       (outcome.last_checkpoint.empty() ? std::string("none written yet (set output.checkpoint_interval)")
                                                        : outcome.last_checkpoint);
  }

  // Each rank's stepping time, its MPI calls' share (waiting for the others included) and grains: the balance of the
  // decomposition is that of the time outside the calls.
  const std::vector<double> seconds =
      ranks::gather_all({stepping_seconds, held_here(), stepping_calls.exchange_seconds,
                         stepping_calls.reduce_seconds, static_cast<double>(stepping_calls.exchanges),
                         static_cast<double>(stepping_calls.reductions)});
  std::vector<SystemTimer> timers = stepper_->timers();
  for (const SystemTimer& branch : stepper_->branch_timers())
    if (branch.calls > 0) timers.push_back(branch);
  // Every rank's systems and branches (the same list on each: the same model registers them), gathered for the
  // per-system table over the ranks.
  std::vector<SystemTimer> listed = stepper_->timers();
  for (const SystemTimer& branch : stepper_->branch_timers()) listed.push_back(branch);
  const std::vector<RankTimers> per_rank = gather_rank_timers(listed, stepping_seconds);
  if (root) {
    constexpr std::size_t kFields = 6;
    const std::size_t rank_count = seconds.size() / kFields;
    std::string balance;
    double longest = 0.0, sum = 0.0;
    for (std::size_t r = 0; r < rank_count; ++r) {
      const double* row = &seconds[kFields * r];
      const double computing = row[0] - row[2] - row[3];
      char text[320];
      std::snprintf(text, sizeof text,
                    "\n  rank %zu: %lld %s, stepping %.3f s: computing %.3f s, exchanging %.3f s (%.0f calls), "
                    "reducing %.3f s (%.0f calls)",
                    r, static_cast<long long>(row[1]), held, row[0], computing, row[2], row[4], row[3], row[5]);
      balance += text;
      longest = std::max(longest, computing);
      sum += computing;
    }
    const double mean = sum / static_cast<double>(rank_count);
    if (grains)
      spdlog::info("ranks' stepping (imbalance, the longest computing time over the mean: {:.3f}; the MPI calls' times "
                   "include waiting for the slowest rank; the boxes cut anew {} time(s) as the bed moved):{}",
                   mean > 0.0 ? longest / mean : 1.0, world_.contacts->ranks.rebalances, balance);
    else
      spdlog::info("ranks' stepping (imbalance, the longest computing time over the mean: {:.3f}; the MPI calls' times "
                   "include waiting for the slowest rank{}; the boxes cut anew {} time(s) as the water moved):{}",
                   mean > 0.0 ? longest / mean : 1.0,
                   model_->fluid.preconditioner == FluidModel::Preconditioner::kBoomerAmg
                       ? ", hypre's pressure solve not among them"
                       : "",
                   world_.fluid_neighbours->ranks.rebalances, balance);
    try {
      write_text_file(out / "timings.csv", format_timing_csv(timers, stepping_seconds));
    } catch (const std::exception& error) {
      spdlog::error("{}", error.what());
    }
    spdlog::info("per-system timings of rank 0 ({} threads):\n{}", threads, format_timing_table(timers, stepping_seconds));
    if (!per_rank.empty()) {
      spdlog::info("per-system timings over the {} ranks (each rank's in timings_ranks.csv):\n{}", per_rank.size(),
                   format_rank_timing_table(per_rank));
      try {
        write_text_file(out / "timings_ranks.csv", format_rank_timing_csv(per_rank));
      } catch (const std::exception& error) {
        spdlog::error("{}", error.what());
      }
    }
    if (outcome.exit_code == kExitOk)
      spdlog::info("{}", outcome.message);
    else
      spdlog::error("{}", outcome.message);
  }
  return outcome;
}

}  // namespace riffle
