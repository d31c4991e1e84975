// What a grain reads from the mean-flow column besides its mean velocity (systems/physics/mean_flow/grain_forces.hpp):
// the shear lift against Wiberg & Smith's formula, the turbulent shear at a height, the Lagrangian time against
// Thomson's T_L = 2 sigma_w^2 / (C0 eps) in the log layer, and the Langevin fluctuations' statistics (unit variance,
// exp(-t/T) memory whatever the step, the Reynolds stress and Nezu & Nakagawa's intensities) within sampling error.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <vector>

#include "systems/physics/math/counter_random.hpp"
#include "systems/physics/mean_flow/grain_forces.hpp"

using namespace riffle;

namespace {
}  // namespace

TEST_CASE("shear lift: 1/2 rho C_L pi r^2 (u_top^2 - u_bottom^2) of the relative horizontal velocities") {
  // 2 mm quartz under water at 0.30 m/s over its top and 0.10 m/s under it, at rest: 2.513e-5 N by hand.
  const double lift = shear_lift(1000.0, 0.2, 0.001, Vec3(0.30, 0.0, 0.0), Vec3(0.10, 0.0, 0.0));
  CHECK(lift == doctest::Approx(0.5 * 1000.0 * 0.2 * std::numbers::pi * 1e-6 * (0.09 - 0.01)).epsilon(1e-14));
  CHECK(lift == doctest::Approx(2.5133e-5).epsilon(1e-4));
  // Only the horizontal parts count; a spanwise component adds its square.
  CHECK(shear_lift(1000.0, 0.2, 0.001, Vec3(0.30, 0.0, 5.0), Vec3(0.10, 0.0, -5.0)) == doctest::Approx(lift));
  CHECK(shear_lift(1000.0, 0.2, 0.001, Vec3(0.0, 0.30, 0.0), Vec3(0.10, 0.0, 0.0)) == doctest::Approx(lift));
  // A grain faster than the water over its top is pushed down; no shear, no lift.
  CHECK(shear_lift(1000.0, 0.2, 0.001, Vec3(-0.05, 0.0, 0.0), Vec3(-0.25, 0.0, 0.0)) < 0.0);
  CHECK(shear_lift(1000.0, 0.2, 0.001, Vec3(0.2, 0.0, 0.0), Vec3(0.2, 0.0, 0.0)) == 0.0);
}

TEST_CASE("turbulent shear: nu_t du/dz and |dU/dz| at a height, linear between the faces") {
  ColumnGrid grid;
  grid.cells = 10;
  grid.cell_height = 0.001;
  MeanFlowColumn column;
  // u = S z, v = -S z / 2: the floor's and the interior faces' gradients are exact for a linear profile.
  const double rate = 20.0;
  for (std::size_t i = 0; i < grid.cells; ++i) {
    column.velocity_x.push_back(rate * grid.centre(i));
    column.velocity_y.push_back(-0.5 * rate * grid.centre(i));
  }
  for (std::size_t j = 0; j <= grid.cells; ++j) column.eddy_viscosity.push_back(1e-5 * static_cast<double>(j));
  const ColumnEnds ends{0.0, true, rate * grid.top()}, ends_y{0.0, true, -0.5 * rate * grid.top()};
  for (const double z : {0.0, 0.00025, 0.0031, 0.00999, 0.01}) {
    CAPTURE(z);
    const TurbulentShear shear = turbulent_shear_at(grid, column, ends, ends_y, z);
    const double eddy = 1e-5 * z / grid.cell_height;  // linear in z: the interpolation is exact
    CHECK(shear.stress_x == doctest::Approx(eddy * rate).epsilon(1e-12));
    CHECK(shear.stress_y == doctest::Approx(-0.5 * eddy * rate).epsilon(1e-12));
    CHECK(shear.shear_rate == doctest::Approx(rate * std::sqrt(1.25)).epsilon(1e-12));
    CHECK(shear.friction_velocity() == doctest::Approx(std::sqrt(eddy * rate * std::sqrt(1.25))).epsilon(1e-12));
  }
}

TEST_CASE("Lagrangian time: Thomson's 2 sigma_w^2 / (C0 eps) in the log layer, 0.33 z / u* at C0 = 4") {
  const TurbulenceIntensities intensities;
  const double kappa = 0.41, friction = 0.03, z = 0.004;
  const double shear_rate = friction / (kappa * z);                    // the log law's dU/dz
  const double dissipation = friction * friction * friction / (kappa * z);  // equilibrium: production = eps
  const double sigma_w = intensities.vertical * friction;
  for (const double c0 : {3.0, 4.0, 6.0}) {
    CHECK(lagrangian_time_scale(shear_rate, c0, intensities) ==
          doctest::Approx(2.0 * sigma_w * sigma_w / (c0 * dissipation)).epsilon(1e-12));
  }
  CHECK(lagrangian_time_scale(shear_rate, 4.0, intensities) == doctest::Approx(0.33 * z / friction).epsilon(0.01));
  CHECK(std::isinf(lagrangian_time_scale(0.0, 4.0, intensities)));
}

TEST_CASE("Langevin state: unit variance and exp(-t/T) memory, whatever the step") {
  // 20,000 independent processes from rest, advanced to 5 T (spun up: the variance 1 - exp(-10)), then the
  // correlation with the state a time T later, taken with steps of T/2 and of T/20.
  constexpr int kProcesses = 20000;
  const double time_scale = 0.01;
  for (const int steps_per_t : {2, 20}) {
    CAPTURE(steps_per_t);
    const double dt = time_scale / steps_per_t;
    double variance = 0.0, lagged = 0.0, variance_later = 0.0;
    for (int p = 0; p < kProcesses; ++p) {
      Vec3 state = Vec3::Zero();
      std::uint64_t step = 0;
      for (int k = 0; k < 5 * steps_per_t; ++k) state = advance_langevin(state, dt, time_scale, counter_normals(3, step++, p));
      const Vec3 start = state;
      for (int k = 0; k < steps_per_t; ++k) state = advance_langevin(state, dt, time_scale, counter_normals(3, step++, p));
      variance += start.squaredNorm() / 3.0;
      variance_later += state.squaredNorm() / 3.0;
      lagged += start.dot(state) / 3.0;
    }
    const double n = 3.0 * kProcesses;
    CHECK(std::abs(variance / kProcesses - 1.0) < 4.0 * std::sqrt(2.0 / n));
    CHECK(std::abs(variance_later / kProcesses - 1.0) < 4.0 * std::sqrt(2.0 / n));
    // The correlation's standard error for n pairs is (1 - r^2) / sqrt(n).
    const double memory = std::exp(-1.0);
    CHECK(std::abs(lagged / kProcesses - memory) < 4.0 * (1.0 - memory * memory) / std::sqrt(n) + 4.0 * std::sqrt(2.0 / n) * memory);
  }
  // A zero step or an unsheared water (infinite T) holds the state.
  const Vec3 state(0.3, -1.2, 0.7);
  CHECK(advance_langevin(state, 0.0, time_scale, Vec3(1, 1, 1)) == state);
  CHECK(advance_langevin(state, 1e-3, std::numeric_limits<double>::infinity(), Vec3(1, 1, 1)) == state);
}

TEST_CASE("Langevin fluctuations: Nezu & Nakagawa's intensities and the closure's Reynolds stress, along the shear") {
  const TurbulenceIntensities intensities;
  constexpr int kDraws = 200000;
  // The shear along x, then turned 30 degrees toward y: the statistics follow its direction.
  for (const double angle : {0.0, std::numbers::pi / 6.0}) {
    CAPTURE(angle);
    TurbulentShear shear;
    const double stress = 4e-4;  // u* = 0.02 m/s
    shear.stress_x = stress * std::cos(angle);
    shear.stress_y = stress * std::sin(angle);
    const double friction = std::sqrt(stress);
    double uu = 0.0, vv = 0.0, ww = 0.0, uw = 0.0, vw = 0.0;
    for (int i = 0; i < kDraws; ++i) {
      const Vec3 f = fluctuation_velocity(counter_normals(9, i, 0), shear, intensities);
      const double along = f.x() * std::cos(angle) + f.y() * std::sin(angle);
      const double across = -f.x() * std::sin(angle) + f.y() * std::cos(angle);
      uu += along * along;
      vv += across * across;
      ww += f.z() * f.z();
      uw += along * f.z();
      vw += across * f.z();
    }
    const double n = kDraws, tolerance = 4.0 * std::sqrt(2.0 / n);
    const double u2 = friction * friction;
    CHECK(std::abs(std::sqrt(uu / n) / friction / 2.30 - 1.0) < tolerance);
    CHECK(std::abs(std::sqrt(vv / n) / friction / 1.63 - 1.0) < tolerance);
    CHECK(std::abs(std::sqrt(ww / n) / friction / 1.27 - 1.0) < tolerance);
    // -<u'w'> = u*^2: the stress the closure carries (standard error of the covariance ~ sigma_u sigma_w / sqrt(n)).
    CHECK(std::abs(-uw / n / u2 - 1.0) < 4.0 * 2.30 * 1.27 * 1.1 / std::sqrt(n));
    CHECK(std::abs(vw / n / u2) < 4.0 * 1.63 * 1.27 / std::sqrt(n));
  }
  CHECK(fluctuation_velocity(Vec3(1, 1, 1), TurbulentShear{}, intensities) == Vec3::Zero());
}

TEST_CASE("a height that is not a number reads no cells, no velocity and no turbulence") {
  ColumnGrid grid;
  grid.cells = 4;
  grid.cell_height = 0.001;
  MeanFlowColumn column;
  column.velocity_x.assign(4, 0.1);
  column.velocity_y.assign(4, 0.0);
  column.eddy_viscosity.assign(5, 1e-5);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK(sphere_cells(grid, nan, 0.001).empty);
  std::vector<double> per_cell(4, 0.0);
  CHECK(deposit_sphere(grid, nan, 0.001, 1.0, per_cell) == 0.0);
  CHECK(std::isnan(profile_at(grid, column.velocity_x, nan, ColumnEnds{})));
  const TurbulentShear shear = turbulent_shear_at(grid, column, ColumnEnds{}, ColumnEnds{}, nan);
  CHECK(shear.stress_x == 0.0);
  CHECK(shear.shear_rate == 0.0);
}
