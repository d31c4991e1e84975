#pragma once
// The immutable description of a run, parsed and validated from a scene file. Systems receive it as const; the
// mutable state lives in the World. A checkpoint stores the scene text, so the model is rebuilt on resume.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "components/vec.hpp"

namespace riffle {

struct Material {
  std::string name;
  double density = 0.0;  ///< [kg/m^3]
};

/// Prescribed rigid translation of the tank. x(t) = -A r(t) sin(2 pi f t) along `direction` (seed 000 Eq. 1),
/// with r(t) a C2 quintic ramp from 0 to 1 over `ramp_time` (the seed's "accelerated gradually at the onset").
struct TankMotionModel {
  enum class Kind { kNone, kSinusoidal };
  Kind kind = Kind::kNone;
  Vec3 direction = Vec3::UnitX();  ///< [1] unit vector
  double amplitude = 0.0;          ///< [m] A
  double frequency = 0.0;          ///< [Hz] f
  double ramp_time = 0.0;          ///< [s] 0 = start at full amplitude
};

struct TankModel {
  Vec3 size = Vec3::Zero();            ///< [m] inner size along x, y, z
  Vec3 origin = Vec3::Zero();          ///< [m] inner min corner at rest
  std::vector<std::string> open_faces; ///< faces without a wall: any of x_min, x_max, y_min, y_max, z_min, z_max
  std::int32_t wall_material = 0;      ///< index into Model::materials
  double domain_margin = 0.0;          ///< [m] a particle further than this outside the swept tank is lost
  TankMotionModel motion;
};

struct SphereSpec {
  Vec3 position = Vec3::Zero();          ///< [m]
  Vec3 velocity = Vec3::Zero();          ///< [m/s]
  Vec3 angular_velocity = Vec3::Zero();  ///< [rad/s]
  double radius = 0.0;                   ///< [m]
  std::int32_t material = 0;
  std::int32_t size_class = 0;
};

struct SolidsModel {
  bool enabled = false;
  std::vector<SphereSpec> spheres;     ///< initial spheres, explicit and generated from blocks, in scene order
  std::int64_t sort_every = 0;         ///< [steps] reorder grains by grid cell this often; 0 = never
};

struct OutputModel {
  double vtk_interval = 0.0;         ///< [s] 0 = no frames
  double checkpoint_interval = 0.0;  ///< [s] 0 = only on signal and at the end
  std::int64_t checkpoint_keep = 3;  ///< newest interval checkpoints kept on disk
  std::int64_t diagnostics_every = 1;  ///< [steps] rows of diagnostics.csv
};

struct Model {
  std::string scene_file;   ///< path as given, for messages
  std::string scene_text;   ///< the full scene text (stored in checkpoints)
  std::string name;         ///< run name

  double end_time = 0.0;             ///< [s]
  double dt = 0.0;                   ///< [s] engine (fluid) step
  std::int64_t solid_substeps = 1;   ///< DEM sub-steps per engine step
  Vec3 gravity = Vec3(0.0, 0.0, -9.81);  ///< [m/s^2]

  std::vector<Material> materials;
  TankModel tank;
  SolidsModel solids;
  OutputModel output;

  double solid_dt() const { return dt / static_cast<double>(solid_substeps); }
};

}  // namespace riffle
