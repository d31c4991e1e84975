#include "engine/output/checkpoint_validation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <type_traits>
#include <utility>
#include <vector>

#include "systems/physics/mps/mps_common.hpp"
#include "systems/physics/geometry/domain.hpp"
#include "systems/physics/geometry/periodic_box.hpp"
#include "systems/physics/geometry/tank_kinematics.hpp"
#include "systems/physics/dem/contact_slabs.hpp"
#include "systems/physics/dem/neighbour_range.hpp"

namespace riffle {

namespace {

std::string show(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}
std::string show(const Vec3& value) {
  std::string text = "(";  // appended in place: GCC 12 warns (-Wrestrict) about "(" + std::string
  text += show(value[0]);
  text += ", ";
  text += show(value[1]);
  text += ", ";
  text += show(value[2]);
  return text + ")";
}
template <class Integer, std::enable_if_t<std::is_integral_v<Integer>, int> = 0>
std::string show(Integer value) {
  return std::to_string(value);
}

bool finite(double value) { return std::isfinite(value); }
bool finite(const Vec3& value) { return value.allFinite(); }

/// Names the file in every refusal: "<file>: <field>: <problem>".
class Refusal {
 public:
  explicit Refusal(const std::string& file) : file_(file) {}

  [[noreturn]] void fail(const std::string& field, const std::string& problem) const {
    throw CheckpointError(file_ + ": " + field + ": " + problem);
  }
  /// "solids.radius[12] = -1"
  template <class Value>
  std::string item(const std::string& field, std::size_t index, const Value& value) const {
    return field + "[" + std::to_string(index) + "] = " + show(value);
  }

  template <class Value>
  void finite_values(const std::string& field, const std::vector<Value>& values) const {
    for (std::size_t i = 0; i < values.size(); ++i)
      if (!finite(values[i])) fail(item(field, i, values[i]), "must be finite");
  }
  void finite_value(const std::string& field, double value) const {
    if (!finite(value)) fail(field + " = " + show(value), "must be finite");
  }
  void finite_value(const std::string& field, const Vec3& value) const {
    if (!finite(value)) fail(field + " = " + show(value), "must be finite");
  }
  void positive_values(const std::string& field, const std::vector<double>& values) const {
    for (std::size_t i = 0; i < values.size(); ++i)
      if (!(values[i] > 0.0)) fail(item(field, i, values[i]), "must be positive");
  }
  void count(const std::string& field, std::size_t found, std::size_t expected, const std::string& why) const {
    if (found != expected)
      fail(field,
           "holds " + std::to_string(found) + " entries, expected " + std::to_string(expected) + " (" + why + ")");
  }

  /// Every real field of an SoA component (for_each_field) is finite.
  template <class Component>
  void finite_fields(const std::string& component_name, const Component& component) const {
    Component::for_each_field(component, [&](const FieldInfo& info, const auto& field) {
      using Value = typename std::decay_t<decltype(field)>::value_type;
      if constexpr (std::is_same_v<Value, double> || std::is_same_v<Value, Vec3>)
        finite_values(component_name + "." + info.name, field);
    });
  }

  /// Ids unique and below next_id, and next_id equal to the count: entities are added with ids 0, 1, ... and never
  /// removed, so the ids are a permutation of 0..count-1 (and no id can overflow when more are added).
  void ids(const std::string& component_name, const std::vector<EntityId>& ids, EntityId next_id) const {
    if (next_id != ids.size())
      fail(component_name + ".next_id = " + show(next_id),
           "must equal the number of entries (" + std::to_string(ids.size()) + "): none is ever removed");
    std::vector<char> seen(ids.size(), 0);
    for (std::size_t i = 0; i < ids.size(); ++i) {
      if (ids[i] >= next_id) fail(item(component_name + ".id", i, ids[i]), "must be below next_id = " + show(next_id));
      if (seen[ids[i]]) fail(item(component_name + ".id", i, ids[i]), "is used twice");
      seen[ids[i]] = 1;
    }
  }

  /// CSR offsets: `entries` + 1 of them, starting at 0, never decreasing, ending at `total`.
  void offsets(const std::string& field, const std::vector<std::uint32_t>& offsets, std::size_t entries,
               std::size_t total) const {
    count(field, offsets.size(), entries + 1, "one per grain plus one");
    if (offsets[0] != 0) fail(item(field, 0, offsets[0]), "must be 0");
    for (std::size_t i = 1; i < offsets.size(); ++i)
      if (offsets[i] < offsets[i - 1]) fail(item(field, i, offsets[i]), "must not be below the one before it");
    if (offsets.back() != total)
      fail(item(field, entries, offsets.back()), "must equal the number of pairs, " + std::to_string(total));
  }

 private:
  const std::string& file_;
};

void check_world_time(const Refusal& refusal, const World& world, const Model& model) {
  if (!std::isfinite(world.time) || world.time < 0.0)
    refusal.fail("time = " + show(world.time), "must be finite and not negative");
  // Each step advances the time by run.dt, or with a fluid by a Courant-limited step of at least fluid.min_dt; with
  // the mean-flow fluid by a step the grains' drag may shorten without a floor (coupling.drag_number).
  const double steps = static_cast<double>(world.step);
  const double longest = steps * model.dt * (1.0 + 1e-6);
  const double shortest_step = model.fluid.enabled      ? std::min(model.fluid.min_dt, model.dt)
                               : model.mean_flow.enabled ? 0.0
                                                         : model.dt;
  const double shortest = steps * shortest_step * (1.0 - 1e-6);
  if (world.time > longest || world.time < shortest)
    refusal.fail("time = " + show(world.time),
                 "does not match step = " + show(world.step) + " (steps of " +
                     (model.fluid.enabled ? show(model.fluid.min_dt) + " to " : std::string()) + show(model.dt) +
                     " s)");
}

void check_tank_motion(const Refusal& refusal, const TankMotion& tank, const Model& model) {
  refusal.finite_value("tank_motion.time", tank.time);
  refusal.finite_value("tank_motion.displacement", tank.displacement);
  refusal.finite_value("tank_motion.velocity", tank.velocity);
  refusal.finite_value("tank_motion.acceleration", tank.acceleration);
  // The motion is part of the scene, and a table is re-read from its CSV on resume: the kinematics the checkpoint
  // holds must be the scene's at their time, or the walls would jump (a table or [tank.motion] edited since). Exact
  // up to rounding (1e-9 relative, 1e-12 absolute in SI units); a change away from the checkpoint's time passes.
  const TankMotion expected = tank_kinematics(model.tank.motion, tank.time);
  auto same = [&](const char* field, const Vec3& value, const Vec3& wanted) {
    for (int axis = 0; axis < 3; ++axis)
      if (!(std::abs(value[axis] - wanted[axis]) <= 1e-9 * std::max(std::abs(value[axis]), std::abs(wanted[axis])) + 1e-12))
        refusal.fail(std::string("tank_motion.") + field + " = " + show(value),
                     "differs from the scene's motion at t = " + show(tank.time) + " s, " + show(wanted) +
                         " (was [tank.motion] or its table changed since the checkpoint was written?)");
  };
  same("displacement", tank.displacement, expected.displacement);
  same("velocity", tank.velocity, expected.velocity);
  same("acceleration", tank.acceleration, expected.acceleration);
}

/// The grains are the scene's own: the same ids, each with the radius, material, size class, mass and inertia the
/// scene gave it (none of these change during a run), and every centre inside the domain.
void check_grains_match_scene(const Refusal& refusal, const Solids& grains, const Solids& scene, const Model& model) {
  // validate_grains has made the ids a permutation of 0..count-1.
  refusal.count("solids", grains.size(), scene.size(), "the grains of its scene");
  std::vector<std::size_t> scene_slot(scene.size());
  for (std::size_t i = 0; i < scene.size(); ++i) scene_slot[scene.id[i]] = i;  // scene ids: a permutation too
  for (std::size_t i = 0; i < grains.size(); ++i) {
    const std::size_t k = scene_slot[grains.id[i]];
    auto same = [&](const char* field, auto value, auto expected) {
      if (value != expected)
        refusal.fail(refusal.item(std::string("solids.") + field, i, value),
                     "differs from the scene's grain id " + show(grains.id[i]) + " (" + show(expected) + ")");
    };
    same("radius", grains.radius[i], scene.radius[k]);
    same("material", grains.material[i], scene.material[k]);
    same("size_class", grains.size_class[i], scene.size_class[k]);
    same("fixed", grains.fixed[i], scene.fixed[k]);
    same("mass", grains.mass[i], scene.mass[k]);
    same("moment_of_inertia", grains.moment_of_inertia[i], scene.moment_of_inertia[k]);
  }
  const DomainBox domain = grain_domain_box(model);
  for (std::size_t i = 0; i < grains.size(); ++i)
    if (!domain.contains(grains.position[i]))
      refusal.fail(refusal.item("solids.position", i, grains.position[i]),
                   "is outside the domain " + show(domain.low) + " - " + show(domain.high));
}

/// The walls are the scene's tank: only their position and velocity move.
void check_walls(const Refusal& refusal, const Walls& walls, const Walls& scene) {
  refusal.count("walls", walls.size(), scene.size(), "the closed faces of its scene's tank");
  if (walls.next_id != scene.next_id)
    refusal.fail("walls.next_id = " + show(walls.next_id), "differs from the scene's");
  for (std::size_t i = 0; i < walls.size(); ++i) {
    const bool same = walls.id[i] == scene.id[i] && walls.name[i] == scene.name[i] &&
                      walls.rest_point[i] == scene.rest_point[i] && walls.normal[i] == scene.normal[i] &&
                      walls.half_extent_u[i] == scene.half_extent_u[i] &&
                      walls.half_extent_v[i] == scene.half_extent_v[i] &&
                      walls.moves_with_tank[i] == scene.moves_with_tank[i] && walls.material[i] == scene.material[i];
    if (!same)
      refusal.fail("walls[" + std::to_string(i) + "] (\"" + walls.name[i] + "\")",
                   "differs from the scene's tank wall \"" + scene.name[i] + "\"");
  }
  refusal.finite_fields("walls", walls);
}

/// The neighbour lists: CSR offsets sized grains + 1, pair indices in range, the reverse index a permutation of the
/// pairs, wall indices below the wall count. Lists never built (valid = false) may also be empty.
void check_contacts(const Refusal& refusal, const Contacts& contacts, const Solids& grains, std::size_t wall_count,
                    const Model& model) {
  const bool empty = contacts.pair_offsets.empty() && contacts.pair_second.empty() && contacts.pair_spring.empty() &&
                     contacts.pair_rolling_spring.empty() && contacts.pair_overlap.empty() &&
                     contacts.second_offsets.empty() && contacts.second_pairs.empty() &&
                     contacts.wall_pair_offsets.empty() && contacts.wall_pair_wall.empty() &&
                     contacts.wall_pair_spring.empty() && contacts.wall_pair_rolling_spring.empty() &&
                     contacts.wall_pair_force.empty() &&
                     contacts.wall_pair_torque.empty() && contacts.wall_pair_overlap.empty() &&
                     contacts.build_position.empty();
  refusal.finite_value("contacts.build_tank_displacement", contacts.build_tank_displacement);
  if (!contacts.valid && empty) return;
  const std::size_t grain_count = grains.size();
  const std::size_t pairs = contacts.pair_second.size();
  const std::string per_pair = "one per grain pair";
  refusal.offsets("contacts.pair_offsets", contacts.pair_offsets, grain_count, pairs);
  refusal.count("contacts.pair_spring", contacts.pair_spring.size(), pairs, per_pair);
  refusal.count("contacts.pair_rolling_spring", contacts.pair_rolling_spring.size(), pairs, per_pair);
  refusal.count("contacts.pair_overlap", contacts.pair_overlap.size(), pairs, per_pair);
  // A periodic box: a second slot may be a ghost; the halo is rebuilt from the positions the list was built at,
  // exactly as the resumed run will (solid_neighbours), and the ghost stands for its owner.
  Halo halo;
  halo.real_count = static_cast<std::uint32_t>(grain_count);
  if (model.tank.any_periodic() && contacts.build_position.size() == grain_count)
    build_halo(contacts.build_position, grains.id, periodic_box(model), halo_width(grains, model, contacts.skin), halo);
  const std::size_t slot_count = grain_count + halo.size();
  for (std::size_t i = 0; i < grain_count; ++i)
    for (std::uint32_t k = contacts.pair_offsets[i]; k < contacts.pair_offsets[i + 1]; ++k) {
      const std::uint32_t second = contacts.pair_second[k];
      if (second >= slot_count || halo.owner_of(second) <= i)
        refusal.fail(refusal.item("contacts.pair_second", k, second),
                     "must be above its first grain " + std::to_string(i) + " and below the grain count " +
                         std::to_string(slot_count) + (halo.size() ? " (ghosts included)" : ""));
      if (k > contacts.pair_offsets[i] && second <= contacts.pair_second[k - 1])
        refusal.fail(refusal.item("contacts.pair_second", k, second), "must be above the one before it (ascending)");
    }
  // Reverse index: grain j's entries are ascending pair indices whose second grain is j; with the offsets ending at
  // the pair count, that makes it a permutation of the pairs.
  refusal.offsets("contacts.second_offsets", contacts.second_offsets, grain_count, pairs);
  refusal.count("contacts.second_pairs", contacts.second_pairs.size(), pairs, per_pair);
  for (std::size_t j = 0; j < grain_count; ++j)
    for (std::uint32_t s = contacts.second_offsets[j]; s < contacts.second_offsets[j + 1]; ++s) {
      const std::uint32_t k = contacts.second_pairs[s];
      if (k >= pairs || contacts.pair_second[k] >= slot_count || halo.owner_of(contacts.pair_second[k]) != j)
        refusal.fail(refusal.item("contacts.second_pairs", s, k),
                     "must be a pair whose second grain is " + std::to_string(j));
      if (s > contacts.second_offsets[j] && k <= contacts.second_pairs[s - 1])
        refusal.fail(refusal.item("contacts.second_pairs", s, k), "must be above the one before it (ascending)");
    }
  const std::size_t wall_pairs = contacts.wall_pair_wall.size();
  const std::string per_wall_pair = "one per grain-wall pair";
  refusal.offsets("contacts.wall_pair_offsets", contacts.wall_pair_offsets, grain_count, wall_pairs);
  refusal.count("contacts.wall_pair_spring", contacts.wall_pair_spring.size(), wall_pairs, per_wall_pair);
  refusal.count("contacts.wall_pair_rolling_spring", contacts.wall_pair_rolling_spring.size(), wall_pairs,
                per_wall_pair);
  refusal.count("contacts.wall_pair_force", contacts.wall_pair_force.size(), wall_pairs, per_wall_pair);
  refusal.count("contacts.wall_pair_torque", contacts.wall_pair_torque.size(), wall_pairs, per_wall_pair);
  refusal.count("contacts.wall_pair_overlap", contacts.wall_pair_overlap.size(), wall_pairs, per_wall_pair);
  for (std::size_t k = 0; k < wall_pairs; ++k)
    if (contacts.wall_pair_wall[k] >= wall_count)
      refusal.fail(refusal.item("contacts.wall_pair_wall", k, contacts.wall_pair_wall[k]),
                   "must be below the wall count " + std::to_string(wall_count));
  refusal.count("contacts.build_position", contacts.build_position.size(), grain_count, "one per grain");
  refusal.finite_values("contacts.pair_spring", contacts.pair_spring);
  refusal.finite_values("contacts.pair_rolling_spring", contacts.pair_rolling_spring);
  refusal.finite_values("contacts.pair_overlap", contacts.pair_overlap);
  refusal.finite_values("contacts.wall_pair_spring", contacts.wall_pair_spring);
  refusal.finite_values("contacts.wall_pair_rolling_spring", contacts.wall_pair_rolling_spring);
  refusal.finite_values("contacts.wall_pair_force", contacts.wall_pair_force);
  refusal.finite_values("contacts.wall_pair_torque", contacts.wall_pair_torque);
  refusal.finite_values("contacts.wall_pair_overlap", contacts.wall_pair_overlap);
  refusal.finite_values("contacts.build_position", contacts.build_position);
  // The skin decides when the lists are rebuilt: it is the scene's, or half the smallest radius (default_skin).
  const double skin = model.contact.skin > 0.0 ? model.contact.skin : default_skin(grains);
  if (contacts.valid && contacts.skin != skin)
    refusal.fail("contacts.skin = " + show(contacts.skin), "differs from the scene's skin " + show(skin));
  // The contact pass writes a pair's two grains from the task of the first grain's slab: a pair whose grains lie in
  // slabs further apart (a list not built from these positions) would let two tasks write one grain.
  const ContactSlabs slabs = contact_slabs(contacts.build_position, halo_width(grains, model, skin), periodic_box(model));
  std::vector<std::uint32_t> slab_of(grain_count);
  for (std::uint32_t s = 0; s < slabs.count(); ++s)
    for (std::uint32_t n = slabs.offsets[s]; n < slabs.offsets[s + 1]; ++n) slab_of[slabs.grains[n]] = s;
  for (std::size_t i = 0; i < grain_count; ++i)
    for (std::uint32_t k = contacts.pair_offsets[i]; k < contacts.pair_offsets[i + 1]; ++k) {
      if (!neighbouring_slabs(slabs, slab_of[i], slab_of[halo.owner_of(contacts.pair_second[k])]))
        refusal.fail(refusal.item("contacts.pair_second", k, contacts.pair_second[k]),
                     "lies beyond the list's reach of its first grain " + std::to_string(i) +
                         " at the positions it was built at");
    }
}

/// The MPS particles are the scene's: the same ids, less the fluid particles fluid_escape removed (with
/// fluid.escape = "remove", no more than fluid.escape_fraction_limit of them), fluid particles in slots [0, F) and the
/// tank's wall and dummy particles after them (the cell sort reorders each group only within itself), each particle
/// of the kind the scene gave its id, walls and dummies at the scene's rest positions.
void check_fluid(const Refusal& refusal, const FluidParticles& fluid, const FluidSummary& summary,
                 const FluidParticles& scene, const Model& model, std::uint32_t format) {
  const std::size_t scene_fluid_count = fluid_slot_count(scene);
  const std::size_t boundary_count = scene.size() - scene_fluid_count;
  const bool removes = model.fluid.escape == FluidModel::EscapePolicy::kRemove;
  // The removed particles' ids stay used (never reused): next_id is the scene's, the ids a subset of its.
  if (fluid.next_id != scene.next_id)
    refusal.fail("fluid.next_id = " + show(fluid.next_id),
                 "must equal the scene's, " + show(scene.next_id) + " (ids are never reused)");
  if (!removes || fluid.size() > scene.size() || fluid.size() < boundary_count)
    refusal.count("fluid", fluid.size(), scene.size(),
                  removes ? "the fluid, wall and dummy particles of its scene, less removed fluid particles"
                          : "the fluid, wall and dummy particles of its scene");
  std::vector<char> seen(scene.size(), 0);
  for (std::size_t i = 0; i < fluid.size(); ++i) {
    if (fluid.id[i] >= fluid.next_id)
      refusal.fail(refusal.item("fluid.id", i, fluid.id[i]), "must be below next_id = " + show(fluid.next_id));
    if (seen[fluid.id[i]]) refusal.fail(refusal.item("fluid.id", i, fluid.id[i]), "is used twice");
    seen[fluid.id[i]] = 1;
  }
  std::vector<std::size_t> scene_slot(scene.size());
  for (std::size_t k = 0; k < scene.size(); ++k) scene_slot[scene.id[k]] = k;
  const std::size_t fluid_count = fluid.size() - boundary_count;
  const std::size_t removed = scene_fluid_count - fluid_count;
  for (std::size_t i = 0; i < fluid.size(); ++i) {
    const std::size_t k = scene_slot[fluid.id[i]];
    if (fluid.kind[i] != scene.kind[k] || (i < fluid_count) != (scene.kind[k] == kFluidKind))
      refusal.fail(refusal.item("fluid.kind", i, fluid.kind[i]),
                   "must be " + show(scene.kind[k]) + ", the kind of particle id " + show(fluid.id[i]) +
                       " in its scene, and fluid particles (0) must hold slots [0, " + std::to_string(fluid_count) +
                       ") before walls (1) and dummies (2)");
    if (i >= fluid_count && fluid.rest_position[i] != scene.rest_position[k])
      refusal.fail(refusal.item("fluid.rest_position", i, fluid.rest_position[i]),
                   "differs from the scene's wall particle (" + show(scene.rest_position[k]) + ")");
  }
  // A run stops once more than the limit has gone (fluid_checks): no checkpoint of it is written.
  if (static_cast<double>(removed) > model.fluid.escape_fraction_limit * static_cast<double>(scene_fluid_count)) {
    char limit[32];
    std::snprintf(limit, sizeof limit, "%g", model.fluid.escape_fraction_limit);
    refusal.fail("fluid", "holds " + std::to_string(fluid_count) + " fluid particles of the scene's " +
                              std::to_string(scene_fluid_count) +
                              ": more were removed than fluid.escape_fraction_limit = " + limit + " allows");
  }
  refusal.finite_fields("fluid", fluid);
  for (std::size_t i = 0; i < fluid.size(); ++i) {
    if (fluid.free_surface[i] != 0 && fluid.free_surface[i] != 1)
      refusal.fail(refusal.item("fluid.free_surface", i, fluid.free_surface[i]), "must be 0 or 1");
    if (fluid.number_density[i] < 0.0)
      refusal.fail(refusal.item("fluid.number_density", i, fluid.number_density[i]), "must not be negative");
  }
  const DomainBox domain = domain_box(model);
  for (std::size_t i = 0; i < fluid_count; ++i)
    if (!domain.contains(fluid.position[i]))
      refusal.fail(refusal.item("fluid.position", i, fluid.position[i]),
                   "is outside the domain " + show(domain.low) + " - " + show(domain.high));

  if (summary.fluid_count != fluid_count)
    refusal.fail("fluid_summary.fluid_count = " + show(summary.fluid_count),
                 "must equal the fluid particles, " + std::to_string(fluid_count));
  // The removals by reason add up to the removed count; a file older than the reasons counts none of its own.
  const std::size_t by_reason = summary.removed_left_domain + summary.removed_lone_droplet;
  const bool reasons_stored = format >= FluidSummary::kFirstFormatWithRemovalReasons;
  if (by_reason < summary.removed_left_domain || (reasons_stored ? by_reason != removed : by_reason != 0))
    refusal.fail("fluid_summary.removed_left_domain + removed_lone_droplet = " + show(summary.removed_left_domain) +
                     " + " + show(summary.removed_lone_droplet),
                 "must equal the fluid particles removed, " + std::to_string(reasons_stored ? removed : 0));
  if (!std::isfinite(summary.body_force_integral))
    refusal.fail("fluid_summary.body_force_integral = " + show(summary.body_force_integral), "must be finite");
  if (summary.surface_count > fluid_count)
    refusal.fail("fluid_summary.surface_count = " + show(summary.surface_count),
                 "must not exceed the fluid particles, " + std::to_string(fluid_count));
  if (summary.solver_unknowns > fluid.size())
    refusal.fail("fluid_summary.solver_unknowns = " + show(summary.solver_unknowns),
                 "must not exceed the particles, " + std::to_string(fluid.size()));
  if (summary.solver_iterations < 0)
    refusal.fail("fluid_summary.solver_iterations = " + show(summary.solver_iterations), "must not be negative");
  const std::pair<const char*, double> reals[] = {
      {"kinetic_energy", summary.kinetic_energy}, {"max_speed", summary.max_speed},
      {"mean_density_ratio", summary.mean_density_ratio}, {"volume", summary.volume},
      {"solver_residual", summary.solver_residual}, {"courant", summary.courant}};
  for (const auto& [field, value] : reals)
    if (!std::isfinite(value) || value < 0.0)
      refusal.fail(std::string("fluid_summary.") + field + " = " + show(value), "must be finite and not negative");
}

/// Frames and interval checkpoints are written on a schedule of the time: their bookkeeping cannot run ahead of it.
void check_output(const Refusal& refusal, const OutputState& output, const World& world, const Model& model) {
  const std::vector<double>& frames = output.frame_times;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    if (!std::isfinite(frames[k]) || frames[k] < 0.0 || frames[k] > world.time)
      refusal.fail(refusal.item("output.frame_times", k, frames[k]),
                   "must be finite, not negative and not after the time " + show(world.time));
    if (k > 0 && !(frames[k] > frames[k - 1]))
      refusal.fail(refusal.item("output.frame_times", k, frames[k]), "must be after the frame before it");
  }
  // Frame or checkpoint k is due at k * interval - dt / 2: no more of them than that allows by now.
  auto most = [&](double interval) { return interval > 0.0 ? (world.time + 0.5 * model.dt) / interval + 2.0 : 0.0; };
  if (static_cast<double>(frames.size()) > most(model.output.vtk_interval))
    refusal.fail("output.frame_times", std::to_string(frames.size()) +
                                           " frames: more than output.vtk_interval allows by t = " + show(world.time));
  if (static_cast<double>(output.checkpoints_due) > most(model.output.checkpoint_interval))
    refusal.fail("output.checkpoints_due = " + show(output.checkpoints_due),
                 "more than output.checkpoint_interval allows by t = " + show(world.time));
  const std::vector<std::uint64_t>& kept = output.kept_steps;
  if (kept.size() > output.checkpoints_due ||
      static_cast<std::int64_t>(kept.size()) > std::max<std::int64_t>(0, model.output.checkpoint_keep))
    refusal.fail("output.kept_steps", std::to_string(kept.size()) +
                                          " entries: more than output.checkpoint_keep or than the checkpoints written");
  for (std::size_t k = 0; k < kept.size(); ++k)
    if (kept[k] > world.step || (k > 0 && kept[k] <= kept[k - 1]))
      refusal.fail(refusal.item("output.kept_steps", k, kept[k]),
                   "must be ascending and not after step " + show(world.step));
}

}  // namespace

void validate_grains(const Solids& grains, std::size_t material_count, const std::string& name) {
  const Refusal refusal(name);
  refusal.ids("solids", grains.id, grains.next_id);
  refusal.finite_fields("solids", grains);
  refusal.positive_values("solids.radius", grains.radius);
  refusal.positive_values("solids.mass", grains.mass);
  refusal.positive_values("solids.moment_of_inertia", grains.moment_of_inertia);
  for (std::size_t i = 0; i < grains.size(); ++i) {
    if (grains.material[i] < 0 || static_cast<std::size_t>(grains.material[i]) >= material_count)
      refusal.fail(refusal.item("solids.material", i, grains.material[i]),
                   "must be a material index below " + std::to_string(material_count));
    if (grains.size_class[i] < 0 || grains.size_class[i] > kMaxSizeClass)
      refusal.fail(refusal.item("solids.size_class", i, grains.size_class[i]),
                   "must be in 0.." + std::to_string(kMaxSizeClass));
    if (grains.fixed[i] != 0 && grains.fixed[i] != 1)
      refusal.fail(refusal.item("solids.fixed", i, grains.fixed[i]), "must be 0 or 1");
    // The drag law divides by the voidage and raises it to powers: it is a volume fraction, clipped above zero.
    if (!(grains.voidage[i] > 0.0 && grains.voidage[i] <= 1.0))
      refusal.fail(refusal.item("solids.voidage", i, grains.voidage[i]), "must be in (0, 1]");
    if (grains.fluid_weight[i] < 0.0)
      refusal.fail(refusal.item("solids.fluid_weight", i, grains.fluid_weight[i]), "must not be negative");
    // A unit-variance Langevin state: a component past 100 standard deviations never comes from a run, and a huge
    // one would put an unbounded velocity into the drag.
    if (grains.fluctuation_state[i].cwiseAbs().maxCoeff() > kLargestFluctuationState)
      refusal.fail(refusal.item("solids.fluctuation_state", i, grains.fluctuation_state[i]),
                   "each component must lie within +-" + std::to_string(static_cast<int>(kLargestFluctuationState)) +
                       " (a unit-variance Langevin state)");
  }
}

/// The mean-flow column is the scene's grid: every profile of its cells (faces for the eddy viscosity), finite, the
/// solid fraction a fraction.
void check_mean_flow(const Refusal& refusal, const MeanFlowColumn& column, const Model& model) {
  const std::size_t cells = model.mean_flow.cells;
  const auto sized = [&](const char* field, const std::vector<double>& values, std::size_t expected) {
    if (values.size() != expected)
      refusal.fail(std::string("mean_flow.") + field,
                   std::to_string(values.size()) + " values, but the scene's column has " + std::to_string(expected));
    refusal.finite_values(std::string("mean_flow.") + field, values);
  };
  sized("velocity_x", column.velocity_x, cells);
  sized("velocity_y", column.velocity_y, cells);
  sized("solid_fraction", column.solid_fraction, cells);
  sized("impulse_x", column.impulse_x, cells);
  sized("impulse_y", column.impulse_y, cells);
  sized("eddy_viscosity", column.eddy_viscosity, cells + 1);
  for (std::size_t i = 0; i < cells; ++i)
    if (!(column.solid_fraction[i] >= 0.0 && column.solid_fraction[i] < 1.0))
      refusal.fail(refusal.item("mean_flow.solid_fraction", i, column.solid_fraction[i]), "must be in [0, 1)");
  for (const auto& [field, value] : {std::pair{"body_force", column.body_force}, {"bed_surface", column.bed_surface},
                                     {"floor_stress", column.floor_stress}, {"top_stress", column.top_stress}})
    refusal.finite_value(std::string("mean_flow.") + field, value);
}

void validate_checkpoint(const CheckpointData& data, const Model& model, const World& initial,
                         const std::string& name) {
  const Refusal refusal(name);
  const World& world = data.world;
  auto same_presence = [&](const char* component, bool found, bool expected) {
    if (found != expected)
      refusal.fail(component, std::string(found ? "present" : "absent") + ", but its scene " +
                                  (expected ? "needs it" : "has none"));
  };
  same_presence("solids", world.solids.has_value(), initial.solids.has_value());
  same_presence("walls", world.walls.has_value(), initial.walls.has_value());
  same_presence("tank_motion", world.tank_motion.has_value(), initial.tank_motion.has_value());
  same_presence("contacts", world.contacts.has_value(), initial.contacts.has_value());
  same_presence("fluid", world.fluid.has_value(), initial.fluid.has_value());
  same_presence("fluid_summary", world.fluid_summary.has_value(), initial.fluid_summary.has_value());
  same_presence("mean_flow", world.mean_flow.has_value(), initial.mean_flow.has_value());

  check_world_time(refusal, world, model);
  if (world.tank_motion) check_tank_motion(refusal, *world.tank_motion, model);
  if (world.walls) check_walls(refusal, *world.walls, *initial.walls);
  if (world.solids) {
    validate_grains(*world.solids, model.materials.size(), name);
    check_grains_match_scene(refusal, *world.solids, *initial.solids, model);
  }
  if (world.contacts)
    check_contacts(refusal, *world.contacts, *world.solids, world.walls ? world.walls->size() : 0, model);
  if (world.fluid) check_fluid(refusal, *world.fluid, *world.fluid_summary, *initial.fluid, model, data.format);
  if (world.mean_flow) check_mean_flow(refusal, *world.mean_flow, model);
  check_output(refusal, data.output, world, model);
}

}  // namespace riffle
