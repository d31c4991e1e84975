// The bed-load measures of the mean-flow fluid (systems/physics/measures/bedload_transport.hpp) on grains and a
// column set by hand, against the definitions worked by hand: Theta of the stress the water above the bed carries,
// q* of the mobile grains' flux, the moving fraction, the moving grains' mean speed and height, and the speed of
// those moving above the bed surface (the bed-load layer); fixed grains count in none of them.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "systems/physics/measures/bedload_transport.hpp"

using namespace riffle;

TEST_CASE("bed-load transport: Theta, q*, the moving fraction and the moving grains' speed, all and above the bed") {
  Model model;
  model.mean_flow.enabled = true;
  model.mean_flow.density = 1000.0;
  model.mean_flow.top = 0.04;
  model.tank.size = Vec3(0.02, 0.01, 0.05);
  Solids grains;
  const double radius = 0.001, density = 2650.0;
  // z_bed = 10 mm. A fixed grain (moving fast: it must count nowhere), a resting grain in the bed, a grain creeping in
  // the bed at 0.02 m/s, and two moving above the bed at 0.10 and 0.30 m/s.
  grains.add(Vec3(0.001, 0.005, 0.001), Vec3(5.0, 0.0, 0.0), radius, density, 0, 0);
  grains.add(Vec3(0.005, 0.005, 0.007), Vec3::Zero(), radius, density, 0, 0);
  grains.add(Vec3(0.009, 0.005, 0.009), Vec3(0.02, 0.0, 0.0), radius, density, 0, 0);
  grains.add(Vec3(0.013, 0.005, 0.011), Vec3(0.10, 0.0, 0.005), radius, density, 0, 0);
  grains.add(Vec3(0.017, 0.005, 0.012), Vec3(0.30, 0.0, 0.0), radius, density, 0, 0);
  grains.fixed[0] = 1;
  MeanFlowColumn column;
  column.bed_surface = 0.010;
  column.body_force = 0.01;  // [m/s^2]: tau_b = rho f (top - z_bed) = 0.3 Pa
  column.top_stress = 0.0;
  const ShieldsGrain grain = shields_grain(model, grains);
  CHECK(grain.diameter == doctest::Approx(0.002));
  CHECK(grain.density == doctest::Approx(2650.0));
  const BedloadTransport out = bedload_transport(model, grains, column, grain, 0.01);
  CHECK(out.bed_stress == doctest::Approx(0.3));
  CHECK(out.shields == doctest::Approx(0.3 / (1650.0 * 9.81 * 0.002)));
  CHECK(out.friction_velocity == doctest::Approx(std::sqrt(0.3e-3)));
  const double volume = 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
  const double flux = volume * (0.02 + 0.10 + 0.30) / (0.02 * 0.01);
  CHECK(out.flux == doctest::Approx(flux));
  CHECK(out.flux_star == doctest::Approx(flux / std::sqrt(1.65 * 9.81 * 0.002 * 0.002 * 0.002)));
  CHECK(out.moving == 3);
  CHECK(out.moving_fraction == doctest::Approx(3.0 / 4.0));
  CHECK(out.moving_speed == doctest::Approx((0.02 + 0.10 + 0.30) / 3.0));
  CHECK(out.moving_height == doctest::Approx((-0.001 + 0.001 + 0.002) / 3.0));
  CHECK(out.moving_above_bed == 2);
  CHECK(out.moving_above_bed_speed == doctest::Approx((0.10 + 0.30) / 2.0));
  // Nothing above the bed moving: zero, not a division by zero.
  grains.velocity[3] = grains.velocity[4] = Vec3::Zero();
  const BedloadTransport still = bedload_transport(model, grains, column, grain, 0.01);
  CHECK(still.moving_above_bed == 0);
  CHECK(still.moving_above_bed_speed == 0.0);
}
