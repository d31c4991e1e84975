#pragma once
// Solid grains (DEM spheres) as structure-of-arrays data. One entry per sphere; slot order may change when the
// grains are sorted by grid cell, `id` never does.
#include <cereal/types/vector.hpp>
#include <cstdint>
#include <vector>

#include "components/component_id.hpp"
#include "components/soa.hpp"
#include "components/vec.hpp"

namespace riffle {

struct Solids {
  static constexpr ComponentId kId = ComponentId::kSolids;

  std::vector<EntityId> id;            ///< [1] stable identity
  std::vector<Vec3> position;          ///< [m] centre, lab frame; filled by the integrator
  std::vector<Vec3> velocity;          ///< [m/s] centre velocity, lab frame
  std::vector<Vec3> angular_velocity;  ///< [rad/s]
  std::vector<double> radius;          ///< [m]
  std::vector<double> mass;            ///< [kg]
  std::vector<double> moment_of_inertia;  ///< [kg m^2] about the centre (solid sphere: 2/5 m r^2)
  std::vector<Vec3> force;             ///< [N] sum of the non-gravity force sources below (solid_force_sum)
  std::vector<Vec3> torque;            ///< [N m] sum of the torque sources below
  std::vector<Vec3> contact_force;     ///< [N] from grain-grain and grain-wall contacts (solid_contact_gather)
  std::vector<Vec3> contact_torque;    ///< [N m] from contacts, rolling friction included
  // Fluid coupling (seed 000 Sec. 3.2-3.3): fields sampled from the fluid once per fluid step, and the drag.
  std::vector<Vec3> drag_force;        ///< [N] drag of the fluid on the grain, recomputed every sub-step (solid_drag)
  std::vector<Vec3> drag_impulse;      ///< [N s] drag integrated over the sub-steps since the fluid last took it back
  std::vector<Vec3> pressure_force;    ///< [N] -V <grad p>, held over the fluid step (solid_fluid_sampling)
  std::vector<Vec3> fluid_velocity;    ///< [m/s] averaged fluid velocity (seed Eq. 23) at the step start
  std::vector<double> voidage;         ///< [1] fluid volume fraction epsilon at the step end; 1 if dry
  std::vector<double> fluid_weight;    ///< [1] sum of the sampling weights of the fluid around the grain; 0 = dry
  std::vector<std::int32_t> material;  ///< [1] index into the scene's material table
  std::vector<std::int32_t> size_class;  ///< [1] index into the scene's size classes (for per-class output)

  EntityId next_id = 0;  ///< the id the next added sphere gets

  template <class Self, class Visit>
  static void for_each_field(Self& self, Visit&& visit) {
    visit(FieldInfo{"id", "1", true}, self.id);
    visit(FieldInfo{"position", "m", false}, self.position);  // VTK points, not a point-data array
    visit(FieldInfo{"velocity", "m/s", true}, self.velocity);
    visit(FieldInfo{"angular_velocity", "rad/s", true}, self.angular_velocity);
    visit(FieldInfo{"radius", "m", true}, self.radius);
    visit(FieldInfo{"mass", "kg", true}, self.mass);
    visit(FieldInfo{"moment_of_inertia", "kg m^2", false}, self.moment_of_inertia);
    visit(FieldInfo{"force", "N", true}, self.force);
    visit(FieldInfo{"torque", "N m", true}, self.torque);
    visit(FieldInfo{"contact_force", "N", true}, self.contact_force);
    visit(FieldInfo{"contact_torque", "N m", false}, self.contact_torque);
    visit(FieldInfo{"drag_force", "N", true}, self.drag_force);
    visit(FieldInfo{"drag_impulse", "N s", false}, self.drag_impulse);
    visit(FieldInfo{"pressure_force", "N", true}, self.pressure_force);
    visit(FieldInfo{"fluid_velocity", "m/s", true}, self.fluid_velocity);
    visit(FieldInfo{"voidage", "1", true}, self.voidage);
    visit(FieldInfo{"fluid_weight", "1", true}, self.fluid_weight);
    visit(FieldInfo{"material", "1", true}, self.material);
    visit(FieldInfo{"size_class", "1", true}, self.size_class);
  }

  std::size_t size() const { return id.size(); }

  /// Appends one sphere at rest-free state; returns its slot.
  std::size_t add(const Vec3& position_m, const Vec3& velocity_m_s, double radius_m, double density_kg_m3,
                  std::int32_t material_index, std::int32_t size_class_index) {
    const std::size_t slot = size();
    resize_fields(*this, slot + 1);
    const double kPi = 3.14159265358979323846;
    id[slot] = next_id++;
    position[slot] = position_m;
    velocity[slot] = velocity_m_s;
    angular_velocity[slot] = Vec3::Zero();
    radius[slot] = radius_m;
    mass[slot] = density_kg_m3 * 4.0 / 3.0 * kPi * radius_m * radius_m * radius_m;
    moment_of_inertia[slot] = 0.4 * mass[slot] * radius_m * radius_m;
    force[slot] = Vec3::Zero();
    torque[slot] = Vec3::Zero();
    contact_force[slot] = Vec3::Zero();
    contact_torque[slot] = Vec3::Zero();
    drag_force[slot] = Vec3::Zero();
    drag_impulse[slot] = Vec3::Zero();
    pressure_force[slot] = Vec3::Zero();
    fluid_velocity[slot] = Vec3::Zero();
    voidage[slot] = 1.0;
    fluid_weight[slot] = 0.0;
    material[slot] = material_index;
    size_class[slot] = size_class_index;
    return slot;
  }

  template <class Archive>
  void serialize(Archive& archive) {
    archive(next_id);
    for_each_field(*this, [&](const FieldInfo&, auto& field) { archive(field); });
  }
};

}  // namespace riffle
