#pragma once
// A run: the model, the world, the stepper, and the run loop with its outputs (VTK frames, diagnostics.csv,
// timings.csv, checkpoints), progress reporting, signal handling and the failure policy.
#include <atomic>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/setup/budget.hpp"
#include "engine/output/checkpoint.hpp"
#include "components/model.hpp"
#include "engine/run/stepper.hpp"
#include "components/world.hpp"

namespace riffle {

/// Process exit codes (documented in README.md and `riffle --help`).
enum ExitCode : int {
  kExitOk = 0,
  kExitUsage = 1,         ///< bad command line
  kExitInvalidInput = 2,  ///< invalid scene or checkpoint
  kExitUnstable = 3,      ///< the run stopped with a diagnosis (NaN, particle lost); last good checkpoint kept
  kExitIoError = 4,       ///< output could not be written
  kExitInterrupted = 130, ///< SIGINT: checkpoint written, clean exit
  kExitTerminated = 143,  ///< SIGTERM: checkpoint written, clean exit
};

/// Asks the running loop to stop after the current step, or within about 2 s inside a step that takes longer
/// (async-signal-safe: stores into a lock-free atomic that the stepper reads between sub-steps).
void request_stop(int signal_number);
/// The signal number of a pending stop request, or 0.
int stop_requested();

/// The run folder's copy of the scene as the run read it (--set overrides applied; the text its checkpoints hold).
inline constexpr const char* kSceneAsRunFile = "scene_as_run.toml";

struct RunOptions {
  std::string out_dir;                ///< where every output goes (created if needed)
  int threads = 0;                    ///< 0 = all cores
  std::optional<double> until;        ///< [s] overrides run.end_time
  bool progress = false;              ///< print a progress line (on a terminal)
};

struct RunOutcome {
  int exit_code = kExitOk;
  std::string message;          ///< one-line summary or diagnosis
  std::string last_checkpoint;  ///< path of the newest checkpoint written, if any
};

/// The one-line diagnosis of a failed step (world.step_status), as a run's outcome message gives it.
std::string diagnosis(const World& world, const Model& model);

/// The run folder a checkpoint belongs to: the folder holding its checkpoints/ (also for a bare file name given from
/// inside checkpoints/).
std::filesystem::path checkpoint_run_directory(const std::string& checkpoint_path);

class Simulation {
 public:
  /// Throws SceneError.
  /// `overrides`: --set KEY=VALUE, applied to the scene before it is validated (engine/scene/scene_overrides.hpp).
  static std::unique_ptr<Simulation> from_scene_file(const std::string& path, const SceneLimits& limits = {},
                                                     const std::vector<std::string>& overrides = {});
  static std::unique_ptr<Simulation> from_model(Model model);
  /// Throws CheckpointError, or SceneError if the embedded scene no longer validates.
  static std::unique_ptr<Simulation> from_checkpoint(const std::string& path, const SceneLimits& limits = {});
  /// The same from decoded data (`name` is the file, for messages): the data is validated against its scene first.
  static std::unique_ptr<Simulation> from_checkpoint_data(CheckpointData data, const std::string& name,
                                                          const SceneLimits& limits = {});

  /// Runs to options.until (or run.end_time) writing all outputs into options.out_dir.
  RunOutcome run(const RunOptions& options);

  /// One engine step without any output (for tests and benchmarks).
  void step() { stepper_->step(); }

  const Model& model() const { return *model_; }
  World& world() { return world_; }
  const Stepper& stepper() const { return *stepper_; }
  CheckpointData checkpoint_data() const;
  std::uint64_t checkpoint_step() const { return world_.step; }

  /// A run over several MPI ranks (mpirun -np N): what in `model` keeps it from being spread over them, or "" if
  /// nothing does. Today the grains alone are decomposed (systems/physics/ranks/grain_ranks.hpp): a scene of grains
  /// with contacts, without water (MPS or mean flow), without periodic axes.
  static std::string over_ranks_problem(const Model& model);
  /// Keeps this rank's share of the grains: every rank built the same world (scene or checkpoint), and each keeps the
  /// grains in its box of a recursive bisection (no message needed). The run then exchanges grains every sub-step.
  void split_over_ranks();
  /// True once split_over_ranks has run.
  bool over_ranks() const {
    return (world_.contacts && world_.contacts->ranks.active) ||
           (world_.fluid_neighbours && world_.fluid_neighbours->ranks.active);
  }
  /// The whole world at rank 0, for the outputs of a run over ranks: every rank's grains (ordered by id), a neighbour
  /// list over them with every touching pair's spring, the wall contacts as the ranks had them. Collective; an empty
  /// world on the other ranks. Without `pairs` the list holds the wall contacts alone (what frames and probes read;
  /// a checkpoint and the bed profile's coordination numbers need the pairs, whose list costs a rebuild).
  World gathered_world(bool pairs = true) const;
  /// The checkpoint of `world` (this run's model and output bookkeeping): the gathered world of a run over ranks.
  CheckpointData checkpoint_data_of(const World& world) const;

 private:
  Simulation(Model model, World world, OutputState output);
  /// run() for a run over ranks: every rank steps its grains; rank 0 alone writes, from the gathered world.
  RunOutcome run_over_ranks(const RunOptions& options);

  /// A resumed run in another folder than its checkpoint's: the series before the checkpoint copied into `out`
  /// (carry_earlier_series), and said in the log.
  void carry_series_into(const std::filesystem::path& out) const;

  std::unique_ptr<const Model> model_;
  World world_;
  OutputState output_;
  std::unique_ptr<Stepper> stepper_;
  std::filesystem::path checkpoint_run_dir_;  ///< the run folder of the checkpoint this run resumed from, if any
};

}  // namespace riffle
