#pragma once
// The tank's prescribed kinematics, seed 000 Eq. (1): x = -A sin(2 pi f t), with a C2 start-up ramp (the seed:
// "accelerated gradually at the onset of the oscillation"), a phase and a start time; or a tabulated motion
// interpolated by a cubic spline. Exact derivatives, evaluated at any time, so that the
// walls, the wall particles and the initial state all see the same motion.
#include "components/model.hpp"
#include "components/tank_motion.hpp"
#include "components/walls.hpp"

namespace riffle {

/// Ramp factor r(t) in [0, 1] and its first two derivatives: r = s^3 (10 - 15 s + 6 s^2), s = t / ramp_time.
struct Ramp {
  double value, rate, curvature;
};
Ramp start_up_ramp(double time, double ramp_time);

/// Displacement, velocity and acceleration of the tank at `time`, exact derivatives of the prescribed motion
/// (components/model.hpp TankMotionModel: a sinusoid with ramp, phase and start time, or a spline through a table).
TankMotion tank_kinematics(const TankMotionModel& motion, double time);

/// The largest |displacement| along each axis the motion ever reaches (the domain's sweep): A |direction| for the
/// sinusoid, the spline's exact maximum per axis for a table.
Vec3 tank_motion_sweep(const TankMotionModel& motion);

/// Places the walls that follow the tank according to `tank` (also used to set up the initial state).
void apply_tank_motion(const TankMotion& tank, Walls& walls);

}  // namespace riffle
