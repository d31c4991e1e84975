// The mean-flow fluid's column (systems/physics/mean_flow/column.hpp) against closed forms: the sphere's slices and
// caps, its deposit at the column's ends, the profile's interpolation and ends, the bed surface, the mixing length
// (kappa z in clear water, none in a packed bed, van Driest's damping), the momentum step's exact discrete balance
// (with a profile forcing's pull too) and the profile forcing's target and its pull on the water above a bed.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "systems/physics/mean_flow/column.hpp"
#include "systems/physics/mean_flow/column_model.hpp"
#include "systems/physics/measures/bedload.hpp"

using namespace riffle;

namespace {

double sphere_volume(double radius) { return 4.0 / 3.0 * std::numbers::pi * radius * radius * radius; }

/// [m^3] A sphere's cap of height c (0 <= c <= 2 r): pi c^2 (3 r - c) / 3.
double cap_volume(double radius, double c) { return std::numbers::pi * c * c * (3.0 * radius - c) / 3.0; }

ColumnGrid grid_of(std::size_t cells, double cell_height, double bottom = 0.0) {
  ColumnGrid grid;
  grid.bottom = bottom;
  grid.cell_height = cell_height;
  grid.cells = cells;
  return grid;
}
}  // namespace

TEST_CASE("mean-flow column: sphere slices match the cap formula and sum to the sphere") {
  const double r = 1.3e-3;
  const double centre = 0.0123;
  for (const double c : {0.0, 0.1e-3, 0.7e-3, 1.3e-3, 2.0e-3, 2.6e-3}) {
    CAPTURE(c);
    // The cap below centre - r + c, and the one above centre + r - c.
    CHECK(sphere_slab_volume(r, centre, centre - 5.0 * r, centre - r + c) ==
          doctest::Approx(cap_volume(r, c)).epsilon(1e-13).scale(1e-12));
    CHECK(sphere_slab_volume(r, centre, centre + r - c, centre + 5.0 * r) ==
          doctest::Approx(cap_volume(r, c)).epsilon(1e-13).scale(1e-12));
  }
  CHECK(sphere_slab_volume(r, centre, centre - r, centre + r) == doctest::Approx(sphere_volume(r)).epsilon(1e-14));
  CHECK(sphere_slab_volume(r, centre, centre + r, centre + 2 * r) == 0.0);
  CHECK(sphere_slab_volume(r, centre, centre, centre) == 0.0);

  // Over cells much thinner, as thin and thicker than the sphere, whatever its place: the cells' sum is the sphere.
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const double h : {0.1e-3, 1.3e-3, 2.6e-3, 5e-3}) {
    const ColumnGrid grid = grid_of(static_cast<std::size_t>(std::ceil(0.03 / h)), h, -0.001);
    for (int k = 0; k < 20; ++k) {
      const double z = 0.002 + 0.02 * unit(random);
      std::vector<double> per_cell(grid.cells, 0.0);
      const double inside = deposit_sphere(grid, z, r, 1.0, per_cell);
      double sum = 0.0;
      for (std::size_t i = 0; i < grid.cells; ++i) {
        CHECK(per_cell[i] >= 0.0);
        CHECK(per_cell[i] == doctest::Approx(sphere_slab_volume(r, z, grid.face(i), grid.face(i + 1))));
        sum += per_cell[i];
      }
      CHECK(sum == doctest::Approx(sphere_volume(r)).epsilon(1e-13));
      CHECK(inside == doctest::Approx(sphere_volume(r)).epsilon(1e-13));
    }
  }
}

TEST_CASE("mean-flow column: a sphere at the column's ends deposits and returns only its part inside") {
  const double r = 1e-3;
  const ColumnGrid grid = grid_of(10, 0.7e-3, 0.002);  // from 2 mm to 9 mm
  const double weight = 2.5;
  struct Case {
    double centre;
    double expected_inside;  // [m^3]
  };
  const Case cases[] = {
      {grid.bottom, 0.5 * sphere_volume(r)},                     // halved by the floor
      {grid.bottom - 0.4e-3, cap_volume(r, 0.6e-3)},             // a cap above the floor
      {grid.top(), 0.5 * sphere_volume(r)},                      // halved by the top
      {grid.top() + 0.25e-3, cap_volume(r, 0.75e-3)},            // a cap below the top
      {grid.bottom - r, 0.0},                                    // touching the floor from below
      {grid.top() + 2.0 * r, 0.0},                               // well above
      {0.5 * (grid.bottom + grid.top()), sphere_volume(r)},      // inside
  };
  for (const Case& c : cases) {
    CAPTURE(c.centre);
    std::vector<double> per_cell(grid.cells, 0.0);
    const double inside = deposit_sphere(grid, c.centre, r, weight, per_cell);
    double sum = 0.0;
    for (double v : per_cell) sum += v;
    CHECK(inside == doctest::Approx(c.expected_inside).epsilon(1e-13).scale(1e-12));
    CHECK(sum == doctest::Approx(weight * c.expected_inside).epsilon(1e-13).scale(1e-12));
  }
  // A sphere taller than the whole column: the column's slab of it.
  const ColumnGrid thin = grid_of(3, 0.2e-3, 0.0);
  std::vector<double> per_cell(thin.cells, 0.0);
  CHECK(deposit_sphere(thin, 0.3e-3, r, 1.0, per_cell) ==
        doctest::Approx(sphere_slab_volume(r, 0.3e-3, 0.0, 0.6e-3)).epsilon(1e-14));
}

TEST_CASE("mean-flow column: profile_at interpolates linearly and takes the floor, the lid or the free top") {
  const ColumnGrid grid = grid_of(4, 0.01, 0.1);  // centres 0.105, 0.115, 0.125, 0.135; top 0.14
  const std::vector<double> values = {1.0, 3.0, 4.0, -2.0};
  ColumnEnds free_top;
  free_top.bottom_value = 0.5;
  ColumnEnds lid = free_top;
  lid.top_given = true;
  lid.top_value = 7.0;
  for (const ColumnEnds* ends : {&free_top, &lid}) {
    // The floor's value at the floor, below it too (clamped), linear up to the first centre.
    CHECK(profile_at(grid, values, 0.1, *ends) == doctest::Approx(0.5).epsilon(1e-14));
    CHECK(profile_at(grid, values, 0.0, *ends) == doctest::Approx(0.5).epsilon(1e-14));
    CHECK(profile_at(grid, values, 0.1025, *ends) == doctest::Approx(0.75).epsilon(1e-14));
    for (std::size_t i = 0; i < grid.cells; ++i)
      CHECK(profile_at(grid, values, grid.centre(i), *ends) == doctest::Approx(values[i]).epsilon(1e-14));
    // Linear between centres: a quarter of the way from centre 1 to centre 2, and the middle of 2 and 3.
    CHECK(profile_at(grid, values, 0.1175, *ends) == doctest::Approx(3.25).epsilon(1e-14));
    CHECK(profile_at(grid, values, 0.130, *ends) == doctest::Approx(1.0).epsilon(1e-14));
  }
  // Above the last centre: flat for a free top, linear to the lid's value at the top face (and clamped above it).
  CHECK(profile_at(grid, values, 0.1375, free_top) == doctest::Approx(-2.0).epsilon(1e-14));
  CHECK(profile_at(grid, values, 0.14, free_top) == doctest::Approx(-2.0).epsilon(1e-14));
  CHECK(profile_at(grid, values, 0.5, free_top) == doctest::Approx(-2.0).epsilon(1e-14));
  CHECK(profile_at(grid, values, 0.1375, lid) == doctest::Approx(2.5).epsilon(1e-14));
  CHECK(profile_at(grid, values, 0.14, lid) == doctest::Approx(7.0).epsilon(1e-14));
  CHECK(profile_at(grid, values, 0.5, lid) == doctest::Approx(7.0).epsilon(1e-14));
  // One cell: floor to centre to lid.
  const ColumnGrid one = grid_of(1, 0.2);
  CHECK(profile_at(one, {2.0}, 0.05, lid) == doctest::Approx(1.25).epsilon(1e-14));
  CHECK(profile_at(one, {2.0}, 0.15, lid) == doctest::Approx(4.5).epsilon(1e-14));
  CHECK(profile_at(one, {2.0}, 0.15, free_top) == doctest::Approx(2.0).epsilon(1e-14));
}

TEST_CASE("mean-flow column: the bed surface of a step, of a graded bed and of an empty column") {
  const ColumnGrid grid = grid_of(8, 1e-3, -0.002);
  // A step: packed cells 0..2 and clear water above; half the largest fraction is crossed at face 3.
  std::vector<double> step(8, 0.0);
  for (std::size_t i = 0; i < 3; ++i) step[i] = 0.6;
  CHECK(bed_surface(grid, step) == doctest::Approx(grid.face(3)).epsilon(1e-14));
  // A graded top: half of 0.6 is crossed between centre 3 (0.45) and centre 4 (0.1), at 0.15 / 0.35 of a cell.
  std::vector<double> graded = {0.6, 0.6, 0.6, 0.45, 0.1, 0.0, 0.0, 0.0};
  CHECK(bed_surface(grid, graded) == doctest::Approx(grid.centre(3) + 1e-3 * 0.15 / 0.35).epsilon(1e-14));
  // A loose grain high above a bed does not raise it (below half the largest), a second packed layer does.
  graded[6] = 0.2;
  CHECK(bed_surface(grid, graded) == doctest::Approx(grid.centre(3) + 1e-3 * 0.15 / 0.35).epsilon(1e-14));
  graded[6] = 0.6;
  CHECK(bed_surface(grid, graded) == doctest::Approx(grid.centre(6) + 1e-3 * 0.6 / 1.2).epsilon(1e-14));
  // Filled to the top: the top face; empty: the floor.
  CHECK(bed_surface(grid, std::vector<double>(8, 0.55)) == doctest::Approx(grid.top()).epsilon(1e-14));
  CHECK(bed_surface(grid, std::vector<double>(8, 0.0)) == grid.bottom);
}

TEST_CASE("mean-flow column: the mixing length is kappa z in clear water, with the rough floor's start") {
  const ColumnGrid grid = grid_of(50, 0.2e-3, 0.01);
  const std::vector<double> clear(grid.cells, 0.0);
  MixingLengthClosure closure;
  const double nu = 1e-6;
  // Smooth floor: kappa z (1 - exp(-z+ / A+)), van Driest's damping, z+ = z u* / nu.
  for (const double u_star : {0.01, 0.05}) {
    const std::vector<double> lengths = mixing_lengths(grid, clear, closure, u_star, nu);
    REQUIRE(lengths.size() == grid.cells + 1);
    CHECK(lengths[0] == 0.0);
    for (std::size_t j = 0; j <= grid.cells; ++j) {
      const double z = grid.face(j) - grid.bottom;
      const double damping = 1.0 - std::exp(-z * u_star / (nu * 26.0));
      CHECK(lengths[j] == doctest::Approx(0.41 * z * damping).epsilon(1e-12).scale(1e-15));
    }
  }
  // Far from the floor in wall units the damping is 1 to rounding: e.g. z+ = 4000 at the top for u* = 0.4.
  CHECK(mixing_lengths(grid, clear, closure, 0.4, nu).back() ==
        doctest::Approx(0.41 * 0.01).epsilon(1e-12));
  // No friction velocity yet: no turbulence over a smooth floor.
  for (double l : mixing_lengths(grid, clear, closure, 0.0, nu)) CHECK(l == 0.0);

  // Rough floor, viscosity negligible (k_s+ = 1e9): l = kappa (z + z0), z0 = k_s exp(-kappa B_r) = k_s / 32.6.
  closure.floor = MixingLengthClosure::Floor::kRough;
  closure.roughness = 2.5e-3;
  const double z0 = 2.5e-3 * std::exp(-0.41 * 8.5);
  // With u* = 0 (no friction velocity yet) the inviscid start kappa z0 too.
  for (const double u_star : {1.0e3, 0.0}) {
    CAPTURE(u_star);
    const std::vector<double> lengths = mixing_lengths(grid, clear, closure, u_star, u_star > 0.0 ? 1e-15 : nu);
    for (std::size_t j = 0; j <= grid.cells; ++j)
      CHECK(lengths[j] == doctest::Approx(0.41 * (grid.face(j) - grid.bottom + z0)).epsilon(1e-12));
  }
  // At k_s+ = 100 the molecular viscosity carries part of the floor's stress, so l0 must be smaller than kappa z0
  // for Nikuradse's B_r: l0+ = 0.689 solves F(l0+) = ln(4 kappa k_s+) - 1 - kappa B_r = 0.615 (by hand), against
  // kappa z0+ = 1.257 (the verification test checks the profile it gives); the growth above is still kappa z.
  const std::vector<double> viscous = mixing_lengths(grid, clear, closure, 100.0 * nu / 2.5e-3, nu);
  CHECK(viscous[0] / (0.41 * z0) == doctest::Approx(0.689 / 1.257).epsilon(0.01));
  for (std::size_t j = 1; j <= grid.cells; ++j)
    CHECK(viscous[j] - viscous[0] == doctest::Approx(0.41 * (grid.face(j) - grid.bottom)).epsilon(1e-12));
  // Below k_s+ ~ 55 the floor is not fully rough and starts at 0.
  CHECK(mixing_lengths(grid, clear, closure, 40.0 * nu / 2.5e-3, nu)[0] == 0.0);
}

TEST_CASE("mean-flow column: no mixing length in a packed bed, below its highest packed cell, nor over a buried floor") {
  const ColumnGrid grid = grid_of(8, 1e-3);
  const double h = 1e-3;
  // Packed cells 0, 1 and 3, a loose pocket at 2 (counts as packed: below the highest packed cell), then a loose
  // layer (phi = 0.2) and clear water.
  const std::vector<double> phi = {0.61, 0.63, 0.3, 0.61, 0.2, 0.0, 0.0, 0.0};
  MixingLengthClosure closure;
  for (const auto floor : {MixingLengthClosure::Floor::kSmooth, MixingLengthClosure::Floor::kRough}) {
    closure.floor = floor;
    closure.roughness = 2e-3;
    // u* large: van Driest's damping is 1 to rounding above the bed.
    const std::vector<double> lengths = mixing_lengths(grid, phi, closure, 10.0, 1e-6);
    for (std::size_t j = 0; j <= 4; ++j) CHECK(lengths[j] == 0.0);
    // Li & Sawamoto: dl/dz = kappa (phi_max - phi) / phi_max.
    const double loose = 0.41 * h * (0.61 - 0.2) / 0.61;
    CHECK(lengths[5] == doctest::Approx(loose).epsilon(1e-12));
    for (std::size_t j = 6; j <= 8; ++j)
      CHECK(lengths[j] == doctest::Approx(loose + 0.41 * h * static_cast<double>(j - 5)).epsilon(1e-12));
  }
}

TEST_CASE("mean-flow column: a smooth floor under a packed bed damps nothing, a lid caps and damps the length") {
  const ColumnGrid grid = grid_of(8, 1e-3);
  const double h = 1e-3, nu = 1e-6;
  const std::vector<double> phi = {0.61, 0.61, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  MixingLengthClosure closure;  // smooth floor
  // The floor carries no stress under the bed (u* = 0): the bed's mixing length is Li & Sawamoto's all the same.
  const std::vector<double> buried = mixing_lengths(grid, phi, closure, 0.0, nu);
  for (std::size_t j = 0; j <= 2; ++j) CHECK(buried[j] == 0.0);
  for (std::size_t j = 3; j <= 8; ++j) CHECK(buried[j] == doctest::Approx(0.41 * h * static_cast<double>(j - 2)));
  // A lid with a large friction velocity: min(kappa z, kappa (H - z)) in clear water; with none, no length at all.
  const std::vector<double> clear(8, 0.0);
  const std::vector<double> capped = mixing_lengths(grid, clear, closure, 10.0, nu, TopWall{true, 10.0});
  for (std::size_t j = 0; j <= 8; ++j)
    CHECK(capped[j] == doctest::Approx(0.41 * h * static_cast<double>(std::min<std::size_t>(j, 8 - j))));
  for (double l : mixing_lengths(grid, clear, closure, 10.0, nu, TopWall{true, 0.0})) CHECK(l == 0.0);
  // Van Driest's factor of the lid: 1 - exp(-(H - z) u* / (26 nu)) one cell below it.
  const double u_star = 26.0 * nu / h;  // the factor is 1 - 1/e one cell below
  const std::vector<double> damped = mixing_lengths(grid, clear, closure, 10.0, nu, TopWall{true, u_star});
  CHECK(damped[7] == doctest::Approx(0.41 * h * (1.0 - std::exp(-1.0))).epsilon(1e-12));
  // A free top is no wall.
  CHECK(mixing_lengths(grid, clear, closure, 10.0, nu).back() == doctest::Approx(0.41 * 8.0 * h));
}

TEST_CASE("mean-flow column: the eddy viscosity l^2 times the shear at the faces, with the floor's, the lid's and the free top's gradients") {
  const ColumnGrid grid = grid_of(3, 0.1);
  const std::vector<double> u = {1.0, 2.0, 4.0}, v = {0.0, 1.0, 1.0}, lengths = {0.5, 1.0, 2.0, 3.0};
  ColumnEnds lid;
  lid.top_given = true;
  lid.top_value = 5.0;
  ColumnEnds free_top;
  const std::vector<double> one = eddy_viscosities(grid, u, {}, lengths, lid, lid);
  CHECK(one[0] == doctest::Approx(0.25 * 1.0 / 0.05));
  CHECK(one[1] == doctest::Approx(1.0 * 1.0 / 0.1));
  CHECK(one[2] == doctest::Approx(4.0 * 2.0 / 0.1));
  CHECK(one[3] == doctest::Approx(9.0 * 1.0 / 0.05));
  CHECK(eddy_viscosities(grid, u, {}, lengths, free_top, free_top)[3] == 0.0);
  // A flow that turns: the magnitude of the shear.
  const std::vector<double> two = eddy_viscosities(grid, u, v, lengths, lid, free_top);
  CHECK(two[0] == doctest::Approx(0.25 * 1.0 / 0.05));
  CHECK(two[1] == doctest::Approx(1.0 * std::hypot(10.0, 10.0)));
  CHECK(two[2] == doctest::Approx(4.0 * 20.0));
  CHECK(two[3] == doctest::Approx(9.0 * 1.0 / 0.05));
}

TEST_CASE("mean-flow column: the momentum step's discrete balance holds to rounding") {
  std::mt19937_64 random(20240611);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < 40; ++trial) {
    const std::size_t cells = 1 + static_cast<std::size_t>(60.0 * unit(random));
    const ColumnGrid grid = grid_of(cells, 1e-4 * (0.5 + unit(random)), -0.01 * unit(random));
    std::vector<double> phi(cells), impulse(cells), velocity(cells), nu_t(cells + 1);
    for (std::size_t i = 0; i < cells; ++i) {
      phi[i] = 0.62 * unit(random);
      impulse[i] = 1e-4 * (unit(random) - 0.3);
      velocity[i] = unit(random) - 0.5;
    }
    for (double& n : nu_t) n = 1e-4 * unit(random) * unit(random);
    ColumnEnds ends;
    ends.bottom_value = 0.1 * (unit(random) - 0.5);
    ends.top_given = trial % 2 == 0;
    ends.top_value = unit(random);
    ColumnStep step;
    step.density = 1000.0 + 50.0 * unit(random);
    step.viscosity = 1e-6 * (0.5 + unit(random));
    step.dt = std::pow(10.0, -5.0 + 5.0 * unit(random));
    step.body_force = unit(random) - 0.5;
    // Every third trial also pulls towards a target profile (a profile forcing), implicit in u'.
    std::vector<double> target(cells);
    for (double& t : target) t = unit(random) - 0.5;
    if (trial % 3 == 0) {
      step.relaxation_rate = 10.0 * unit(random);
      step.relaxation_target = &target;
    }
    CAPTURE(trial);
    CAPTURE(cells);
    CAPTURE(step.dt);
    const std::vector<double> before = velocity;
    const double momentum_before = column_momentum(grid, phi, before, step.density);
    const ColumnStresses stresses = advance_column(grid, phi, nu_t, impulse, ends, step, velocity);
    // sum rho eps h (u' - u) = dt sum rho eps h (f + k (u_target - u')) - sum impulse + dt (tau_top - tau_floor)
    double change = 0.0, gravity = 0.0, exchange = 0.0, scale = 0.0;
    for (std::size_t i = 0; i < cells; ++i) {
      const double mass = step.density * (1.0 - phi[i]) * grid.cell_height;
      change += mass * (velocity[i] - before[i]);
      gravity += step.dt * mass * step.body_force;
      const double pull = step.dt * mass * step.relaxation_rate * (target[i] - velocity[i]);
      gravity += pull;
      scale += std::abs(pull);
      exchange += impulse[i];
      scale += mass * (std::abs(velocity[i]) + std::abs(before[i])) + std::abs(step.dt * mass * step.body_force) +
               std::abs(impulse[i]);
    }
    const double walls = step.dt * (stresses.top - stresses.floor);
    scale += std::abs(step.dt * stresses.top) + std::abs(step.dt * stresses.floor);
    CHECK(std::abs(change - (gravity - exchange + walls)) <= 1e-12 * scale);
    CHECK(std::abs(column_momentum(grid, phi, velocity, step.density) - momentum_before - change) <= 1e-12 * scale);
    if (!ends.top_given) CHECK(stresses.top == 0.0);
    // The stresses returned are those column_shear_stress reads at the floor and the top after the step.
    CHECK(column_shear_stress(grid, phi, nu_t, velocity, ends, step.density, step.viscosity, grid.bottom) ==
          doctest::Approx(stresses.floor).epsilon(1e-12).scale(1e-12));
    CHECK(column_shear_stress(grid, phi, nu_t, velocity, ends, step.density, step.viscosity, grid.top()) ==
          doctest::Approx(stresses.top).epsilon(1e-12).scale(1e-12));
  }
}

TEST_CASE("mean-flow column: the profile forcing's target is the power law above its base, and its pull above the bed is in the bed's stress") {
  MeanFlowModel flow;
  flow.bottom = 0.0;
  flow.top = 0.02;
  flow.cells = 200;
  flow.cell_size = 1e-4;
  CHECK(profile_forcing_target(flow).empty());
  MeanFlowColumn column;
  column.velocity_x.assign(flow.cells, 0.3);
  column.solid_fraction.assign(flow.cells, 0.0);
  column.bed_surface = 0.00505;  // half-way up cell 50
  CHECK(profile_forcing_stress(flow, column) == 0.0);
  CHECK(column_bed_stress(flow, column) == 0.0);

  MeanFlowModel::ProfileForcing& forcing = flow.profile_forcing;
  forcing.enabled = true;
  forcing.velocity = -0.8;  // along -x: the rate takes |velocity|, the target its sign
  forcing.base = 0.005;
  forcing.strength = 4.0;
  forcing.volume_fraction = 0.1;
  CHECK(forcing.rate() == doctest::Approx(0.5).epsilon(1e-15));
  const std::vector<double> target = profile_forcing_target(flow);
  REQUIRE(target.size() == flow.cells);
  for (std::size_t i = 0; i < flow.cells; ++i) {
    const double z = (static_cast<double>(i) + 0.5) * flow.cell_size;
    CAPTURE(i);
    if (z <= forcing.base) CHECK(target[i] == 0.0);
    else CHECK(target[i] == doctest::Approx(-0.8 * std::pow((z - 0.005) / 0.015, 1.0 / 7.0)).epsilon(1e-14));
  }
  CHECK(target[199] == doctest::Approx(-0.8 * std::pow(0.01495 / 0.015, 1.0 / 7.0)).epsilon(1e-14));

  // The pull on the water above the bed: rho (1 - phi) k (u_target - u) over each cell's part above the surface
  // (cell 50 half of it), with a solid fraction that halves the water in the cells 50-59.
  for (std::size_t i = 50; i < 60; ++i) column.solid_fraction[i] = 0.5;
  double expected = 0.0;
  for (std::size_t i = 50; i < flow.cells; ++i) {
    const double above = i == 50 ? 0.5e-4 : 1e-4;
    const double water = i < 60 ? 0.5 : 1.0;
    expected += 1000.0 * water * above * 0.5 * (target[i] - 0.3);
  }
  CHECK(profile_forcing_stress(flow, column) == doctest::Approx(expected).epsilon(1e-12));
  // The bed's stress adds it to the drive's and the lid's (here none).
  CHECK(column_bed_stress(flow, column) == doctest::Approx(expected).epsilon(1e-12));
  column.top_stress = 0.25;
  CHECK(column_bed_stress(flow, column) == doctest::Approx(expected + 0.25).epsilon(1e-12));
}
