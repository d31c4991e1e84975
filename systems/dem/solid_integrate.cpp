#include "systems/dem/solid_integrate.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "systems/physics/tank_kinematics.hpp"

namespace riffle {

namespace {
constexpr std::size_t kGrain = 1024;

void half_kick(GrainState& grains, const GrainProperties& properties, const GrainTotalForce& total, const Vec3& gravity, double half_dt, std::size_t begin, std::size_t end) {
  for (std::size_t i = begin; i < end; ++i) {
    grains.velocity[i] += half_dt * (total.force[i] / properties.mass[i] + gravity);
    grains.angular_velocity[i] += (half_dt / properties.moment_of_inertia[i]) * total.torque[i];
  }
}
}  // namespace

void SolidKickDrift::run(SystemContext& context) {
  GrainState& grains = context.write<GrainState>();
  const GrainProperties& properties = context.read<GrainProperties>();
  const GrainTotalForce& total = context.read<GrainTotalForce>();
  const Vec3 gravity = context.model.gravity;
  const double dt = context.dt;
  if (context.model.solids.fixed_to_tank) {  // a fixed bed: the tank's displacement over the sub-step, exactly
    const TankMotion start = tank_kinematics(context.model.tank.motion, context.time);
    const TankMotion end = tank_kinematics(context.model.tank.motion, context.time + dt);
    for (std::size_t i = 0; i < grains.size(); ++i) {
      grains.position[i] += end.displacement - start.displacement;
      grains.velocity[i] = end.velocity;
      grains.angular_velocity[i] = Vec3::Zero();
    }
    context.count_items(grains.size());
    return;
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, grains.size(), kGrain),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      half_kick(grains, properties, total, gravity, 0.5 * dt, range.begin(), range.end());
                      for (std::size_t i = range.begin(); i < range.end(); ++i)
                        grains.position[i] += dt * grains.velocity[i];
                    });
  context.count_items(grains.size());
}

void SolidKick::run(SystemContext& context) {
  GrainState& grains = context.write<GrainState>();
  const GrainProperties& properties = context.read<GrainProperties>();
  const GrainTotalForce& total = context.read<GrainTotalForce>();
  const Vec3 gravity = context.model.gravity;
  const double half_dt = 0.5 * context.dt;
  if (context.model.solids.fixed_to_tank) return;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, grains.size(), kGrain),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      half_kick(grains, properties, total, gravity, half_dt, range.begin(), range.end());
                    });
  context.count_items(grains.size());
}

}  // namespace riffle
