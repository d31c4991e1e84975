#pragma once
// Checkpoints: everything needed to continue a run bit for bit, and nothing from the wall clock.
//
// File layout (little-endian):
//   8 bytes  magic "RIFFLECP"
//   4 bytes  format version (kCheckpointVersion)
//   4 bytes  zero
//   8 bytes  payload size in bytes
//   8 bytes  FNV-1a 64 checksum of the payload
//   payload  cereal binary archive of CheckpointData
// Files are written to a temporary file of their own ("<path>.<pid>.<counter>.tmp"), synced and renamed into
// place (engine/output/replace_file.hpp), so a crash never leaves a half-written checkpoint under the real name.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "components/world.hpp"

namespace riffle {

// 2: contacts; 3: fluid and fluid summary; 4: coupling fields; 5: without fluid_summary.last_dt (World::last_step
// holds the step length); 6: the grains' undisturbed fluid velocity, fluid acceleration, added-mass, history and
// lubrication forces, and the history force's state (history_relative_velocity, history_mode_0..7) (FieldInfo::
// since_format: an older file leaves them at their defaults); 7: the fluid's viscous_acceleration and the grains'
// viscous_force ([coupling] viscous_stress); 8: the grains' `fixed` flag ([solids] fixed_below); 9: the mean-flow
// fluid's column (World::mean_flow; absent in older files); 10: the grains' fluctuation_state ([mean_flow]
// fluctuations); 11: the walls' part of the grains' own disturbance (self_induced_wall_x, _y, _z); 12: the fluid
// particles removed by reason and the bulk-velocity controller's integral (FluidSummary); 13: without the pairs'
// forces and torques (Contacts::kLastFormatWithPairForces: the contact pass adds them to the grains directly); 14: the
// history force's implicit mass (history_mass: the kicks take the step's own part of the history force implicitly);
// 15: the contacts' rolling springs (pair_rolling_spring, wall_pair_rolling_spring: [contact] rolling_law =
// "elastic_plastic"; an older file gives zeros).
inline constexpr std::uint32_t kCheckpointVersion = 15;
/// The first format with the mean-flow column.
inline constexpr std::uint32_t kFirstCheckpointVersionWithMeanFlow = 9;
/// The oldest format still read: format 4 differs from 5 only by FluidSummary's last_dt (components/fluid.hpp), and
/// users' settled beds and runs to resume are in it. Reading one gives the same data; writing it back gives format 5.
inline constexpr std::uint32_t kOldestCheckpointVersionRead = 4;

/// Output bookkeeping that must survive a resume so the frame series and diagnostics continue seamlessly.
struct OutputState {
  std::vector<double> frame_times;          ///< [s] time of every VTK frame written so far (frame k = index k)
  std::uint64_t checkpoints_due = 0;        ///< interval checkpoints written so far
  std::vector<std::uint64_t> kept_steps;    ///< steps of the interval checkpoints still on disk, oldest first

  template <class Archive>
  void serialize(Archive& archive) {
    archive(frame_times, checkpoints_due, kept_steps);
  }
};

struct CheckpointData {
  std::string scene_file;  ///< the scene's file, absolute (files it names are relative to it)
  std::string scene_text;  ///< the full scene; the model is rebuilt from it
  World world;
  OutputState output;
  std::uint32_t format = kCheckpointVersion;  ///< the format of the file read (a write always gives the current one)
};

class CheckpointError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// FNV-1a, 64 bit.
std::uint64_t fnv1a64(std::string_view bytes);

/// Serialises `data` into the checkpoint byte format.
std::string encode_checkpoint(const CheckpointData& data);
/// Parses checkpoint bytes of format kOldestCheckpointVersionRead to kCheckpointVersion; `name` is used in messages.
/// Throws CheckpointError for anything but a well-formed file: every length prefix is checked against the bytes left
/// before it is allocated. What the fields say is checked separately, against the scene
/// (engine/output/checkpoint_validation.hpp).
CheckpointData decode_checkpoint(const std::string& bytes, const std::string& name);

/// Writes atomically (unique temporary file, fsync, rename). Throws CheckpointError on I/O failure.
void write_checkpoint(const std::string& path, const CheckpointData& data);
/// Reads and decodes a regular file (a FIFO, a device or a directory is refused at once, without reading).
CheckpointData read_checkpoint(const std::string& path);

}  // namespace riffle
