// The threshold and transport laws of systems/physics/measures/bedload.hpp against values worked by hand from the papers'
// constants (seed 003's grains: d = 1 and 2 mm quartz, s = 2.65, in water, nu = 1e-6 m^2/s, g = 9.81 m/s^2).
#include <doctest/doctest.h>

#include <cmath>

#include "systems/physics/measures/bedload.hpp"

using namespace riffle;

namespace {
constexpr double kG = 9.81, kS = 2.65, kNu = 1.0e-6;
}  // namespace

TEST_CASE("dimensionless grain size and particle Reynolds number of 1 and 2 mm sand in water") {
  // D* = d [g (s-1) / nu^2]^(1/3): (9.81 * 1.65 / 1e-12)^(1/3) = (1.61865e13)^(1/3) = 25296 per metre.
  CHECK(dimensionless_grain_size(1e-3, kS, kG, kNu) == doctest::Approx(25.296).epsilon(1e-4));
  CHECK(dimensionless_grain_size(2e-3, kS, kG, kNu) == doctest::Approx(50.592).epsilon(1e-4));
  // Re_p = sqrt(1.65 * 9.81 * 1e-3) * 1e-3 / 1e-6 = 0.127226 * 1000 = 127.23; and Re_p = D*^(3/2).
  CHECK(particle_reynolds_number(1e-3, kS, kG, kNu) == doctest::Approx(127.23).epsilon(1e-4));
  const double grain_size = dimensionless_grain_size(2e-3, kS, kG, kNu);
  CHECK(particle_reynolds_number(2e-3, kS, kG, kNu) == doctest::Approx(std::pow(grain_size, 1.5)).epsilon(1e-12));
  // Re_f = u* d / nu with u* = sqrt(Theta (s-1) g d): Theta = 0.04, d = 1 mm: u* = 0.025445 m/s, Re_f = 25.445.
  CHECK(friction_reynolds_number(0.04, 127.226) == doctest::Approx(25.445).epsilon(1e-4));
  CHECK(std::isnan(dimensionless_grain_size(1e-3, 0.9, kG, kNu)));  // a grain lighter than water
  CHECK(std::isnan(particle_reynolds_number(0.0, kS, kG, kNu)));
}

TEST_CASE("the Shields curve of Soulsby & Whitehouse (1997) and of Brownlie (1981)") {
  // Soulsby & Whitehouse: 0.30 / (1 + 1.2 D*) + 0.055 (1 - exp(-0.020 D*)).
  // D* = 1: 0.30 / 2.2 + 0.055 (1 - 0.980199) = 0.136364 + 0.001089 = 0.137453.
  CHECK(shields_threshold_soulsby_whitehouse(1.0) == doctest::Approx(0.137453).epsilon(1e-5));
  // D* = 25.296 (1 mm): 0.30 / 31.355 + 0.055 (1 - exp(-0.50592)) = 0.009568 + 0.055 * 0.39702 = 0.031404.
  CHECK(shields_threshold_soulsby_whitehouse(25.296) == doctest::Approx(0.031404).epsilon(1e-4));
  // Coarse grains: 0.055 (the fit's asymptote); D* -> 0: 0.30.
  CHECK(shields_threshold_soulsby_whitehouse(1e6) == doctest::Approx(0.055).epsilon(1e-6));
  CHECK(shields_threshold_soulsby_whitehouse(1e-9) == doctest::Approx(0.30).epsilon(1e-6));
  // Brownlie: 0.22 Y + 0.06 10^(-7.7 Y), Y = Re_p^-0.6. Re_p = 127.23 (1 mm): Y = exp(-0.6 ln 127.23) = 0.054631,
  // 0.22 Y = 0.012019, 10^(-0.42066) = 0.37970, 0.06 * 0.37970 = 0.022782: 0.034801.
  CHECK(shields_threshold_brownlie(127.23) == doctest::Approx(0.034801).epsilon(1e-4));
  // Re_p = 1: 0.22 + 0.06 * 10^-7.7 = 0.22000000120.
  CHECK(shields_threshold_brownlie(1.0) == doctest::Approx(0.2200000012).epsilon(1e-9));
  CHECK(shields_threshold_brownlie(1e12) == doctest::Approx(0.06).epsilon(1e-4));  // coarse: Shields' 0.06
  CHECK(std::isnan(shields_threshold_brownlie(0.0)));
  CHECK(std::isnan(shields_threshold_soulsby_whitehouse(-1.0)));
}

TEST_CASE("bed-load laws of Meyer-Peter & Mueller (1948) and Wong & Parker (2006)") {
  // MPM 8 (Theta - 0.047)^1.5: Theta = 0.1: 8 * 0.053^1.5 = 8 * 0.0122015 = 0.097612.
  CHECK(bedload_meyer_peter_mueller(0.1) == doctest::Approx(0.097612).epsilon(1e-5));
  // Theta = 0.3: 8 * 0.253^1.5 = 8 * 0.127257 = 1.018054.
  CHECK(bedload_meyer_peter_mueller(0.3) == doctest::Approx(1.018054).epsilon(1e-5));
  // Wong-Parker 3.97 (Theta - 0.0495)^1.5: Theta = 0.1: 3.97 * 0.0505^1.5 = 3.97 * 0.0113485 = 0.045053.
  CHECK(bedload_wong_parker(0.1) == doctest::Approx(0.045053).epsilon(1e-5));
  // At and below each threshold: none.
  CHECK(bedload_meyer_peter_mueller(0.047) == 0.0);
  CHECK(bedload_meyer_peter_mueller(0.02) == 0.0);
  CHECK(bedload_wong_parker(0.0495) == 0.0);
  CHECK(bedload_wong_parker(0.048) == 0.0);
  // q_s = q* sqrt((s-1) g d^3): d = 1 mm: sqrt(1.65 * 9.81 * 1e-9) = 1.27226e-4 m^2/s per unit q*.
  CHECK(bedload_volume_flux(1.0, 1e-3, kS, kG) == doctest::Approx(1.27226e-4).epsilon(1e-5));
  CHECK(einstein_number(bedload_volume_flux(0.37, 2e-3, kS, kG), 2e-3, kS, kG) == doctest::Approx(0.37).epsilon(1e-12));
  CHECK(std::isnan(einstein_number(1e-4, 1e-3, 1.0, kG)));
}
