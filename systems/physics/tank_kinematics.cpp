#include "systems/physics/tank_kinematics.hpp"

#include <cmath>

namespace riffle {

Ramp start_up_ramp(double time, double ramp_time) {
  if (ramp_time <= 0.0 || time >= ramp_time) return {1.0, 0.0, 0.0};
  if (time <= 0.0) return {0.0, 0.0, 0.0};
  const double s = time / ramp_time;
  const double value = s * s * s * (10.0 + s * (-15.0 + 6.0 * s));
  const double rate = 30.0 * s * s * (1.0 - s) * (1.0 - s) / ramp_time;
  const double curvature = 60.0 * s * (1.0 - s) * (1.0 - 2.0 * s) / (ramp_time * ramp_time);
  return {value, rate, curvature};
}

TankMotion tank_kinematics(const TankMotionModel& motion, double time) {
  TankMotion tank;
  tank.time = time;
  if (motion.kind == TankMotionModel::Kind::kNone) return tank;
  const double omega = 2.0 * 3.14159265358979323846 * motion.frequency;
  const double sine = std::sin(omega * time);
  const double cosine = std::cos(omega * time);
  const Ramp ramp = start_up_ramp(time, motion.ramp_time);
  // x = -A r sin(wt); x' = -A (r' sin + r w cos); x'' = -A (r'' sin + 2 r' w cos - r w^2 sin)
  const double x = -motion.amplitude * ramp.value * sine;
  const double v = -motion.amplitude * (ramp.rate * sine + ramp.value * omega * cosine);
  const double a = -motion.amplitude *
                   (ramp.curvature * sine + 2.0 * ramp.rate * omega * cosine - ramp.value * omega * omega * sine);
  tank.displacement = x * motion.direction;
  tank.velocity = v * motion.direction;
  tank.acceleration = a * motion.direction;
  return tank;
}

void apply_tank_motion(const TankMotion& tank, Walls& walls) {
  for (std::size_t wall = 0; wall < walls.size(); ++wall) {
    if (!walls.moves_with_tank[wall]) continue;
    walls.point[wall] = walls.rest_point[wall] + tank.displacement;
    walls.velocity[wall] = tank.velocity;
  }
}

}  // namespace riffle
