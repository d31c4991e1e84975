#include "engine/scene/scene.hpp"
#include "engine/scene/scene_overrides.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <initializer_list>
#include <map>
#include <optional>

#include "engine/scene/bed_scene.hpp"
#include "engine/scene/output_scene.hpp"
#include "engine/setup/bed_generation.hpp"
#include "engine/setup/budget.hpp"
#include "engine/setup/initial_state.hpp"
#include "systems/physics/time/solid_step.hpp"
#include "engine/scene/fluid_scene.hpp"
#include "engine/scene/mean_flow_scene.hpp"
#include "engine/scene/motion_table.hpp"
#include "systems/physics/math/cubic_spline.hpp"
#include "systems/physics/dem/contact_law.hpp"
#include "systems/physics/coupling/sampling_kernel.hpp"
#include "systems/physics/geometry/periodic_box.hpp"
#include "systems/physics/geometry/tank_kinematics.hpp"
#include "systems/physics/mps/mps_common.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace riffle {

std::int32_t read_material(const Model& model, TableReader& reader, const std::string& key) {
  const std::size_t problems_before = reader.problem_count();
  const std::string name = reader.text(key, std::nullopt);
  for (std::size_t k = 0; k < model.materials.size(); ++k)
    if (model.materials[k].name == name) return static_cast<std::int32_t>(k);
  // text() has already reported a missing or non-string value; anything else (even "") names no material.
  if (reader.problem_count() == problems_before) {
    std::string known;
    for (const Material& material : model.materials) known += (known.empty() ? "" : ", ") + material.name;
    reader.problem(key, "unknown material \"" + name + "\" (materials defined: " +
                            (known.empty() ? "none" : known) + ")");
  }
  return 0;
}

namespace {

/// Why `name` cannot be the default output folder out/<name>, or "" if it can: it must be one plain path
/// component, so that the run writes inside out/ (not "../../..") and the log file can be opened (no NUL).
std::string run_name_problem(const std::string& name) {
  constexpr std::size_t kMaxNameBytes = 200;  // well below NAME_MAX (255), leaving room for suffixes
  if (name.empty()) return "expected a non-empty name (it names the output folder out/<name>)";
  if (name == "." || name == "..") return "\"" + name + "\" is not a folder name (the output goes to out/<name>)";
  if (name.size() > kMaxNameBytes)
    return "expected at most " + std::to_string(kMaxNameBytes) +
           " bytes (it names the output folder out/<name>), got " + std::to_string(name.size());
  for (const char c : name) {
    const auto byte = static_cast<unsigned char>(c);
    if (c == '/' || c == '\\')
      return "expected a plain folder name without '/' or '\\' (the output goes to out/<name>), got \"" + name + "\"";
    if (byte < 0x20 || byte == 0x7f)
      return "expected a name without control characters (NUL, tab, newline...): it names the output folder "
             "out/<name>";
  }
  return "";
}

void read_run(TableReader& run, Model& model, const SceneLimits& limits) {
  model.name = run.text("name", "riffle");
  if (const std::string problem = run_name_problem(model.name); !problem.empty()) run.problem("name", problem);
  // [GiB]; the command line's --memory-limit wins (parse_scene has set it already).
  const double memory_limit = run.number("memory_limit", 0.0, "GiB", Bounds::non_negative());
  if (limits.memory_limit <= 0.0 && memory_limit > 0.0) {
    model.memory_limit = memory_limit * 1024.0 * 1024.0 * 1024.0;
    model.memory_limit_source = "run.memory_limit";
  }
  model.end_time = run.number("end_time", std::nullopt, "s", Bounds::positive());
  model.dt = run.number("dt", std::nullopt, "s", Bounds::positive());
  model.solid_substeps = run.integer("solid_substeps", model.solid_substeps, 1, 1000000);
  model.gravity = run.vec3("gravity", Vec3(0.0, 0.0, -9.81), "m/s^2", Bounds::any());
  if (model.dt > 0.0 && model.end_time > 0.0 && model.end_time / model.dt > 1e12)
    run.problem("dt", "dt is too small for end_time (more than 1e12 steps)");
  // The run loop takes no step when end_time < dt / 2 and overshoots end_time when it is below dt.
  if (model.dt > 0.0 && model.end_time > 0.0 && model.dt > model.end_time)
    run.problem("dt", "dt = " + format_number(model.dt) + " s is longer than end_time = " +
                          format_number(model.end_time) + " s: the run would end before its first step");
  run.finish();
}

void read_materials(TableReader& materials, Model& model, bool contacts_enabled) {
  for (auto& [name, reader] : materials.named_tables()) {
    Material material;
    material.name = name;
    material.density = reader.number("density", std::nullopt, "kg/m^3", Bounds::positive());
    // Elastic constants are required exactly when grains touch: the contact laws and the time-step estimates use them.
    const std::optional<double> no_default = std::nullopt;
    material.young_modulus =
        reader.number("young_modulus", contacts_enabled ? no_default : std::optional<double>(0.0), "Pa",
                      contacts_enabled ? Bounds::positive() : Bounds::non_negative());
    material.poisson_ratio =
        reader.number("poisson_ratio", contacts_enabled ? no_default : std::optional<double>(0.0), "1",
                      Bounds{-1.0, 0.5, false, false});
    reader.finish();
    model.materials.push_back(material);
  }
  if (model.materials.empty()) materials.problem("", "expected at least one [materials.NAME] table");
}

/// A tabulated motion: the CSV named by `file` (relative to the scene file), its spline, and the checks that the run
/// never leaves the table while the tank moves (outside it the tank rests at the end's displacement).
void read_motion_table_keys(TableReader& motion, const Model& scene, TankMotionModel& model) {
  const std::size_t problems_before = motion.problem_count();
  std::filesystem::path path = motion.text("file", std::nullopt);
  motion.finish();
  if (motion.problem_count() != problems_before) return;
  if (path.is_relative()) path = std::filesystem::path(scene.scene_file).parent_path() / path;
  if (const std::string problem = read_motion_table(path.lexically_normal().string(), model.table);
      !problem.empty()) {
    motion.problem("file", problem);
    return;
  }
  const MotionTable& table = model.table;
  for (int axis = 0; axis < 3; ++axis)
    if (!table.displacement[static_cast<std::size_t>(axis)].empty()) {
      model.direction = Vec3::Unit(axis);  // the diagnostics' tank_displacement_m is along the first listed axis
      break;
    }
  // A velocity jump where the run crosses an end of the table: allowed up to 1e-3 of the table's peak speed (the
  // spline through rows at rest has a small ringing slope, not zero).
  double peak = 0.0;
  auto velocity_at = [&](double t) {
    Vec3 velocity = Vec3::Zero();
    for (std::size_t a = 0; a < 3; ++a)
      if (!table.displacement[a].empty())
        velocity[static_cast<int>(a)] = spline_at(table.time, table.displacement[a], table.curvature[a], t).slope;
    return velocity;
  };
  for (const double t : table.time) peak = std::max(peak, velocity_at(t).norm());
  const double allowed = 1e-3 * peak;
  const double start_speed = velocity_at(table.time.front()).norm();
  const double end_speed = velocity_at(table.time.back()).norm();
  char text[512];
  if (table.time.front() > 0.0 && start_speed > allowed) {
    std::snprintf(text, sizeof text,
                  "%s: the table starts at t = %g s, after the run's start (t = 0), with the tank moving at %.3g m/s "
                  "(more than 1e-3 of its peak speed %.3g m/s): the tank rests before the first row, so that would be "
                  "a jump in velocity; start the table at t <= 0 or at rest",
                  table.file.c_str(), table.time.front(), start_speed, peak);
    motion.problem("file", text);
  }
  if (scene.end_time > table.time.back() && end_speed > allowed) {
    std::snprintf(text, sizeof text,
                  "%s: the table ends at t = %g s, before run.end_time = %g s, with the tank moving at %.3g m/s (more "
                  "than 1e-3 of its peak speed %.3g m/s): the tank rests after the last row, so that would be a jump "
                  "in velocity; extend the table to end_time or end it at rest",
                  table.file.c_str(), table.time.back(), scene.end_time, end_speed, peak);
    motion.problem("file", text);
  }
}

void read_motion(TableReader& motion, const Model& scene, TankMotionModel& model) {
  const std::size_t problems_before = motion.problem_count();
  const std::string kind = motion.choice("kind", "none", {"none", "sinusoidal", "table"});
  // With an invalid kind the other keys cannot be judged; calling amplitude etc. "unknown" would mislead.
  if (motion.problem_count() != problems_before) return;
  if (kind == "none") {
    model.kind = TankMotionModel::Kind::kNone;
    motion.finish();
    return;
  }
  if (kind == "table") {
    model.kind = TankMotionModel::Kind::kTable;
    read_motion_table_keys(motion, scene, model);
    return;
  }
  model.kind = TankMotionModel::Kind::kSinusoidal;
  const Vec3 direction = motion.vec3("direction", Vec3::UnitX(), "1", Bounds::any());
  // stableNorm: the plain norm overflows for components near 1e300 (normalising to a zero vector) and
  // underflows to 0 for components near 1e-200, although both give a valid direction.
  const double length = direction.stableNorm();
  if (!(length > 0.0) || !std::isfinite(length))
    motion.problem("direction", "expected a non-zero direction vector");
  else
    model.direction = direction / length;
  model.amplitude = motion.number("amplitude", std::nullopt, "m", Bounds::non_negative());
  model.frequency = motion.number("frequency", std::nullopt, "Hz", Bounds::positive());
  model.ramp_time = motion.number("ramp_time", model.ramp_time, "s", Bounds::non_negative());
  // Degrees, as a phase is usually quoted; -90 turns x = -A sin(wt) into x = A cos(wt).
  model.phase = motion.number("phase", 0.0, "deg", Bounds::closed(-360.0, 360.0)) * (3.14159265358979323846 / 180.0);
  model.start_time = motion.number("start_time", model.start_time, "s", Bounds::non_negative());
  motion.finish();
}

/// [tank] periodic: the axes along which the box repeats (docs/SCENES.md). Such an axis has no walls, so its faces
/// cannot be listed as open, and the tank cannot move along it: a periodic box is the same box one period on, and a
/// shaken one would shake its own images, which no real tank does.
void read_periodic(TableReader& tank, TankModel& model, bool motion_valid) {
  const std::size_t problems_before = tank.problem_count();
  const std::vector<std::string> axes = tank.choices("periodic", {"x", "y"});
  if (tank.problem_count() != problems_before || axes.empty()) return;
  const Vec3 sweep = motion_valid ? tank_motion_sweep(model.motion) : Vec3::Zero();
  for (const std::string& axis_name : axes) {
    const int axis = axis_name == "x" ? 0 : 1;
    model.periodic[static_cast<std::size_t>(axis)] = true;
    for (int side = 0; side < 2; ++side)
      if (model.face_open(axis, side))
        tank.problem("periodic", std::string("the tank is periodic along ") + axis_name + ", which has no walls, so " +
                                     tank_face_name(axis, side) +
                                     " cannot also be listed in open_faces: a face is either open (particles leave "
                                     "through it) or periodic (they come back through the other face)");
    if (sweep[axis] > 0.0)
      tank.problem("periodic", std::string("the tank moves along ") + axis_name + " ([tank.motion]), which is "
                                   "periodic: a periodic box is the same box one period on, so shaking it along that "
                                   "axis would shake only its images; drive the flow instead, or move the tank along "
                                   "another axis");
  }
}

void read_tank(TableReader& tank, Model& model) {
  model.tank.size = tank.vec3("size", std::nullopt, "m", Bounds::positive());
  model.tank.origin = tank.vec3("origin", model.tank.origin, "m", Bounds::any());
  model.tank.open_faces =
      tank.choices("open_faces", std::vector<std::string>(kTankFaceNames.begin(), kTankFaceNames.end()));
  model.tank.wall_material = read_material(model, tank, "wall_material");
  model.tank.domain_margin = tank.number("domain_margin", model.tank.domain_margin, "m", Bounds::non_negative());
  const std::size_t problems_before_motion = tank.problem_count();
  if (auto motion = tank.table("motion", false)) read_motion(*motion, model, model.tank.motion);
  // A motion with problems (say a table that could not be read) has no sweep to judge.
  read_periodic(tank, model.tank, tank.problem_count() == problems_before_motion);
  tank.finish();
}

std::string format_length(double value) {
  std::ostringstream stream;
  stream << value;  // not std::to_string: its fixed 6 decimals print a 1e-7 m diameter as 0.000000
  return stream.str();
}

void read_solids(TableReader& solids, Model& model) {
  model.solids.enabled = true;
  // Without a valid tank size every grain would also be reported as outside the tank, burying the real problem.
  const bool tank_known = (model.tank.size.array() > 0.0).all();
  model.solids.sort_every = solids.integer("sort_every", model.solids.sort_every, 0, 1000000000);
  model.solids.fixed_to_tank = solids.boolean("fixed_to_tank", false);
  // Bounds: a hold beyond a day of simulated time is a typo (no scene here runs a simulated hour).
  if (solids.has("hold_until")) {
    model.solids.hold_until = solids.number("hold_until", std::nullopt, "s", Bounds::closed(0.0, 86400.0));
    if (model.solids.fixed_to_tank)
      solids.problem("hold_until", "fixed_to_tank already holds the grains for the whole run; give one or the other");
  }
  if (solids.has("fixed_below")) {
    // A height in the tank: bounded by the largest tank a scene may describe, as positions are.
    model.solids.fixed_below = solids.number("fixed_below", std::nullopt, "m", Bounds::closed(-1e4, 1e4));
    if (model.solids.fixed_to_tank)
      solids.problem("fixed_below", "fixed_to_tank already holds every grain for the whole run; give one or the other");
  }
  if (solids.has("initial_state")) {
    // Relative to the scene file, so a scene and the run it continues can move together.
    std::filesystem::path path = solids.text("initial_state", "");
    if (path.is_relative()) path = std::filesystem::path(model.scene_file).parent_path() / path;
    model.solids.initial_state = path.lexically_normal().string();
    try {
      model.solids.initial_grains = std::make_shared<const Solids>(read_initial_grains(model));
    } catch (const std::exception& error) {
      solids.problem("initial_state", error.what());
    }
  }
  for (TableReader& sphere : solids.tables("spheres")) {
    SphereSpec spec;
    const std::size_t problems_before = sphere.problem_count();
    spec.position = sphere.vec3("position", std::nullopt, "m", Bounds::any());
    const bool position_known = sphere.problem_count() == problems_before;
    spec.velocity = sphere.vec3("velocity", spec.velocity, "m/s", Bounds::any());
    spec.angular_velocity = sphere.vec3("angular_velocity", spec.angular_velocity, "rad/s", Bounds::any());
    spec.radius = sphere.number("radius", std::nullopt, "m", Bounds::positive());
    spec.material = read_material(model, sphere, "material");
    spec.size_class = static_cast<std::int32_t>(sphere.integer("size_class", 0, 0, 1000));
    spec.fixed = sphere.boolean("fixed", false);
    if (spec.fixed && model.solids.fixed_to_tank)
      sphere.problem("fixed", "fixed_to_tank already holds every grain for the whole run; give one or the other");
    if (tank_known && position_known && spec.radius > 0.0 && !inside_tank(model.tank, spec.position, spec.radius))
      sphere.problem("position", "the sphere does not fit inside the tank at rest (tank spans origin to "
                                 "origin + size)");
    sphere.finish();
    model.solids.spheres.push_back(spec);
  }
  // Blocks in two passes: every block is read and counted first, and the scene's total checked (grain_count_problem)
  // before any is kept, so that blocks each under the per-block cap cannot together exhaust memory. A block is laid
  // out when the run starts (engine/setup/bed_generation.hpp generate_block); its count is exact here.
  struct PlannedBlock {
    TableReader* reader;
    SphereBlockSpec spec;
  };
  std::vector<TableReader> block_readers = solids.tables("blocks");
  std::vector<PlannedBlock> planned;
  double planned_grains = static_cast<double>(model.solids.spheres.size());
  for (TableReader& block : block_readers) {
    const std::size_t problems_before = block.problem_count();
    SphereBlockSpec spec;
    spec.low = block.vec3("min", std::nullopt, "m", Bounds::any());
    const Vec3 high = block.vec3("max", std::nullopt, "m", Bounds::any());
    spec.spacing = block.number("spacing", std::nullopt, "m", Bounds::positive());
    spec.lattice = block.choice("lattice", "cubic", {"cubic", "hexagonal"}) == "hexagonal"
                       ? SphereBlockSpec::Lattice::kHexagonal
                       : SphereBlockSpec::Lattice::kCubic;
    spec.sphere.radius = block.number("radius", std::nullopt, "m", Bounds::positive());
    spec.sphere.velocity = block.vec3("velocity", spec.sphere.velocity, "m/s", Bounds::any());
    spec.sphere.material = read_material(model, block, "material");
    spec.sphere.size_class = static_cast<std::int32_t>(block.integer("size_class", 0, 0, 1000));
    block.finish();
    // A block with a bad key cannot be laid out meaningfully; its problems are already reported.
    if (block.problem_count() != problems_before) continue;
    if (spec.spacing < 2.0 * spec.sphere.radius) {
      block.problem("spacing", "spacing must be at least the sphere diameter (" +
                                   format_length(2 * spec.sphere.radius) + " m) so that generated spheres do not overlap");
      continue;
    }
    const Vec3 extent = high - spec.low;
    if ((extent.array() < 0.0).any()) {
      block.problem("max", "every component of max must be >= the one of min");
      continue;
    }
    const Eigen::Array3d counts = (extent.array() / spec.pitch().array() + 1e-9).floor() + 1.0;
    if (counts.prod() > 5e7) {
      block.problem("spacing", "the block would generate more than 5e7 spheres");
      continue;
    }
    if (!tank_known) continue;
    for (int axis = 0; axis < 3; ++axis)
      spec.counts[static_cast<std::size_t>(axis)] = static_cast<std::int64_t>(counts[axis]);
    planned_grains += counts.prod();
    planned.push_back({&block, spec});
  }
  if (!planned.empty()) {
    const std::string too_many = grain_count_problem(model, planned_grains);
    if (!too_many.empty()) {
      planned.back().reader->problem("spacing", too_many);
      planned.clear();
    }
  }
  for (PlannedBlock& block : planned) {
    block.spec.count = block_sphere_count(block.spec, model.tank);
    if (block.spec.count == 0)
      block.reader->problem("min", "the block places no sphere inside the tank");
    else
      model.solids.blocks.push_back(block.spec);
  }
  read_bed_generators(solids, model);
  solids.finish();
}

}  // namespace

double default_checkpoint_interval(double end_time, double dt) {
  // A long run that dies (a blow-up, an escaped-water limit, a killed machine) must be resumable without the scene
  // having asked for it; a short one gains nothing from checkpoints and pays their writes (and its outputs stay
  // those of a run without checkpoints: every shipped scene is either short or sets the key).
  constexpr double kLongRunSteps = 1000.0;
  constexpr double kCheckpointsPerRun = 10.0;
  if (!(dt > 0.0) || !(end_time > 0.0) || end_time < kLongRunSteps * dt) return 0.0;
  return end_time / kCheckpointsPerRun;
}

namespace {

void read_output(TableReader& output, Model& model) {
  model.output.vtk_interval = output.number("vtk_interval", model.output.vtk_interval, "s", Bounds::non_negative());
  model.output.vtk_pieces = enum_choice(output, "vtk_pieces", model.output.vtk_pieces, OutputModel::kVtkPiecesNames);
  model.output.vtk_encoding =
      enum_choice(output, "vtk_encoding", model.output.vtk_encoding, OutputModel::kVtkEncodingNames);
  model.output.vtk_precision =
      enum_choice(output, "vtk_precision", model.output.vtk_precision, OutputModel::kVtkPrecisionNames);
  model.output.vtk_dummy_particles = output.boolean("vtk_dummy_particles", model.output.vtk_dummy_particles);
  model.output.checkpoint_interval =
      output.number("checkpoint_interval", model.output.checkpoint_interval, "s", Bounds::non_negative());
  model.output.checkpoint_keep = output.integer("checkpoint_keep", model.output.checkpoint_keep, 1, 1000000);
  model.output.diagnostics_every = output.integer("diagnostics_every", model.output.diagnostics_every, 1, 1000000000);
  read_bed_profile_keys(output, model);  // engine/scene/output_scene.cpp
  read_probes(output, model);            // [[output.probes]], engine/scene/output_scene.cpp
  output.finish();
}

/// [contact]: the contact law, its constants per material pair, and the neighbour-list skin.
void read_contact(TableReader& contact, Model& model) {
  ContactModel& out = model.contact;
  out.enabled = true;
  const std::string law = contact.choice("law", "hertz_mindlin", {"hertz_mindlin", "linear_spring_dashpot"});
  out.law = law == "linear_spring_dashpot" ? ContactLaw::kLinearSpringDashpot : ContactLaw::kHertzMindlin;
  ContactPairParameters defaults;
  defaults.restitution = contact.number("restitution", std::nullopt, "1", Bounds::closed(0.0, 1.0));
  defaults.friction = contact.number("friction", std::nullopt, "1", Bounds::non_negative());
  defaults.rolling_friction =
      contact.number("rolling_friction", defaults.rolling_friction, "1", Bounds::non_negative());
  // Ai et al. (2011) model C, or A (seed 003's): systems/physics/dem/contact_law.hpp. The elastic-plastic law is the
  // default because it converges at rest: under torques below its cap it holds a contact still at every sub-step,
  // where the constant torque chatters and lets a bed creep at a speed of first order in the sub-step.
  out.rolling_law = contact.choice("rolling_law", "elastic_plastic", {"constant_torque", "elastic_plastic"}) ==
                            "elastic_plastic"
                        ? RollingLaw::kElasticPlastic
                        : RollingLaw::kConstantTorque;
  if (out.law == ContactLaw::kLinearSpringDashpot)
    out.collision_time = contact.number("collision_time", std::nullopt, "s", Bounds::positive());
  out.max_impact_speed = contact.number("max_impact_speed", out.max_impact_speed, "m/s", Bounds::positive());
  out.rayleigh_fraction =
      contact.number("rayleigh_fraction", out.rayleigh_fraction, "1", Bounds{0.0, 1.0, false, true});
  out.steps_per_collision =
      contact.number("steps_per_collision", out.steps_per_collision, "1", Bounds::closed(4.0, 1e6));
  // At least 1e-3: e = 0 is calibrated as half the tolerance, and the scaled collision of a smaller restitution is
  // so overdamped that it does not end within achieved_restitution's integration (the scene fuzzer found e = 5e-309).
  out.restitution_tolerance =
      contact.number("restitution_tolerance", out.restitution_tolerance, "1", Bounds::closed(1e-3, 0.5));
  out.skin = contact.number("skin", out.skin, "m", Bounds::non_negative());
  out.sort_every_rebuild = contact.integer("sort_every_rebuild", out.sort_every_rebuild, 1, 1000000);

  const std::size_t count = model.materials.size();
  out.material_count = count;
  out.pairs.assign(count * count, defaults);
  for (TableReader& override_table : contact.tables("pairs")) {
    const std::vector<std::string> names = override_table.choices("materials", [&] {
      std::vector<std::string> known;
      for (const Material& material : model.materials) known.push_back(material.name);
      return known;
    }(), "the material names");
    ContactPairParameters pair = defaults;
    pair.restitution = override_table.number("restitution", defaults.restitution, "1", Bounds::closed(0.0, 1.0));
    pair.friction = override_table.number("friction", defaults.friction, "1", Bounds::non_negative());
    pair.rolling_friction =
        override_table.number("rolling_friction", defaults.rolling_friction, "1", Bounds::non_negative());
    override_table.finish();
    if (names.size() != 2 && !(names.size() == 1)) {
      override_table.problem("materials", "expected the names of two materials (or one, for a material with itself)");
      continue;
    }
    auto index_of = [&](const std::string& name) {
      for (std::size_t k = 0; k < count; ++k)
        if (model.materials[k].name == name) return k;
      return std::size_t{0};
    };
    const std::size_t a = index_of(names.front()), b = index_of(names.back());
    out.pairs[a * count + b] = pair;
    out.pairs[b * count + a] = pair;
  }
  contact.finish();

  // Derived constants: effective moduli and the damping calibrated to the requested restitution. The calibration
  // integrates a collision ODE (a few ms), so it runs once per distinct restitution, not once per material pair.
  std::map<double, double> damping_for_restitution;
  for (std::size_t a = 0; a < count; ++a)
    for (std::size_t b = 0; b < count; ++b) {
      ContactPairParameters& pair = out.pairs[a * count + b];
      const Material& first = model.materials[a];
      const Material& second = model.materials[b];
      if (first.young_modulus <= 0.0 || second.young_modulus <= 0.0) continue;  // reported by read_materials
      const double shear_first = first.young_modulus / (2.0 * (1.0 + first.poisson_ratio));
      const double shear_second = second.young_modulus / (2.0 * (1.0 + second.poisson_ratio));
      pair.effective_young = 1.0 / ((1.0 - first.poisson_ratio * first.poisson_ratio) / first.young_modulus +
                                    (1.0 - second.poisson_ratio * second.poisson_ratio) / second.young_modulus);
      pair.effective_shear =
          1.0 / ((2.0 - first.poisson_ratio) / shear_first + (2.0 - second.poisson_ratio) / shear_second);
      if (pair.restitution >= 0.0 && pair.restitution <= 1.0) {
        // Perfectly plastic (e = 0) needs an infinite dashpot: aim at half the tolerance instead, so that the
        // achieved restitution, checked at the chosen sub-step, is within the tolerance of 0.
        // A restitution below half the tolerance is calibrated as half the tolerance: within the tolerance of what was
        // asked, and a collision that ends.
        pair.calibrated_restitution = std::max(pair.restitution, 0.5 * out.restitution_tolerance);
        auto [cached, inserted] = damping_for_restitution.emplace(pair.calibrated_restitution, 0.0);
        if (inserted) cached->second = calibrate_damping(out.law, pair.calibrated_restitution);
        pair.damping = cached->second;
      }
      prepare_contact_pair(pair, out.law, out.collision_time);
    }
}

/// The reader of a sub-table for reporting a problem in it (the table was read and finished already).
std::optional<TableReader> table_at(TableReader& scene, std::initializer_list<const char*> path) {
  std::optional<TableReader> reader = scene.table(*path.begin(), false);
  for (auto it = path.begin() + 1; reader && it != path.end(); ++it) reader = reader->table(*it, false);
  return reader;
}

/// A periodic box ([tank] periodic) as a whole: grains cross its seams through the contact list's halo, the MPS
/// fluid through the neighbour lists' halo; each needs every period longer than twice its list's reach (so that a
/// particle meets one image of another, never its own: systems/physics/geometry/periodic_box.hpp). Grains and water together
/// are coupled across the seam through the grains' images (systems/coupling/, docs/COUPLING.md): the period must
/// also exceed twice the largest sampling radius r + r_e.
void check_periodic(TableReader& scene, const Model& model) {
  if (!model.tank.any_periodic()) return;
  auto tank = table_at(scene, {"tank"});
  if (!tank) return;
  if (model.fluid.enabled) {
    const double reach = model.fluid.effective_radius() + model.fluid.neighbour_skin_ratio * model.fluid.spacing;
    if (!periodic_cutoff_fits(periodic_box(model), reach)) {
      char text[512];
      std::snprintf(text, sizeof text,
                    "a periodic period must exceed twice the fluid neighbour lists' reach (r_e + skin = %g m), so "
                    "that a particle never meets two images of one neighbour or its own: make tank.size along the "
                    "periodic axes larger than %g m",
                    reach, 2.0 * reach);
      tank->problem("periodic", text);
      return;
    }
    if (!model.solids.enabled) return;
  }
  if (model.solids.enabled && !model.contact.enabled) {
    tank->problem("periodic", "periodic grains need [contact]: the contact list's rebuild is where grains are wrapped "
                              "into the box and their ghosts across the seam are built");
    return;
  }
  // Every grain the run starts with, generated beds and a settled bed ([solids] initial_state) included.
  const GrainSizes sizes = scene_grain_sizes(model.solids);
  const double smallest = sizes.smallest_radius, largest = sizes.largest_radius;
  if (!(largest > 0.0)) return;
  const double skin = model.contact.skin > 0.0 ? model.contact.skin : 0.5 * smallest;  // default_skin
  const double reach = 2.0 * largest + skin;
  if (!periodic_cutoff_fits(periodic_box(model), reach)) {
    char text[512];
    std::snprintf(text, sizeof text,
                  "a periodic period must exceed twice the contact list's reach (largest diameter + skin = %g m), "
                  "so that a grain never meets two images of one neighbour or its own: make tank.size along the "
                  "periodic axes larger than %g m",
                  reach, 2.0 * reach);
    tank->problem("periodic", text);
    return;
  }
  if (!model.fluid.enabled) return;
  // A grain samples the water (and spreads its drag back) within r + r_e (with the self-induced correction a dilute
  // grain's kernel is no narrower than at l0 = r: coupling_kernel_radius), through its images across the seams: one
  // image per axis, never two, only while the period exceeds twice that radius.
  const double sampling =
      coupling_kernel_radius(largest, model.fluid.effective_radius(), model.fluid.spacing,
                             model.coupling.self_induced_velocity);
  if (!periodic_cutoff_fits(periodic_box(model), sampling)) {
    char text[512];
    std::snprintf(text, sizeof text,
                  "a periodic period must exceed twice the grains' sampling radius of the water (largest radius + "
                  "r_e, or a dilute grain's kernel: %g m), so that a grain never samples two images of one fluid "
                  "particle: make tank.size along the periodic axes larger than %g m",
                  sampling, 2.0 * sampling);
    tank->problem("periodic", text);
  }
}

/// Scene-wide limits, judged from the budget before any particle is laid out (engine/setup/budget.hpp): the totals over
/// the per-block caps, the memory estimate against the limit, and a contact skin that would make every grain list
/// every other one.
void check_budget(TableReader& scene, const Model& model) {
  const SceneBudget budget = estimate_budget(model);
  char text[512];
  const GrainSizes sizes = scene_grain_sizes(model.solids);
  if (model.contact.enabled && model.contact.skin > 0.0 && sizes.count > 0) {
    const double largest = sizes.largest_radius;
    // Beyond a diameter the skin buys no fewer rebuilds worth having, and each grain lists ~(skin / r)^3 others.
    if (model.contact.skin > 4.0 * largest) {
      std::snprintf(text, sizeof text,
                    "a skin of %g m is more than twice the largest grain diameter (%g m): every grain would list "
                    "every grain within it (an estimated %.3g pairs) and each step would crawl; leave it out (half "
                    "the smallest radius) or keep it below a grain diameter",
                    model.contact.skin, 2.0 * largest, budget.grain_pairs);
      if (auto contact = table_at(scene, {"contact"})) contact->problem("skin", text);
      return;
    }
  }
  const double mps = budget.fluid_particles + budget.wall_particles + budget.dummy_particles;
  if (mps > kMaxSceneFluidParticles) {
    std::snprintf(text, sizeof text,
                  "the scene would have %.4g MPS particles (%.4g fluid, %.4g wall, %.4g dummy), more than the 5e7 a "
                  "scene may have; coarsen the spacing",
                  mps, budget.fluid_particles, budget.wall_particles, budget.dummy_particles);
    if (auto fluid = table_at(scene, {"fluid"})) fluid->problem("spacing", text);
    return;
  }
  if (budget.grains > std::min(kMaxSceneGrains, model.max_grains)) {
    if (auto solids = table_at(scene, {"solids"}))
      solids->problem("", grain_count_problem(model, budget.grains));
    return;
  }
  if (!(budget.bytes > effective_memory_limit(model))) return;
  std::snprintf(text, sizeof text,
                "the scene needs an estimated %s: grains %s (%.4g grains, %.3g pairs), MPS particles %s (%.4g "
                "particles, %.3g neighbour entries), grids %s (%.3g voidage nodes); ",
                format_bytes(budget.bytes).c_str(), format_bytes(budget.grain_bytes).c_str(), budget.grains,
                budget.grain_pairs, format_bytes(budget.fluid_bytes).c_str(), mps, budget.fluid_neighbours,
                format_bytes(budget.grid_bytes).c_str(), budget.voidage_nodes);
  const std::string message = text + memory_limit_advice(model);
  // Blame the key behind the largest part.
  std::optional<TableReader> blamed;
  std::string key;
  if (budget.fluid_bytes >= budget.grain_bytes && budget.fluid_bytes >= budget.grid_bytes) {
    blamed = table_at(scene, {"fluid"}), key = "spacing";
  } else if (budget.grain_bytes >= budget.grid_bytes) {
    const bool pairs = budget.grain_pair_bytes > 0.5 * budget.grain_bytes && model.contact.skin > 0.0;
    blamed = pairs ? table_at(scene, {"contact"}) : table_at(scene, {"solids"}), key = pairs ? "skin" : "";
  } else if (model.tank.motion.kind != TankMotionModel::Kind::kNone) {
    blamed = table_at(scene, {"tank", "motion"}),
    key = model.tank.motion.kind == TankMotionModel::Kind::kTable ? "file" : "amplitude";
  } else {
    blamed = table_at(scene, {"tank"}), key = "size";
  }
  if (blamed)
    blamed->problem(key, message);
  else
    scene.problem("", message);
}

}  // namespace

/// [coupling]: grains and fluid together (seed 000 Secs. 3.2-3.3; numerics.md 5).
/// [coupling] lubrication keys: each length in reduced radii (`lubrication_cutoff`, `roughness`) or in metres
/// (`lubrication_cutoff_m`, `roughness_m`), not both.
void read_lubrication(TableReader& coupling, Model& model) {
  CouplingModel& out = model.coupling;
  out.lubrication = coupling.boolean("lubrication", false);
  const auto length = [&](const std::string& key, double fallback, double& value, bool& absolute) {
    const std::string metres = key + "_m";
    if (coupling.has(key) && coupling.has(metres)) {
      coupling.number(key, fallback, "1", Bounds::positive());  // read, so that only this problem is reported
      coupling.problem(metres, "give " + key + " (in reduced radii) or " + metres + " (in metres), not both");
    }
    absolute = coupling.has(metres);
    value = absolute ? coupling.number(metres, 0.0, "m", Bounds::positive())
                     : coupling.number(key, fallback, "1", Bounds::positive());
  };
  length("lubrication_cutoff", 1.0, out.lubrication_cutoff, out.lubrication_cutoff_absolute);
  length("roughness", 1.0e-3, out.roughness, out.roughness_absolute);
  if (out.lubrication_cutoff_absolute == out.roughness_absolute && out.roughness >= out.lubrication_cutoff)
    coupling.problem(out.roughness_absolute ? "roughness_m" : "roughness",
                     "the roughness must be below the lubrication cut-off");
  if (out.lubrication && !model.contact.enabled)
    coupling.problem("lubrication", "lubrication needs [contact] (it uses the contacts' neighbour list)");
}

namespace {

/// The [coupling] defaults a scene gets that depend on the rest of the scene (a Model built in code starts with
/// these off): the grain's undisturbed velocity, on wherever it holds (the MPS water, where a grain reads the water
/// its own drag set moving, more so as l0 shrinks, with the isotropic kernel its integrals are for; the mean-flow
/// fluid's plane average holds no grain's own disturbance), and added mass with the MPS water (every grain that
/// accelerates against the water carries it: a heavy grain in a shaken tank moves 20 % too far without it, and it is
/// capped where the bed's water could not take its reaction; the mean-flow fluid has no acceleration to give it), and
/// the shear lift with the mean-flow fluid (without it a bed starts moving at 1.68 times the Shields threshold, with
/// it at 1.24-1.26, the same at 400 and 800 cells: docs/cases/bedload.md; the MPS water's kernel is wider than a grain
/// and cannot give the velocity across one).
bool default_self_induced_velocity(const Model& model, double sampling_vertical_radius) {
  return model.fluid.enabled && sampling_vertical_radius == 0.0;
}
bool default_added_mass(const Model& model) { return model.fluid.enabled; }
// The history force needs the slip of the undisturbed water (the self-induced correction) and belongs with the added
// mass (both are the unsteady part of Maxey & Riley's equation): on where both are.
bool default_history_force(const Model& model, bool added_mass, bool self_induced_velocity) {
  return model.fluid.enabled && added_mass && self_induced_velocity && model.dt * 10.0 <= CouplingModel{}.history_window;
}
bool default_lift(const Model& model) { return model.mean_flow.enabled; }

}  // namespace

void read_coupling(TableReader& coupling, Model& model) {
  CouplingModel& out = model.coupling;
  out.drag = coupling.boolean("drag", true);
  out.pressure_gradient = coupling.boolean("pressure_gradient", true);
  out.viscous_stress = coupling.boolean("viscous_stress", false);
  out.voidage_radius = coupling.number("voidage_radius", out.voidage_radius, "m", Bounds::non_negative());
  out.voidage_vertical_radius =
      coupling.number("voidage_vertical_radius", out.voidage_vertical_radius, "m", Bounds::non_negative());
  out.voidage_volume = enum_choice(coupling, "voidage_volume", out.voidage_volume, CouplingModel::kVoidageVolumeNames);
  const bool over_tank = out.voidage_volume == CouplingModel::VoidageVolume::kTank;
  // Cells narrower than about 3 l0 see the water's layers one by one: the fluid deposit then ripples with the lattice
  // (numerics 5.3), which the tank's volume does not.
  if (!over_tank && model.fluid.enabled && out.voidage_vertical_radius > 0.0 &&
      out.voidage_vertical_radius < 3.0 * model.fluid.spacing)
    coupling.problem("voidage_vertical_radius", "below 3 l0 (" + std::to_string(3.0 * model.fluid.spacing) +
                                                    " m) the fluid particles' layers alias on the voidage grid; set "
                                                    "voidage_volume = \"tank\"");
  // Over the tank's volume any width is exact, but a kernel far thinner than the tank would need more cells across it
  // than the grid may hold (4096 nodes an axis: grains beyond pile onto its last node), and one thicker than the tank
  // covers no node fully: both are typing errors, not beds.
  const double tank_height = model.tank.size.z();
  if (over_tank && out.voidage_vertical_radius > 0.0 &&
      (out.voidage_vertical_radius < tank_height / 2000.0 || out.voidage_vertical_radius > tank_height))
    coupling.problem("voidage_vertical_radius", "must lie between the tank's height / 2000 (" +
                                                    std::to_string(tank_height / 2000.0) + " m) and its height (" +
                                                    std::to_string(tank_height) + " m)");
  out.min_voidage = coupling.number("min_voidage", out.min_voidage, "1", Bounds::closed(0.0, 1.0));
  out.drag_number = coupling.number("drag_number", out.drag_number, "1", Bounds::non_negative());
  out.voidage_estimate =
      enum_choice(coupling, "voidage_estimate", out.voidage_estimate, CouplingModel::kVoidageEstimateNames);
  out.ergun_inertial_exponent =
      coupling.number("ergun_inertial_exponent", out.ergun_inertial_exponent, "1", Bounds::closed(0.0, 4.0));
  out.newton_drag_coefficient =
      coupling.number("newton_drag_coefficient", out.newton_drag_coefficient, "1", Bounds::positive());
  read_lubrication(coupling, model);
  out.added_mass = coupling.boolean("added_mass", default_added_mass(model));
  out.dense_drag = enum_choice(coupling, "dense_drag", out.dense_drag, CouplingModel::kDenseDragNames);
  out.fluid_velocity = enum_choice(coupling, "fluid_velocity", out.fluid_velocity, CouplingModel::kFluidVelocityNames);
  out.lift = coupling.boolean("lift", default_lift(model));
  if (out.lift) {
    out.lift_coefficient = coupling.number("lift_coefficient", out.lift_coefficient, "1", Bounds::closed(0.0, 10.0));
    if (!model.mean_flow.enabled)
      coupling.problem("lift", "the shear lift reads the velocity across a grain from the mean-flow fluid's column: "
                               "it needs [mean_flow] (the MPS water's sampling kernel is wider than a grain)");
  }
  out.sampling_kernel_reaction =
      coupling.choice("drag_reaction", "grid", {"grid", "sampling_kernel"}) == "sampling_kernel";
  out.sampling_vertical_radius =
      coupling.number("sampling_vertical_radius", out.sampling_vertical_radius, "m", Bounds::non_negative());
  out.self_induced_velocity = coupling.boolean("self_induced_velocity",
                                               default_self_induced_velocity(model, out.sampling_vertical_radius));
  // Fewer than one layer of water across the kernel leaves a grain reading one or two particles.
  if (model.fluid.enabled && out.sampling_vertical_radius > 0.0 && out.sampling_vertical_radius < model.fluid.spacing)
    coupling.problem("sampling_vertical_radius", "below l0 (" + std::to_string(model.fluid.spacing) +
                                                     " m) a grain's kernel holds one or two layers of water");
  // The correction's analytic overlap <rho_s rho_w> and <1/r> are those of the isotropic kernel.
  if (out.self_induced_velocity && out.sampling_vertical_radius > 0.0)
    coupling.problem("sampling_vertical_radius", "self_induced_velocity assumes the isotropic sampling kernel; "
                                                 "leave sampling_vertical_radius at 0 with it");
  out.history_force =
      coupling.boolean("history_force", default_history_force(model, out.added_mass, out.self_induced_velocity));
  out.history_kernel =
      enum_choice(coupling, "history_kernel", out.history_kernel, CouplingModel::kHistoryKernelNames);
  out.history_window = coupling.number("history_window", out.history_window, "s", Bounds::positive());
  // The modes resolve the kernel from the fluid step up: a window of a few steps would be no history at all.
  if (out.history_force && out.history_window < 10.0 * model.dt)
    coupling.problem("history_window", "must be at least 10 run.dt (" + std::to_string(10.0 * model.dt) + " s)");
  if (!out.enabled)
    coupling.problem("drag", "[coupling] needs [solids] and a fluid ([fluid] or [mean_flow]) in the scene");
  coupling.finish();
}

Model parse_scene(const std::string& text, const std::string& file_name, const SceneLimits& limits,
                  const std::vector<std::string>& overrides, SceneKeyCatalogue* catalogue) {
  SceneProblems problems{file_name, {}, catalogue};
  std::optional<toml::table> root = parse_toml(text, problems);
  if (!root) throw SceneError(problems.lines);
  if (!overrides.empty()) {
    // A malformed override is reported and skipped; the scene is still read, so every problem shows at once.
    apply_scene_overrides(*root, overrides, problems);  // engine/scene/scene_overrides.hpp
  }

  Model model;
  model.scene_file = file_name;
  model.scene_text = overrides.empty() ? text : scene_text_with_overrides(*root, file_name, overrides);
  TableReader scene(*root, "", problems);
  std::optional<TableReader> run = scene.table("run", true);
  model.memory_limit = limits.memory_limit > 0.0 ? limits.memory_limit : default_memory_limit();
  model.memory_limit_source = limits.memory_limit > 0.0 ? "--memory-limit" : "the default, 3/4 of physical memory";
  model.max_grains = limits.max_grains;
  if (run) read_run(*run, model, limits);
  // Materials first: the tank, the contacts and the solids refer to them by name.
  if (auto materials = scene.table("materials", true)) read_materials(*materials, model, scene.has("contact"));
  if (auto tank = scene.table("tank", true)) read_tank(*tank, model);
  if (auto contact = scene.table("contact", false)) read_contact(*contact, model);
  if (auto solids = scene.table("solids", false)) read_solids(*solids, model);
  if (auto fluid = scene.table("fluid", false)) read_fluid(*fluid, model);  // engine/scene/fluid_scene.cpp
  if (auto flow = scene.table("mean_flow", false)) read_mean_flow(*flow, model);  // engine/scene/mean_flow_scene.cpp
  model.coupling.enabled = model.solids.enabled && (model.fluid.enabled || model.mean_flow.enabled);
  if (auto coupling = scene.table("coupling", false)) {
    read_coupling(*coupling, model);
  } else if (model.coupling.enabled) {  // the same defaults as an empty [coupling] table
    model.coupling.self_induced_velocity = default_self_induced_velocity(model, model.coupling.sampling_vertical_radius);
    model.coupling.added_mass = default_added_mass(model);
    model.coupling.history_force =
        default_history_force(model, model.coupling.added_mass, model.coupling.self_induced_velocity);
    model.coupling.lift = default_lift(model);
  }
  settle_mean_flow_coupling(scene, model);
  bool checkpoint_interval_given = false;
  if (auto output = scene.table("output", false)) {
    checkpoint_interval_given = output->has("checkpoint_interval");
    read_output(*output, model);
  }
  if (!checkpoint_interval_given)
    model.output.checkpoint_interval = default_checkpoint_interval(model.end_time, model.dt);
  scene.finish();
  // The budget judges the scene as a whole, so only once every part of it is valid.
  if (problems.lines.empty()) check_periodic(scene, model);
  if (problems.lines.empty()) check_budget(scene, model);
  if (!problems.lines.empty()) throw SceneError(problems.lines);

  // What the MPS operators derive from l0 and r_e / l0, once, for every system and probe that needs it.
  if (model.fluid.enabled) fill_mps_constants(model.fluid);

  // The DEM sub-step: chosen from the stability estimates, or checked against them when the scene sets it.
  if (model.contact.enabled && model.solids.enabled &&
      (scene_sphere_count(model.solids) > 0 || !model.solids.initial_state.empty())) {
    std::vector<DesignImpact> impacts;
    const StableStep stable = stable_solid_step(model, impacts);
    model.contact.stable_solid_dt = stable.solid_dt;
    model.contact.stable_solid_dt_reason = stable.reason;
    // In floating point first: an absurd material or grain (E = 1e308, a 1e-300 m grain) must not overflow the count.
    const double needed = std::ceil(model.dt / stable.solid_dt * (1.0 - 1e-12));
    constexpr double kMaxSubsteps = 1e6;  // the most run.solid_substeps accepts
    const char* key = run && run->has("solid_substeps") ? "solid_substeps" : "dt";
    char message[768];
    if (!(stable.solid_dt > 0.0) || !(needed <= kMaxSubsteps)) {
      std::snprintf(message, sizeof message,
                    "the stable DEM sub-step %.4g s (%s) would need %.4g sub-steps per engine step of dt = %.4g s, "
                    "more than %g: lower run.dt, or check the materials' young_modulus, the grain radii and "
                    "contact.max_impact_speed",
                    stable.solid_dt, stable.reason.c_str(), needed, model.dt, kMaxSubsteps);
      if (run) run->problem(key, message);
      throw SceneError(problems.lines);
    }
    if (run && run->has("solid_substeps")) {
      if (model.solid_dt() > stable.solid_dt * (1.0 + 1e-12)) {
        std::snprintf(message, sizeof message,
                      "the sub-step dt / solid_substeps = %.4g s exceeds the stable estimate %.4g s (%s); use "
                      "solid_substeps >= %lld or leave it out to have it chosen",
                      model.solid_dt(), stable.solid_dt, stable.reason.c_str(), static_cast<long long>(needed));
        run->problem("solid_substeps", message);
        throw SceneError(problems.lines);
      }
    } else {
      model.solid_substeps = std::max<std::int64_t>(1, static_cast<std::int64_t>(needed));
    }
    // What the run will achieve, for `riffle check` and the log.
    const RestitutionError achieved = worst_design_impact_error(model.contact, impacts, model.solid_dt());
    model.contact.restitution_error = achieved.error;
    model.contact.restitution_error_pair = achieved.impact;
  }
  return model;
}

std::string read_scene_text(const std::string& path) {
  // stat before opening: a FIFO would block in open() or read forever, /dev/zero or a huge file would fill memory,
  // and a directory opens and reads as empty text ("missing required table [run]" would mislead).
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0)
    throw SceneError({path + ": cannot open the scene file (does it exist and is it readable?)"});
  if (S_ISDIR(info.st_mode)) throw SceneError({path + ": is a directory, not a scene file"});
  if (!S_ISREG(info.st_mode))
    throw SceneError({path + ": is not a regular file (a FIFO, device or socket); a scene must be a regular file"});
  if (static_cast<std::uint64_t>(info.st_size) > kMaxSceneFileBytes)
    throw SceneError({path + ": the scene file is " + std::to_string(info.st_size) + " bytes, more than the " +
                      std::to_string(kMaxSceneFileBytes) + " (16 MiB) a scene may have"});
  std::ifstream file(path, std::ios::binary);
  if (!file) throw SceneError({path + ": cannot open the scene file (does it exist and is it readable?)"});
  // Read in chunks and stop one chunk past the cap: the file may have grown (or been swapped) since stat.
  std::string text;
  text.reserve(static_cast<std::size_t>(info.st_size));
  char chunk[1 << 16];
  while (file && text.size() <= kMaxSceneFileBytes) {
    file.read(chunk, sizeof chunk);
    text.append(chunk, static_cast<std::size_t>(file.gcount()));
  }
  if (file.bad()) throw SceneError({path + ": error while reading the scene file"});
  if (text.size() > kMaxSceneFileBytes)
    throw SceneError({path + ": the scene file grew past " + std::to_string(kMaxSceneFileBytes) +
                      " bytes (16 MiB) while it was read"});
  return text;
}

Model load_scene_file(const std::string& path, const SceneLimits& limits, const std::vector<std::string>& overrides,
                      SceneKeyCatalogue* catalogue) {
  return parse_scene(read_scene_text(path), path, limits, overrides, catalogue);
}

}  // namespace riffle
