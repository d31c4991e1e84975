#include "engine/setup/initial_state.hpp"
#include "engine/setup/mean_flow_column.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <vector>

#include <spdlog/spdlog.h>

#include "engine/output/checkpoint.hpp"
#include "engine/setup/bed_generation.hpp"
#include "engine/output/checkpoint_validation.hpp"
#include "engine/setup/fluid_layout.hpp"
#include "engine/toml/scene_reader.hpp"
#include "systems/physics/mps/initial_profile.hpp"
#include "systems/physics/mps/particle_packing.hpp"
#include "systems/physics/geometry/periodic_box.hpp"
#include "systems/physics/geometry/tank_kinematics.hpp"

namespace riffle {

Walls tank_walls(const TankModel& tank) {
  Walls walls;
  const Vec3 centre = tank.origin + 0.5 * tank.size;
  const Vec3 half = 0.5 * tank.size;
  for (int axis = 0; axis < 3; ++axis) {
    const int u_axis = (axis + 1) % 3;
    const int v_axis = (axis + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      if (tank.face_open(axis, side)) continue;
      const std::string& name = tank_face_name(axis, side);
      if (tank.periodic[static_cast<std::size_t>(axis)]) continue;  // a periodic axis has no walls
      const double sign = side == 0 ? -1.0 : 1.0;
      Vec3 face_centre = centre;
      face_centre[axis] += sign * half[axis];
      const Vec3 inward = -sign * Vec3::Unit(axis);
      walls.add(name, face_centre, inward, half[u_axis] * Vec3::Unit(u_axis), half[v_axis] * Vec3::Unit(v_axis), true,
                tank.wall_material);
    }
  }
  return walls;
}

Solids read_initial_grains(const Model& model) {
  const std::string& path = model.solids.initial_state;
  CheckpointData data = read_checkpoint(path);
  if (!data.world.solids) throw std::runtime_error(path + ": the checkpoint holds no grains");
  // Material indices follow the order of [materials.*] in the scene that wrote the checkpoint: map them by name.
  SceneProblems problems{data.scene_file, {}};
  const std::optional<toml::table> root = parse_toml(data.scene_text, problems);
  const toml::table* materials = root ? (*root)["materials"].as_table() : nullptr;
  if (!materials) throw std::runtime_error(path + ": the checkpoint's scene has no readable [materials]");
  std::vector<std::int32_t> mapped;
  for (auto&& entry : *materials) {
    // A named variable, not a structured binding: clang before 16 cannot capture those in a lambda.
    const std::string_view name = entry.first.str();
    const auto found = std::find_if(model.materials.begin(), model.materials.end(),
                                    [&](const Material& material) { return material.name == name; });
    if (found == model.materials.end())
      throw std::runtime_error(path + ": its grains use material \"" + std::string(name) +
                               "\", which this scene does not define");
    mapped.push_back(static_cast<std::int32_t>(found - model.materials.begin()));
  }
  Solids grains = std::move(*data.world.solids);
  // Checked against the scene that wrote them before anything is taken from them (engine/output/checkpoint_validation.hpp).
  validate_grains(grains, mapped.size(), path);
  for (std::size_t i = 0; i < grains.size(); ++i) {
    grains.material[i] = mapped[static_cast<std::size_t>(grains.material[i])];
    // Mass and inertia follow this scene's density, so a material may be redefined between runs.
    const double density = model.materials[static_cast<std::size_t>(grains.material[i])].density;
    const double r = grains.radius[i];
    grains.mass[i] = density * 4.0 / 3.0 * 3.14159265358979323846 * r * r * r;
    grains.moment_of_inertia[i] = 0.4 * grains.mass[i] * r * r;
    grains.force[i] = grains.torque[i] = grains.contact_force[i] = grains.contact_torque[i] = Vec3::Zero();
  }
  // Again with this scene's densities: a tiny radius can leave a mass or an inertia that underflows to zero.
  validate_grains(grains, model.materials.size(), path);
  return grains;
}

namespace {

/// The water moved off the lattice (docs/FLUID.md, "A packed start"): its particles with a complete kernel are
/// packed around the walls, dummies and the surface water, which stay put; a [fluid.initial_velocity] profile is
/// re-read at each moved particle's new height.
void pack_initial_fluid(const Model& model, const TankMotion& tank, FluidParticles& particles) {
  const FluidModel& fluid = model.fluid;
  std::vector<char> movable(particles.size());
  for (std::size_t i = 0; i < particles.size(); ++i)
    movable[i] = particles.kind[i] == static_cast<std::int32_t>(FluidKind::kFluid) ? 1 : 0;
  PeriodicBox box = periodic_box(model);
  box.low += tank.displacement;
  PackingSettings settings;
  settings.spacing = fluid.spacing;
  settings.effective_radius = fluid.effective_radius();
  std::vector<Vec3> positions = particles.position;
  const PackingReport report = pack_particles(positions, movable, box, settings);
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (!movable[i]) continue;
    const double before = particles.position[i].z() - tank.displacement.z();
    const double after = positions[i].z() - tank.displacement.z();
    particles.velocity[i].x() += initial_profile_velocity(fluid.initial_velocity, after) -
                                 initial_profile_velocity(fluid.initial_velocity, before);
    particles.position[i] = positions[i];
  }
  const double floor = packed_start_viscosity_floor(fluid.spacing, model.gravity.norm());
  if (packed_water_may_not_rest(fluid.kinematic_viscosity, fluid.scatter_viscosity, fluid.spacing,
                                 model.gravity.norm()))
    spdlog::warn("packed start in a liquid of nu = {:.3g} m^2/s, below 0.01 l0 sqrt(g l0) = {:.3g} m^2/s: packed water "
                 "at rest may not come to rest; [fluid] scatter_viscosity = 2 holds it (docs/FLUID.md, \"A packed "
                 "start\")",
                 fluid.kinematic_viscosity, floor);
  spdlog::info("packed start: {} of the water's particles moved off the lattice (mean {:.3f} l0 from their sites); "
               "their number density's RMS deviation {:.4f} after the random offset, {:.4f} after packing",
               report.moved, report.mean_offset, report.spread_after_offset, report.spread_after_packing);
}

}  // namespace

FluidParticles initial_fluid(const Model& model, const TankMotion& tank) {
  const FluidModel& fluid = model.fluid;
  const Vec3& origin = model.tank.origin;
  FluidParticles particles;
  // Grains coupled to the water sample its pressure gradient before the first pressure solve (a new run's initial
  // forces): it starts as that of water at rest, rho g, so that they feel their buoyancy from the first sub-step
  // (with a zero gradient they fell freely for one fluid step, and a neutrally buoyant grain kept that speed for
  // seconds). The pressure itself starts at zero and the first solve finds it, as before: starting it hydrostatic
  // as well moved the free-sloshing frequency test by one step of its fit (0.05 %), so that was left alone.
  // Scene positions are in the tank at rest: at t = 0 the tank may already be displaced (a motion with a phase, or
  // a table that does not start at 0), and the water starts where the tank is (at rest in it: its box velocity).
  auto layout_of = [&](const ParticleBoxModel& box, FluidKind kind) {
    return box.fit_extent ? grid_layout(box_grid(origin, box.low, box.high, fluid.spacing, true), origin, kind)
                          : fluid_box_layout(origin, box.low, box.high, fluid.spacing);
  };
  for (const ParticleBoxModel& box : fluid.boxes)
    for (const LatticeParticle& particle : layout_of(box, FluidKind::kFluid).particles) {
      // [fluid.initial_velocity] adds its profile along x at the particle's height in the tank at rest.
      const Vec3 velocity =
          box.velocity + Vec3::UnitX() * initial_profile_velocity(fluid.initial_velocity, particle.position.z());
      const std::size_t slot = particles.add(particle.position + tank.displacement, velocity, FluidKind::kFluid);
      particles.pressure_gradient[slot] = fluid.density * model.gravity;
      particles.applied_pressure_gradient[slot] = particles.pressure_gradient[slot];
    }

  // Wall-box points that coincide with a tank wall particle, or with another wall box, are placed once. With a
  // box fitted to its extent (off the tank lattice) "coincide" is geometric: a wall-box particle closer than l0/2
  // to one already placed is dropped (for snapped boxes the same thing: distinct lattice points are l0 apart).
  const bool geometric = std::any_of(fluid.wall_boxes.begin(), fluid.wall_boxes.end(),
                                     [](const ParticleBoxModel& box) { return box.fit_extent; });
  std::set<std::array<std::int64_t, 3>> walls_placed;
  std::map<std::array<std::int64_t, 3>, std::vector<Vec3>> placed_near;  // geometric: rest positions by l0 cell
  const double spacing = fluid.spacing;
  auto cell_of = [&](const Vec3& position) {
    std::array<std::int64_t, 3> cell{};
    for (int a = 0; a < 3; ++a)
      cell[static_cast<std::size_t>(a)] = static_cast<std::int64_t>(std::floor((position[a] - origin[a]) / spacing));
    return cell;
  };
  auto too_close = [&](const Vec3& position) {
    const std::array<std::int64_t, 3> cell = cell_of(position);
    for (std::int64_t dk = -1; dk <= 1; ++dk)
      for (std::int64_t dj = -1; dj <= 1; ++dj)
        for (std::int64_t di = -1; di <= 1; ++di) {
          const auto found = placed_near.find({cell[0] + di, cell[1] + dj, cell[2] + dk});
          if (found == placed_near.end()) continue;
          for (const Vec3& other : found->second)
            if ((other - position).norm() < 0.5 * spacing) return true;
        }
    return false;
  };
  // The tank's own wall particles need no entry: a box lies inside the tank, its particles at least l0/4 inside
  // (box_grid), the wall layer l0/2 outside, so none is within l0/2 of a box particle; the map holds box particles
  // only (bounded by the budget's wall-box count).
  auto add_wall = [&](const LatticeParticle& particle, FluidKind kind, bool from_box) {
    if (geometric) {
      if (from_box) {
        if (too_close(particle.position)) return;
        placed_near[cell_of(particle.position)].push_back(particle.position);
      }
    } else if (!walls_placed.insert(particle.cell).second) {
      return;
    }
    const std::size_t slot = particles.add(particle.position + tank.displacement, tank.velocity, kind);
    particles.rest_position[slot] = particle.position;
  };
  if (fluid.tank_walls)
    for (const LatticeParticle& particle : tank_wall_layout(origin, model.tank.size, model.tank.open_faces,
                                                            fluid.spacing, fluid.effective_radius(),
                                                            model.tank.periodic)
                                               .particles)
      add_wall(particle, particle.kind, false);
  for (const ParticleBoxModel& box : fluid.wall_boxes)
    for (const LatticeParticle& particle : layout_of(box, FluidKind::kWall).particles)
      add_wall(particle, FluidKind::kWall, true);
  if (fluid.initial_arrangement == FluidModel::Arrangement::kPacked) pack_initial_fluid(model, tank, particles);
  return particles;
}

World unlaid_world(const Model& model) {
  World world;
  world.tank_motion = tank_kinematics(model.tank.motion, 0.0);
  world.walls = tank_walls(model.tank);
  if (model.solids.enabled) {
    world.solids.emplace();
    world.solid_summary.emplace();
    if (model.contact.enabled) world.contacts.emplace();
  }
  if (model.fluid.enabled) {
    world.fluid.emplace();
    world.fluid_neighbours.emplace();  // built by the first fluid step
    world.fluid_summary.emplace();
    if (model.coupling.enabled) world.fluid_sample.emplace();  // copied from `fluid` before every step
  }
  if (model.mean_flow.enabled) world.mean_flow = initial_column(model, nullptr);
  return world;
}

World initial_world(const Model& model) {
  World world = unlaid_world(model);
  apply_tank_motion(*world.tank_motion, *world.walls);
  if (model.solids.enabled) {
    // The grains of initial_state, read once by the scene reader (a scene whose checkpoint cannot be read is refused).
    if (model.solids.initial_grains) world.solids = *model.solids.initial_grains;
    // Grains of a checkpoint (a settled bed) and of the scene are placed in the tank at rest: shift them with it
    // when it starts displaced (zero for the seed's motion, which starts at x = 0).
    const Vec3 shift = world.tank_motion->displacement;
    for (std::size_t i = 0; i < world.solids->size(); ++i) world.solids->position[i] += shift;
    // The scene's spheres, blocks, beds and fills, generated here, once (a bed whose grains jam throws SceneError).
    Solids& solids = *world.solids;
    for_each_scene_sphere(model, [&](const SphereSpec& sphere) {
      const std::size_t slot = solids.add(Vec3(sphere.position + shift), sphere.velocity, sphere.radius,
                                          model.materials[static_cast<std::size_t>(sphere.material)].density,
                                          sphere.material, sphere.size_class);
      solids.angular_velocity[slot] = sphere.angular_velocity;
      solids.fixed[slot] = sphere.fixed ? 1 : 0;
    });
    // A rough floor: the grains below fixed_below at the start (in the tank at rest), those of initial_state too;
    // a grain fixed in initial_state's checkpoint stays fixed. A fixed grain moves with the tank from the start:
    // the first forces, the t = 0 output and the history force's first slip see it as it will be (a velocity given
    // in the scene or left in a checkpoint is dropped).
    const double fixed_below = model.solids.fixed_below;  // NaN (none): every comparison below is false
    for (std::size_t i = 0; i < world.solids->size(); ++i) {
      if (world.solids->position[i].z() - shift.z() < fixed_below) world.solids->fixed[i] = 1;
      if (world.solids->fixed[i]) {
        world.solids->velocity[i] = world.tank_motion->velocity;
        world.solids->angular_velocity[i] = Vec3::Zero();
      }
    }
  }
  if (model.fluid.enabled) {
    world.fluid = initial_fluid(model, *world.tank_motion);
    world.fluid_summary->fluid_count = static_cast<std::size_t>(
        std::count(world.fluid->kind.begin(), world.fluid->kind.end(), static_cast<std::int32_t>(FluidKind::kFluid)));
    world.fluid_summary->initial_fluid_count = world.fluid_summary->fluid_count;
  }
  if (model.mean_flow.enabled) world.mean_flow = initial_column(model, world.solids ? &*world.solids : nullptr);
  return world;
}

}  // namespace riffle
