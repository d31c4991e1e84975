#pragma once
// Wall motion: the single owner of the tank's prescribed kinematics. Moves every wall that follows the tank to the
// end of the (sub)step and gives it the exact velocity. Seed 000 Eq. (1): x = -A sin(2 pi f t), with a C2 start-up
// ramp (the seed: "accelerated gradually at the onset of the oscillation").
#include "components/tank_motion.hpp"
#include "engine/model.hpp"
#include "engine/system.hpp"

namespace riffle {

/// Ramp factor r(t) in [0, 1] and its first two derivatives: r = s^3 (10 - 15 s + 6 s^2), s = t / ramp_time.
struct Ramp {
  double value, rate, curvature;
};
Ramp start_up_ramp(double time, double ramp_time);

/// Displacement, velocity and acceleration of the tank at `time`, exact derivatives of the prescribed motion.
TankMotion tank_kinematics(const TankMotionModel& motion, double time);

/// Places the walls that follow the tank according to `tank` (also used to set up the initial state).
void apply_tank_motion(const TankMotion& tank, Walls& walls);

class WallMotion final : public System {
 public:
  std::string_view name() const override { return "wall_motion"; }
  Access access() const override { return {{}, {ComponentId::kTankMotion, ComponentId::kWalls}}; }
  void run(SystemContext& context) override;
};

}  // namespace riffle
