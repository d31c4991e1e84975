#include "systems/dem/solid_integrate.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "systems/physics/coupling/added_mass.hpp"
#include "systems/physics/geometry/tank_kinematics.hpp"

namespace riffle {

KickSettings KickSettings::from(const Model& model) {
  KickSettings settings;
  settings.added_mass = model.coupling.enabled && model.coupling.added_mass;
  settings.history = model.coupling.enabled && model.coupling.history_force;
  settings.fluid_velocity = model.coupling.fluid_velocity;
  settings.fluid_density = model.water_density();
  return settings;
}

namespace {
constexpr std::size_t kIntegrateChunk = 1024;  // grains per parallel task

Access kick_access(const KickSettings& settings) {
  // Without the inertial forces the kicks touch only the motion, as before they existed (the step graph is
  // unchanged with both switches off).
  if (!settings.any()) return {component_ids<GrainProperties, GrainTotalForce>(), component_ids<GrainState>()};
  return {component_ids<GrainProperties, GrainTotalForce, GrainSampledFluid, GrainVoidage>(),
          component_ids<GrainState, GrainDrag, GrainAddedMass>()};
}

void half_kick(GrainState& grains, const GrainProperties& properties, const GrainTotalForce& total, const Vec3& gravity, double half_dt, std::size_t begin, std::size_t end) {
  for (std::size_t i = begin; i < end; ++i) {
    if (properties.fixed[i]) continue;  // carried with the tank by the drift (drift_range)
    grains.velocity[i] += half_dt * (total.force[i] / properties.mass[i] + gravity);
    grains.angular_velocity[i] += (half_dt / properties.moment_of_inertia[i]) * total.torque[i];
  }
}

/// The fluid's inertial forces on the grains, for the half kick with them.
struct InertialForces {
  const KickSettings& settings;
  const GrainSampledFluid& sampled;
  const GrainVoidage& voidages;
  GrainDrag& drag;
  GrainAddedMass& added;
};

/// A half kick with added mass and the history force's own step (both implicit, m_a + m_H) and the history of the
/// earlier steps: the linear momentum the fluid gave the grain beyond F ((m_a + m_H) (a_f - dv/dt) + F_H, times
/// half_dt) goes to its drag impulse for the water to take back. added_mass_force holds both implicit parts.
void half_kick_inertial(GrainState& grains, const GrainProperties& properties, const GrainTotalForce& total,
                        const InertialForces& fluid, const Vec3& gravity, double half_dt, std::size_t begin,
                        std::size_t end) {
  // rho 4/3 pi: the grain's volume as grain_volume() counts it, without its pow (this loop runs twice a sub-step).
  const double density_volume = fluid.settings.fluid_density * 4.0 / 3.0 * 3.14159265358979323846;
  for (std::size_t i = begin; i < end; ++i) {
    const bool wet = fluid.sampled.fluid_weight[i] > 0.0;
    const Vec3 history = fluid.settings.history && wet ? fluid.added.history_force[i] : Vec3::Zero();
    if (properties.fixed[i]) {
      // As a held bed: no added mass (the fluid's forces do not accelerate it); the water takes back the history
      // force, as it takes the drag.
      fluid.added.added_mass_force[i] = Vec3::Zero();
      fluid.drag.drag_impulse[i] += half_dt * history;
      continue;
    }
    const double r = properties.radius[i];
    const double coefficient =
        fluid.settings.added_mass && wet
            ? stable_added_mass_coefficient(fluid.voidages.voidage[i], fluid.settings.fluid_velocity)
            : 0.0;
    const double added_mass = coefficient * density_volume * (r * r * r);
    // The history force of the step's own change of slip, m_H (a_f - dv/dt), is implicit beside the added mass.
    const double history_mass = fluid.settings.history && wet ? fluid.added.history_mass[i] : 0.0;
    const double implicit_mass = added_mass + history_mass;
    const AddedMassKick kick = added_mass_kick(total.force[i] + history, properties.mass[i], implicit_mass, gravity,
                                               fluid.sampled.fluid_acceleration[i], half_dt);
    grains.velocity[i] += kick.velocity_change;
    grains.angular_velocity[i] += (half_dt / properties.moment_of_inertia[i]) * total.torque[i];
    fluid.added.added_mass_force[i] = kick.force;
    fluid.drag.drag_impulse[i] += half_dt * (kick.force + history);
  }
}

/// The tank's motion over one sub-step, which carries the fixed grains.
struct TankStep {
  Vec3 displacement = Vec3::Zero();  ///< [m] over the sub-step
  Vec3 end_velocity = Vec3::Zero();  ///< [m/s] at its end
};

TankStep tank_motion_over_step(const SystemContext& context) {
  const TankMotion start = tank_kinematics(context.model.tank.motion, context.time);
  const TankMotion end = tank_kinematics(context.model.tank.motion, context.time + context.dt);
  return {end.displacement - start.displacement, end.velocity};
}

/// x += dt v for a free grain; a fixed one moves with the tank, exactly, at its velocity and without spin (the
/// second half kick leaves it so).
void drift_range(GrainState& grains, const GrainProperties& properties, const TankStep& tank, double dt,
                 std::size_t begin, std::size_t end) {
  for (std::size_t i = begin; i < end; ++i) {
    if (properties.fixed[i]) {
      grains.position[i] += tank.displacement;
      grains.velocity[i] = tank.end_velocity;
      grains.angular_velocity[i] = Vec3::Zero();
    } else {
      grains.position[i] += dt * grains.velocity[i];
    }
  }
}

/// Both kinds of half kick over a range of grains.
void kick_range(SystemContext& context, const KickSettings& settings, double half_dt, bool drift) {
  GrainState& grains = context.write<GrainState>();
  const GrainProperties& properties = context.read<GrainProperties>();
  const GrainTotalForce& total = context.read<GrainTotalForce>();
  const Vec3 gravity = context.model.gravity;
  const double dt = context.dt;
  const TankStep tank_step = drift ? tank_motion_over_step(context) : TankStep{};
  if (!settings.any()) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, grains.size(), kIntegrateChunk),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        half_kick(grains, properties, total, gravity, half_dt, range.begin(), range.end());
                        if (drift) drift_range(grains, properties, tank_step, dt, range.begin(), range.end());
                      });
    return;
  }
  const InertialForces fluid{settings, context.read<GrainSampledFluid>(), context.read<GrainVoidage>(),
                             context.write<GrainDrag>(), context.write<GrainAddedMass>()};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, grains.size(), kIntegrateChunk),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      half_kick_inertial(grains, properties, total, fluid, gravity, half_dt, range.begin(),
                                         range.end());
                      if (drift) drift_range(grains, properties, tank_step, dt, range.begin(), range.end());
                    });
}
}  // namespace

Access SolidKickDrift::access() const { return kick_access(settings_); }
Access SolidKick::access() const { return kick_access(settings_); }

void SolidKickDrift::run(SystemContext& context) {
  const double dt = context.dt;
  // A fixed bed ([solids] fixed_to_tank, or held until hold_until): the tank's displacement over the sub-step, exactly.
  if (context.model.solids.held(context.time)) {
    GrainState& grains = context.write<GrainState>();
    const TankStep tank = tank_motion_over_step(context);
    for (std::size_t i = 0; i < grains.size(); ++i) {
      grains.position[i] += tank.displacement;
      grains.velocity[i] = tank.end_velocity;
      grains.angular_velocity[i] = Vec3::Zero();
    }
    // The held grains still feel the history force (no added mass: they do not accelerate by the fluid's
    // forces); the water takes it back, as it takes their drag.
    if (settings_.history) {
      GrainDrag& drag = context.write<GrainDrag>();
      const GrainAddedMass& added = context.read<GrainAddedMass>();
      for (std::size_t i = 0; i < grains.size(); ++i) drag.drag_impulse[i] += dt * added.history_force[i];
    }
    context.count_items(grains.size());
    return;
  }
  kick_range(context, settings_, 0.5 * dt, true);
  context.count_items(context.read<GrainProperties>().size());
}

void SolidKick::run(SystemContext& context) {
  if (context.model.solids.held(context.time)) return;
  kick_range(context, settings_, 0.5 * context.dt, false);
  context.count_items(context.read<GrainProperties>().size());
}

}  // namespace riffle
