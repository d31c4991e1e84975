// The initial velocity profile's law (systems/physics/mps/initial_profile.hpp) against hand-worked values.
#include <doctest/doctest.h>

#include "systems/physics/mps/initial_profile.hpp"

using namespace riffle;

TEST_CASE("initial profile: zero below z0, u_top above z1, linear or 1/7 power between") {
  InitialVelocityModel profile;
  profile.bottom = 0.005;
  profile.top = 0.02;
  profile.top_velocity = 0.4;
  CHECK(initial_profile_velocity(profile, 0.01) == 0.0);  // kNone
  profile.kind = InitialVelocityModel::Kind::kLinear;
  CHECK(initial_profile_velocity(profile, 0.0) == 0.0);
  CHECK(initial_profile_velocity(profile, 0.005) == 0.0);
  CHECK(initial_profile_velocity(profile, 0.0125) == doctest::Approx(0.2).epsilon(1e-14));  // mid-way: u_top / 2
  CHECK(initial_profile_velocity(profile, 0.02) == 0.4);
  CHECK(initial_profile_velocity(profile, 0.03) == 0.4);
  profile.kind = InitialVelocityModel::Kind::kPower;
  // (1/128)^(1/7) = 1/2: at z0 + (z1 - z0)/128 the 1/7-power profile is at half the lid speed; at mid-height
  // 2^(-1/7) = 0.905723664264...
  CHECK(initial_profile_velocity(profile, 0.005 + 0.015 / 128.0) == doctest::Approx(0.2).epsilon(1e-13));
  CHECK(initial_profile_velocity(profile, 0.0125) == doctest::Approx(0.4 * 0.905723664264).epsilon(1e-11));
  CHECK(initial_profile_velocity(profile, 0.004) == 0.0);
  CHECK(initial_profile_velocity(profile, 0.025) == 0.4);
  profile.exponent = 0.5;
  CHECK(initial_profile_velocity(profile, 0.005 + 0.015 / 4.0) == doctest::Approx(0.2).epsilon(1e-14));
}
