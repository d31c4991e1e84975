#pragma once
// Solid grains (DEM spheres) as structure-of-arrays data. One entry per sphere; slot order may change when the
// grains are sorted by grid cell, `id` never does.
//
// The table is split into roles, each written by its own systems (docs/ARCHITECTURE.md, "Components"), so that the
// scheduler can run the writers of different roles side by side: contact and drag forces, say. `Solids` is the whole
// table: every role at once, for set-up, output, checkpoints and the sorts that reorder the grains.
#include <array>
#include <cereal/types/vector.hpp>
#include <cstdint>
#include <numbers>
#include <vector>

#include "components/component_id.hpp"
#include "components/soa.hpp"
#include "components/vec.hpp"

namespace riffle {

/// Identity and motion: written by the integrator (solid_kick_drift, solid_kick).
struct GrainState {
  static constexpr ComponentId kId = component_id<GrainState>;
  static constexpr std::string_view kName = "grain_state";

  std::vector<EntityId> id;            ///< [1] stable identity
  std::vector<Vec3> position;          ///< [m] centre, lab frame; filled by the integrator
  std::vector<Vec3> velocity;          ///< [m/s] centre velocity, lab frame
  std::vector<Vec3> angular_velocity;  ///< [rad/s]

  std::size_t size() const { return id.size(); }

  template <class Self, class Visit>
  static void for_each_field(Self& self, Visit&& visit) {
    visit(FieldInfo{"id", "1", true}, self.id);
    visit(FieldInfo{"position", "m", false}, self.position);  // VTK points, not a point-data array
    visit(FieldInfo{"velocity", "m/s", true}, self.velocity);
    visit(FieldInfo{"angular_velocity", "rad/s", true}, self.angular_velocity);
  }
};

/// What a grain is: set once by the bed generation, never written by a system.
struct GrainProperties {
  static constexpr ComponentId kId = component_id<GrainProperties>;
  static constexpr std::string_view kName = "grain_properties";

  std::vector<double> radius;             ///< [m]
  std::vector<double> mass;               ///< [kg]
  std::vector<double> moment_of_inertia;  ///< [kg m^2] about the centre (solid sphere: 2/5 m r^2)
  std::vector<std::int32_t> material;     ///< [1] index into the scene's material table
  std::vector<std::int32_t> size_class;   ///< [1] index into the scene's size classes (for per-class output)
  /// [1] 1: the grain is held with the tank for the whole run, a rough floor of grains ([solids] fixed_below, a
  /// sphere's `fixed`); 0: free. Set when the run starts and kept in checkpoints (format 8 on).
  std::vector<std::int32_t> fixed;

  std::size_t size() const { return radius.size(); }

  template <class Self, class Visit>
  static void for_each_field(Self& self, Visit&& visit) {
    visit(FieldInfo{"radius", "m", true}, self.radius);
    visit(FieldInfo{"mass", "kg", true}, self.mass);
    visit(FieldInfo{"moment_of_inertia", "kg m^2", false}, self.moment_of_inertia);
    visit(FieldInfo{"material", "1", true}, self.material);
    visit(FieldInfo{"size_class", "1", true}, self.size_class);
    visit(FieldInfo{"fixed", "1", true, 0.0, 8}, self.fixed);
  }
};

/// The sum of the non-gravity force sources below: written by solid_force_sum, read by the integrator.
struct GrainTotalForce {
  static constexpr ComponentId kId = component_id<GrainTotalForce>;
  static constexpr std::string_view kName = "grain_total_force";

  std::vector<Vec3> force;   ///< [N] contact + drag + pressure force
  std::vector<Vec3> torque;  ///< [N m] contact torque

  std::size_t size() const { return force.size(); }

  template <class Self, class Visit>
  static void for_each_field(Self& self, Visit&& visit) {
    visit(FieldInfo{"force", "N", true}, self.force);
    visit(FieldInfo{"torque", "N m", true}, self.torque);
  }
};

/// Grain-grain and grain-wall contact forces: written by solid_contact_gather.
struct GrainContactForce {
  static constexpr ComponentId kId = component_id<GrainContactForce>;
  static constexpr std::string_view kName = "grain_contact_force";

  std::vector<Vec3> contact_force;   ///< [N] from grain-grain and grain-wall contacts
  std::vector<Vec3> contact_torque;  ///< [N m] from contacts, rolling friction included

  std::size_t size() const { return contact_force.size(); }

  template <class Self, class Visit>
  static void for_each_field(Self& self, Visit&& visit) {
    visit(FieldInfo{"contact_force", "N", true}, self.contact_force);
    visit(FieldInfo{"contact_torque", "N m", false}, self.contact_torque);
  }
};

/// The fluid's drag on the grain (seed 000 Sec. 3.3): written by solid_drag every sub-step; fluid_drag_reaction
/// hands the impulse to the fluid and clears it.
struct GrainDrag {
  static constexpr ComponentId kId = component_id<GrainDrag>;
  static constexpr std::string_view kName = "grain_drag";

  std::vector<Vec3> drag_force;    ///< [N] drag of the fluid on the grain, recomputed every sub-step
  std::vector<Vec3> drag_impulse;  ///< [N s] drag integrated over the sub-steps since the fluid last took it back
  /// [m/s] the fluid velocity the drag used: the sampled one less the grain's own disturbance (docs/COUPLING.md)
  std::vector<Vec3> undisturbed_velocity;
  /// [m/s] the grain's own disturbance of the sampled velocity, one first-order lag per mode of its build-up (fast,
  /// middle, slow: systems/physics/coupling/self_induced.hpp); with the walls' lags below, their sum is
  /// fluid_velocity - undisturbed_velocity. Grain fields, so a resumed run continues each build-up where it was.
  std::vector<Vec3> self_induced_fast, self_induced_middle, self_induced_slow;
  /// [m/s] what the tank's walls take off that disturbance (they hold the water: Blake's image system), one lag per
  /// pair of walls across x, y and z (with the walls' resistance at the grain's scale), as slow as the disturbance's
  /// slowest mode.
  std::vector<Vec3> self_induced_wall_x, self_induced_wall_y, self_induced_wall_z;
  /// Ergun's drag at the grain's voidage over this fluid step, F = (ergun_resistance + ergun_inertial_resistance |w|) w
  /// for the slip w (systems/physics/coupling/drag_law.hpp, ErgunDrag times the grain's volume): [N s/m] and
  /// [N s^2/m^2], set by solid_drag_law once a step for the grains in Ergun's range (else 0), so that the drag's
  /// sub-steps pay only for the slip.
  std::vector<double> ergun_resistance, ergun_inertial_resistance;

  std::size_t size() const { return drag_force.size(); }

  template <class Self, class Visit>
  static void for_each_field(Self& self, Visit&& visit) {
    visit(FieldInfo{"drag_force", "N", true}, self.drag_force);
    visit(FieldInfo{"drag_impulse", "N s", false}, self.drag_impulse);
    visit(FieldInfo{"undisturbed_velocity", "m/s", true, 0.0, 6}, self.undisturbed_velocity);
    visit(FieldInfo{"self_induced_fast", "m/s", false, 0.0, 6}, self.self_induced_fast);
    visit(FieldInfo{"self_induced_middle", "m/s", false, 0.0, 6}, self.self_induced_middle);
    visit(FieldInfo{"self_induced_slow", "m/s", false, 0.0, 6}, self.self_induced_slow);
    visit(FieldInfo{"self_induced_wall_x", "m/s", false, 0.0, 11}, self.self_induced_wall_x);
    visit(FieldInfo{"self_induced_wall_y", "m/s", false, 0.0, 11}, self.self_induced_wall_y);
    visit(FieldInfo{"self_induced_wall_z", "m/s", false, 0.0, 11}, self.self_induced_wall_z);
    // Set by solid_drag_law at every step's start from the voidage, before any reader: not checkpointed.
    visit(FieldInfo{"ergun_resistance", "N s/m", false, 0.0, 0, false}, self.ergun_resistance);
    visit(FieldInfo{"ergun_inertial_resistance", "N s^2/m^2", false, 0.0, 0, false}, self.ergun_inertial_resistance);
  }
};

/// The fluid around the grain as sampled once per fluid step at the step start (seed 000 Sec. 3.2): written by
/// solid_fluid_sampling, held over the sub-steps.
struct GrainSampledFluid {
  static constexpr ComponentId kId = component_id<GrainSampledFluid>;
  static constexpr std::string_view kName = "grain_sampled_fluid";

  std::vector<Vec3> pressure_force;  ///< [N] -V <grad p>
  std::vector<Vec3> fluid_velocity;  ///< [m/s] averaged fluid velocity (seed Eq. 23)
  std::vector<double> fluid_weight;  ///< [1] sum of the sampling weights of the fluid around the grain; 0 = dry
  std::vector<Vec3> fluid_acceleration;  ///< [m/s^2] the water's acceleration Du/Dt around the grain
  std::vector<Vec3> viscous_force;  ///< [N] V rho <nu lap u> ([coupling] viscous_stress; else 0)
  /// [1] the Langevin state of the velocity fluctuation a grain reads in the mean-flow fluid ([mean_flow]
  /// fluctuations = "langevin"; else 0): unit-variance components along the shear, across it and vertical
  std::vector<Vec3> fluctuation_state;

  std::size_t size() const { return pressure_force.size(); }

  template <class Self, class Visit>
  static void for_each_field(Self& self, Visit&& visit) {
    visit(FieldInfo{"pressure_force", "N", true}, self.pressure_force);
    visit(FieldInfo{"fluid_velocity", "m/s", true}, self.fluid_velocity);
    visit(FieldInfo{"fluid_weight", "1", true}, self.fluid_weight);
    visit(FieldInfo{"fluid_acceleration", "m/s^2", true, 0.0, 6}, self.fluid_acceleration);
    visit(FieldInfo{"viscous_force", "N", true, 0.0, 7}, self.viscous_force);
    visit(FieldInfo{"fluctuation_state", "1", false, 0.0, 10}, self.fluctuation_state);
  }
};

/// The fluid volume fraction around the grain at the step end: written by solid_voidage after the fluid's step,
/// while the sampled fluid above belongs to the step start.
struct GrainVoidage {
  static constexpr ComponentId kId = component_id<GrainVoidage>;
  static constexpr std::string_view kName = "grain_voidage";

  std::vector<double> voidage;  ///< [1] fluid volume fraction epsilon; 1 if dry

  std::size_t size() const { return voidage.size(); }

  template <class Self, class Visit>
  static void for_each_field(Self& self, Visit&& visit) {
    visit(FieldInfo{"voidage", "1", true, 1.0}, self.voidage);
  }
};

/// The added-mass and history (Basset) forces of the water on the grain: the added-mass force written by the
/// grains' kicks (solid_kick_drift, solid_kick), the history force and its state by solid_history_force once per
/// fluid step.
struct GrainAddedMass {
  static constexpr ComponentId kId = component_id<GrainAddedMass>;
  static constexpr std::string_view kName = "grain_added_mass";
  static constexpr std::size_t kHistoryModes = 8;  ///< BassetModes::kCount
  static constexpr std::array<const char*, kHistoryModes> kHistoryModeNames = {
      "history_mode_0", "history_mode_1", "history_mode_2", "history_mode_3",
      "history_mode_4", "history_mode_5", "history_mode_6", "history_mode_7"};

  /// [N] (m_a + m_H) (Du/Dt - dv/dt) as applied by the last half kick: the added mass C_a rho V and the history
  /// force's own step (history_mass), both implicit
  std::vector<Vec3> added_mass_force;
  /// [N] the history force of the slip's changes before this fluid step, at the step's end, held over it
  std::vector<Vec3> history_force;
  /// [kg] m_H: the history force of the step's own change of slip is m_H (Du/Dt - dv/dt) at the step's end (the
  /// kernel's integral over one step), taken implicitly by the kicks beside the added mass: explicit, it drives a
  /// light grain in a viscous liquid unstable once m_H passes its mass (m_H / m = 18 (rho mu dt / pi)^(1/2) / (rho_s d))
  std::vector<double> history_mass;
  /// [m/s] the relative velocity u - v at the last history update (the slip of the drag law)
  std::vector<Vec3> history_relative_velocity;
  /// [m/s] the states z_k = int exp(-s_k (t - tau)) dw/dtau dtau of the history kernel's exponential modes
  std::array<std::vector<Vec3>, kHistoryModes> history_mode;

  std::size_t size() const { return added_mass_force.size(); }

  template <class Self, class Visit>
  static void for_each_field(Self& self, Visit&& visit) {
    visit(FieldInfo{"added_mass_force", "N", true, 0.0, 6}, self.added_mass_force);
    visit(FieldInfo{"history_force", "N", true, 0.0, 6}, self.history_force);
    visit(FieldInfo{"history_mass", "kg", false, 0.0, 14}, self.history_mass);
    visit(FieldInfo{"history_relative_velocity", "m/s", false, 0.0, 6}, self.history_relative_velocity);
    for (std::size_t k = 0; k < kHistoryModes; ++k)
      visit(FieldInfo{kHistoryModeNames[k], "m/s", false, 0.0, 6}, self.history_mode[k]);
  }
};

/// Lubrication forces of the water squeezed between a grain and its neighbours or the walls: written by
/// solid_lubrication every sub-step.
struct GrainLubrication {
  static constexpr ComponentId kId = component_id<GrainLubrication>;
  static constexpr std::string_view kName = "grain_lubrication";

  std::vector<Vec3> lubrication_force;  ///< [N] normal lubrication from grain-grain and grain-wall gaps

  std::size_t size() const { return lubrication_force.size(); }

  template <class Self, class Visit>
  static void for_each_field(Self& self, Visit&& visit) {
    visit(FieldInfo{"lubrication_force", "N", true, 0.0, 6}, self.lubrication_force);
  }
};

/// Every role of the grains: the whole table.
struct Solids : EntityGroup<GrainState, GrainProperties, GrainTotalForce, GrainContactForce, GrainDrag,
                            GrainSampledFluid, GrainVoidage, GrainAddedMass, GrainLubrication> {
  static constexpr std::string_view kName = "solids";
  static constexpr bool kPersistent = true;

  /// The order in which checkpoints (frozen by format 4) and VTK frames write the fields: the order of the one table
  /// before the split into roles (for_each_field_in_order); fields added since (format 6 on) at the end.
  static constexpr std::array<const char*, 45> kFieldOrder = {
      "id",           "position",       "velocity",       "angular_velocity", "radius",
      "mass",         "moment_of_inertia", "force",      "torque",           "contact_force",
      "contact_torque", "drag_force",   "drag_impulse",   "pressure_force",   "fluid_velocity",
      "voidage",      "fluid_weight",   "material",       "size_class",
      "undisturbed_velocity", "fluid_acceleration", "added_mass_force", "history_force", "lubrication_force",
      "history_relative_velocity", "history_mode_0", "history_mode_1", "history_mode_2", "history_mode_3",
      "history_mode_4", "history_mode_5", "history_mode_6", "history_mode_7",
      "self_induced_fast", "self_induced_middle", "self_induced_slow", "viscous_force", "fixed",
      "fluctuation_state", "self_induced_wall_x", "self_induced_wall_y", "self_induced_wall_z",
      "ergun_resistance", "ergun_inertial_resistance", "history_mass"};

  EntityId next_id = 0;  ///< the id the next added sphere gets

  std::size_t size() const { return id.size(); }

  /// Appends one sphere at rest, every other field at its default; returns its slot.
  std::size_t add(const Vec3& position_m, const Vec3& velocity_m_s, double radius_m, double density_kg_m3,
                  std::int32_t material_index, std::int32_t size_class_index) {
    const std::size_t slot = size();
    resize_fields(*this, slot + 1);
    id[slot] = next_id++;
    position[slot] = position_m;
    velocity[slot] = velocity_m_s;
    radius[slot] = radius_m;
    mass[slot] = density_kg_m3 * 4.0 / 3.0 * std::numbers::pi * radius_m * radius_m * radius_m;
    moment_of_inertia[slot] = 0.4 * mass[slot] * radius_m * radius_m;
    material[slot] = material_index;
    size_class[slot] = size_class_index;
    return slot;
  }

  /// A field not checkpointed (FieldInfo::checkpointed) is left out, and a field newer than the file read
  /// (FieldInfo::since_format) is not in it: a read gives either its default for every grain.
  template <class Archive>
  void serialize(Archive& archive) {
    archive(next_id);
    bool absent_fields = false;
    for_each_field_in_order(*this, [&](const FieldInfo& info, auto& field) {
      if constexpr (Archive::is_loading::value) {
        bool absent = !info.checkpointed;
        if constexpr (requires { archive.format_version(); })
          absent = absent || archive.format_version() < info.since_format;
        if (absent) {
          field.clear();
          absent_fields = true;
          return;
        }
      } else {
        if (!info.checkpointed) return;
      }
      archive(field);
    });
    if (absent_fields) resize_fields(*this, id.size());
  }
};

}  // namespace riffle
