#pragma once
// Kinematics of the shaken tank at the current time: one rigid translation shared by every wall that follows it
// (and, later, the fluid's wall particles and the non-inertial forcing of the fluid).
#include "components/component_id.hpp"
#include "components/vec.hpp"

namespace riffle {

struct TankMotion {
  static constexpr ComponentId kId = component_id<TankMotion>;
  static constexpr std::string_view kName = "tank_motion";
  static constexpr bool kPersistent = true;

  double time = 0.0;                        ///< [s] the time these kinematics belong to
  Vec3 displacement = Vec3::Zero();         ///< [m] from the rest position
  Vec3 velocity = Vec3::Zero();             ///< [m/s] exact derivative of displacement
  Vec3 acceleration = Vec3::Zero();         ///< [m/s^2] exact second derivative

  template <class Archive>
  void serialize(Archive& archive) {
    archive(time, displacement, velocity, acceleration);
  }
};

}  // namespace riffle
