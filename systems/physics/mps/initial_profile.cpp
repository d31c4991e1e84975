#include "systems/physics/mps/initial_profile.hpp"

#include <cmath>

namespace riffle {

double initial_profile_velocity(const InitialVelocityModel& profile, double z) {
  using Kind = InitialVelocityModel::Kind;
  if (profile.kind == Kind::kNone || z <= profile.bottom) return 0.0;
  if (z >= profile.top) return profile.top_velocity;
  const double eta = (z - profile.bottom) / (profile.top - profile.bottom);
  return profile.top_velocity * (profile.kind == Kind::kLinear ? eta : std::pow(eta, profile.exponent));
}

}  // namespace riffle
