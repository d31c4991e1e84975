// The pieces of the pressure probes in systems/physics/measures/pressure_sensor.hpp: the full-support density against a
// direct integral and the MPS lattice, the wetted fraction at a free surface, a wall and a drop, the reading rule,
// and the disc quadrature against the analytic averages of a linear field and of a half-submerged disc.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "components/vec.hpp"
#include "systems/physics/mps/mps_kernel.hpp"
#include "systems/physics/measures/pressure_sensor.hpp"
#include "tests/support/test_support.hpp"

using namespace riffle;

namespace {


/// Sum of w over the cubic lattice of spacing 1 with sites at half-integers (the fluid layout of a box from the
/// origin) that `keep` accepts, at point x.
template <class Keep>
double lattice_sum(const WendlandKernel& kernel, const Vec3& x, Keep keep) {
  double sum = 0.0;
  for (int i = -8; i <= 8; ++i)
    for (int j = -8; j <= 8; ++j)
      for (int k = -8; k <= 8; ++k) {
        const Vec3 site(i + 0.5, j + 0.5, k + 0.5);
        if (keep(site)) sum += kernel.weight((site - x).norm());
      }
  return sum;
}

using test::half_submerged_mean;

}  // namespace

TEST_CASE("the full-support density is the kernel's volume integral, and the lattice's sums lie within 2 % of it") {
  const double ratio = 2.4;
  // int_0^re w(r) 4 pi r^2 dr by the composite Simpson rule (the integrand is a polynomial of degree 7 on [0, r_e]:
  // 2000 intervals leave ~1e-13).
  const WendlandKernel kernel{ratio};
  const int n = 2000;
  double integral = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double r = ratio * i / n;
    const double f = kernel.weight(r) * 4.0 * std::numbers::pi * r * r;
    integral += f * (i == 0 || i == n ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0));
  }
  integral *= ratio / n / 3.0;
  CHECK(full_support_density(1.0, ratio) == doctest::Approx(integral).epsilon(1e-10));
  CHECK(full_support_density(0.01, 0.024) == doctest::Approx(integral).epsilon(1e-10));  // depends on r_e / l0 only
  const double full = full_support_density(1.0, ratio);
  for (const Vec3& x : {Vec3(0.5, 0.5, 0.5), Vec3(0.0, 0.0, 0.0), Vec3(0.0, 0.5, 0.5), Vec3(0.23, 0.07, 0.41)}) {
    CAPTURE(x.transpose());
    CHECK(std::abs(lattice_sum(kernel, x, [](const Vec3&) { return true; }) / full - 1.0) < 0.02);
  }
}

TEST_CASE("the wetted fraction: one half at a free surface and at a wall's water line, at most 0.24 for a drop") {
  const double ratio = 2.4;
  const WendlandKernel kernel{ratio};
  const double full = full_support_density(1.0, ratio);
  const auto water_below = [](const Vec3& site) { return site.z() < 0.0; };
  // A point on a flat surface of water filling z < 0 (sites at half-integers: the surface is l0/2 above the top
  // layer, as a particle stands for a cube of side l0): half of its support.
  const double on_surface = wetted_fraction(lattice_sum(kernel, Vec3(0.0, 0.0, 0.0), water_below), 0.0, full);
  CHECK(on_surface == doctest::Approx(0.5).epsilon(0.02));
  CHECK(on_surface >= kWetFractionThreshold);
  // l0/2 above the surface: dry by the rule (and its extrapolation is negative there anyway).
  CHECK(wetted_fraction(lattice_sum(kernel, Vec3(0.0, 0.0, 0.5), water_below), 0.0, full) < kWetFractionThreshold);
  // On a wall (solid x < 0) at the water line and 2 l0 below it: half and all of the room the wall leaves.
  const auto solid = [](const Vec3& site) { return site.x() < 0.0; };
  const auto wall_water = [](const Vec3& site) { return site.x() > 0.0 && site.z() < 0.0; };
  // Named variables, not a structured binding: clang before 16 cannot capture those in CAPTURE's lambda.
  for (const std::pair<double, double>& depth_and_fraction : {std::pair{0.0, 0.5}, std::pair{-2.5, 1.0}}) {
    const double z = depth_and_fraction.first, expected = depth_and_fraction.second;
    const Vec3 x(0.0, 0.0, z);
    CAPTURE(z);
    CHECK(wetted_fraction(lattice_sum(kernel, x, wall_water), lattice_sum(kernel, x, solid), full) ==
          doctest::Approx(expected).epsilon(0.03));
  }
  // A lone drop anywhere in the support brings at most w(0) / full = 0.242 < 1/4: spray never wets a point.
  CHECK(wetted_fraction(kernel.weight(0.0), 0.0, full) < kWetFractionThreshold);
  CHECK(wetted_fraction(kernel.weight(0.0), 0.0, full) == doctest::Approx(0.2418).epsilon(1e-3));
  // Clipped to [0, 1]; no room left (inside a wall): dry.
  CHECK(wetted_fraction(10.0, 0.0, full) == 1.0);
  CHECK(wetted_fraction(1.0, full, full) == 0.0);
}

TEST_CASE("a sensor reads the Shepard average where wet, 0 in air, and never less than 0 without tension") {
  CHECK(sensor_pressure(300.0, 2.0, 0.9, false) == 150.0);
  CHECK(sensor_pressure(-300.0, 2.0, 0.4, false) == 0.0);   // above the water it extrapolates from: air
  CHECK(sensor_pressure(-300.0, 2.0, 0.4, true) == -150.0);  // unless the fluid may hold tension
  CHECK(sensor_pressure(300.0, 2.0, 0.2, false) == 0.0);    // spray only: dry
  CHECK(sensor_pressure(-300.0, 2.0, 0.2, true) == 0.0);
}

TEST_CASE("the disc quadrature: shares sum to 1, exact for a linear field, second order for a half-submerged disc") {
  const double radius = 0.005;
  for (int rings : {1, 4, 16}) {
    CAPTURE(rings);
    const std::vector<DiscQuadraturePoint> points = disc_quadrature(radius, radius / rings, 64);
    double total = 0.0, mean_u = 0.0, mean_v = 0.0, max_offset = 0.0;
    for (const DiscQuadraturePoint& q : points) {
      total += q.weight;
      mean_u += q.weight * q.u;
      mean_v += q.weight * q.v;
      max_offset = std::max(max_offset, std::hypot(q.u, q.v));
    }
    CHECK(total == doctest::Approx(1.0).epsilon(1e-14));
    // A linear field a + b u + c v averages to a: the weighted means of u and v vanish.
    CHECK(std::abs(mean_u) < 1e-15 * radius * static_cast<double>(points.size()));
    CHECK(std::abs(mean_v) < 1e-15 * radius * static_cast<double>(points.size()));
    CHECK(max_offset < radius);
  }
  CHECK(disc_quadrature(radius, radius / 100, 16).size() == disc_quadrature(radius, radius / 16, 16).size());
  CHECK(disc_quadrature(radius, 0.0, 16).size() == disc_quadrature(radius, radius / 16, 16).size());
  CHECK(disc_quadrature(0.0, 0.001, 16).size() == 1);

  // max(0, s - v) over the disc against its analytic mean: the error comes from the cells the water line cuts, and
  // falls as the square of the ring width (order 2 +- 0.4 from 4 to 16 rings; 2.3 observed); at 4 rings, the fewest
  // a transducer uses, it is 0.19 % of rho g R (0.1 Pa for a 10 mm disc), checked against 0.25 %.
  std::vector<double> errors;
  for (int rings : {4, 8, 16}) {
    const std::vector<DiscQuadraturePoint> points = disc_quadrature(radius, radius / rings, 16);
    double worst = 0.0;
    for (int k = -20; k <= 20; ++k) {
      const double s = radius * k / 20.0;
      double mean_v = 0.0, mean_u = 0.0;  // the water line across either tangent direction
      for (const DiscQuadraturePoint& q : points) {
        mean_v += q.weight * std::max(0.0, s - q.v);
        mean_u += q.weight * std::max(0.0, s - q.u);
      }
      worst = std::max({worst, std::abs(mean_v - half_submerged_mean(s, radius)),
                        std::abs(mean_u - half_submerged_mean(s, radius))});
    }
    errors.push_back(worst / radius);
  }
  MESSAGE("half-submerged disc: max error / R at 4, 8, 16 rings: " << errors[0] << ", " << errors[1] << ", "
                                                                     << errors[2]);
  CHECK(errors[0] < 0.0025);
  const double order = std::log(errors[0] / errors[2]) / std::log(4.0);
  MESSAGE("observed order " << order);
  CHECK(std::abs(order - 2.0) < 0.4);
}
