#include "systems/physics/geometry/tank_kinematics.hpp"

#include <cmath>

#include "systems/physics/math/cubic_spline.hpp"

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

namespace {

TankMotion table_kinematics(const MotionTable& table, double time) {
  TankMotion tank;
  tank.time = time;
  // Outside the table the tank rests at the end's displacement (the scene reader refuses a table the run leaves
  // while moving: engine/scene/scene.cpp).
  const bool inside = time >= table.time.front() && time <= table.time.back();
  for (int axis = 0; axis < 3; ++axis) {
    const auto a = static_cast<std::size_t>(axis);
    if (table.displacement[a].empty()) continue;
    const SplinePoint point = spline_at(table.time, table.displacement[a], table.curvature[a], time);
    tank.displacement[axis] = point.value;
    tank.velocity[axis] = inside ? point.slope : 0.0;
    tank.acceleration[axis] = inside ? point.curvature : 0.0;
  }
  return tank;
}

}  // namespace

TankMotion tank_kinematics(const TankMotionModel& motion, double time) {
  TankMotion tank;
  tank.time = time;
  if (motion.kind == TankMotionModel::Kind::kNone) return tank;
  if (motion.kind == TankMotionModel::Kind::kTable) return table_kinematics(motion.table, time);
  // Before start_time the tank rests where the motion starts. With the defaults (start 0, phase 0) tau = t and the
  // angle is w t exactly, so the seed's motion is unchanged to the bit.
  const bool resting = time < motion.start_time;
  const double tau = resting ? 0.0 : time - motion.start_time;
  const double omega = 2.0 * 3.14159265358979323846 * motion.frequency;
  const double sine = std::sin(omega * tau + motion.phase);
  const double cosine = std::cos(omega * tau + motion.phase);
  const Ramp ramp = start_up_ramp(tau, motion.ramp_time);
  // x = -A r sin(wt); x' = -A (r' sin + r w cos); x'' = -A (r'' sin + 2 r' w cos - r w^2 sin)
  const double x = -motion.amplitude * ramp.value * sine;
  const double v = -motion.amplitude * (ramp.rate * sine + ramp.value * omega * cosine);
  const double a = -motion.amplitude *
                   (ramp.curvature * sine + 2.0 * ramp.rate * omega * cosine - ramp.value * omega * omega * sine);
  tank.displacement = x * motion.direction;
  tank.velocity = resting ? Vec3::Zero() : Vec3(v * motion.direction);
  tank.acceleration = resting ? Vec3::Zero() : Vec3(a * motion.direction);
  return tank;
}

Vec3 tank_motion_sweep(const TankMotionModel& motion) {
  switch (motion.kind) {
    case TankMotionModel::Kind::kNone: return Vec3::Zero();
    case TankMotionModel::Kind::kSinusoidal: return Vec3(motion.amplitude * motion.direction.cwiseAbs());
    case TankMotionModel::Kind::kTable: {
      Vec3 sweep = Vec3::Zero();
      for (std::size_t a = 0; a < 3; ++a)
        if (!motion.table.displacement[a].empty())
          sweep[static_cast<int>(a)] =
              spline_max_abs(motion.table.time, motion.table.displacement[a], motion.table.curvature[a]);
      return sweep;
    }
  }
  return Vec3::Zero();
}

void apply_tank_motion(const TankMotion& tank, Walls& walls) {
  for (std::size_t wall = 0; wall < walls.size(); ++wall) {
    if (!walls.moves_with_tank[wall]) continue;
    walls.point[wall] = walls.rest_point[wall] + tank.displacement;
    walls.velocity[wall] = tank.velocity;
  }
}

}  // namespace riffle
