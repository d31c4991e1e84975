#include "systems/dem/solid_integrate.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "systems/physics/tank_kinematics.hpp"

namespace riffle {

namespace {
constexpr std::size_t kGrain = 1024;

void half_kick(Solids& solids, const Vec3& gravity, double half_dt, std::size_t begin, std::size_t end) {
  for (std::size_t i = begin; i < end; ++i) {
    solids.velocity[i] += half_dt * (solids.force[i] / solids.mass[i] + gravity);
    solids.angular_velocity[i] += (half_dt / solids.moment_of_inertia[i]) * solids.torque[i];
  }
}
}  // namespace

void SolidKickDrift::run(SystemContext& context) {
  Solids& solids = context.write<Solids>();
  const Vec3 gravity = context.model.gravity;
  const double dt = context.dt;
  if (context.model.solids.fixed_to_tank) {  // a fixed bed: the tank's displacement over the sub-step, exactly
    const TankMotion start = tank_kinematics(context.model.tank.motion, context.time);
    const TankMotion end = tank_kinematics(context.model.tank.motion, context.time + dt);
    for (std::size_t i = 0; i < solids.size(); ++i) {
      solids.position[i] += end.displacement - start.displacement;
      solids.velocity[i] = end.velocity;
      solids.angular_velocity[i] = Vec3::Zero();
    }
    context.count_items(solids.size());
    return;
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, solids.size(), kGrain),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      half_kick(solids, gravity, 0.5 * dt, range.begin(), range.end());
                      for (std::size_t i = range.begin(); i < range.end(); ++i)
                        solids.position[i] += dt * solids.velocity[i];
                    });
  context.count_items(solids.size());
}

void SolidKick::run(SystemContext& context) {
  Solids& solids = context.write<Solids>();
  const Vec3 gravity = context.model.gravity;
  const double half_dt = 0.5 * context.dt;
  if (context.model.solids.fixed_to_tank) return;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, solids.size(), kGrain),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      half_kick(solids, gravity, half_dt, range.begin(), range.end());
                    });
  context.count_items(solids.size());
}

}  // namespace riffle
