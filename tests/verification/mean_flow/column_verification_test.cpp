// The mean-flow fluid's column (systems/physics/mean_flow/column.hpp) against exact solutions and published laws:
// laminar plane Couette (linear, to rounding), open-channel Poiseuille (second order in h, with the scheme's exact
// error f h^2 / (8 nu)), a laminar channel pulled towards a uniform stream by a profile forcing (second order in h), the start-up of Couette flow (first order in dt, backward Euler), and the turbulent open
// channel over a smooth floor (van Driest's mixing length: the log law u+ = ln z+ / 0.41 + 5.2) and over a rough one
// (Nikuradse: u+ = ln(z / k_s) / 0.41 + 8.5), each also against the closure's own continuous profile, found here by
// quadrature, to second order in h.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <vector>

#include "systems/physics/mean_flow/column.hpp"

using namespace riffle;

namespace {
constexpr double kKappa = 0.41;

ColumnGrid grid_of(std::size_t cells, double depth) {
  ColumnGrid grid;
  grid.cell_height = depth / static_cast<double>(cells);
  grid.cells = cells;
  return grid;
}

double observed_order(double coarse_error, double fine_error, double refinement = 2.0) {
  return std::log(coarse_error / fine_error) / std::log(refinement);
}

/// Laminar steady state: three backward-Euler steps of dt = 1e6 diffusion times (each leaves 1e-6 of the last
/// one's distance to the steady state).
ColumnStresses laminar_steady(const ColumnGrid& grid, const ColumnEnds& ends, const ColumnStep& base,
                              std::vector<double>& velocity) {
  ColumnStep step = base;
  step.dt = 1e6 * grid.top() * grid.top() / step.viscosity;
  const std::vector<double> clear(grid.cells, 0.0), no_eddy(grid.cells + 1, 0.0);
  ColumnStresses stresses;
  for (int k = 0; k < 3; ++k) stresses = advance_column(grid, clear, no_eddy, clear, ends, step, velocity);
  return stresses;
}

/// A turbulent open channel's steady state (free top, body force f = u*^2 / H, clear water), reached by steps of
/// large dt with the eddy viscosity relaxed between them (nu_t <- (nu_t + l^2 |du/dz|) / 2: Heron's iteration for
/// the fixed point nu_t = l^2 |du/dz|, which plain lagging would make oscillate) until a step changes u by less than
/// 1e-9 of its largest value (rounding stalls it between 1e-12 and 1e-10 on these grids); the floor's friction velocity that
/// the closure reads is the last step's floor stress. The fixed point does not depend on the iteration.
struct TurbulentSteady {
  std::vector<double> velocity;
  ColumnStresses stresses;
  int iterations = 0;
  double change = 0.0;  // [1] the last step's largest change over the largest velocity
};
/// `lid_velocity` (if not 0): a no-slip lid moving at it instead of the free top (plane Couette flow), its friction
/// velocity the closure's too.
TurbulentSteady turbulent_steady(const ColumnGrid& grid, const MixingLengthClosure& closure, const ColumnStep& base,
                                 double friction_velocity, double lid_velocity = 0.0) {
  ColumnEnds ends;  // floor at rest, free top or a lid
  ends.top_given = lid_velocity != 0.0;
  ends.top_value = lid_velocity;
  TopWall lid{ends.top_given, friction_velocity};
  const std::vector<double> clear(grid.cells, 0.0);
  ColumnStep step = base;
  step.dt = 100.0;  // [s] many times the turbulent diffusion time H / (kappa u*) of these channels
  TurbulentSteady result;
  result.velocity.assign(grid.cells, 0.0);
  std::vector<double> eddy(grid.cells + 1, 0.0);
  double floor_friction = friction_velocity;
  for (result.iterations = 1; result.iterations <= 400; ++result.iterations) {
    const std::vector<double> lengths = mixing_lengths(grid, clear, closure, floor_friction, step.viscosity, lid);
    const std::vector<double> fresh = eddy_viscosities(grid, result.velocity, {}, lengths, ends, ends);
    for (std::size_t j = 0; j <= grid.cells; ++j)
      eddy[j] = result.iterations == 1 ? fresh[j] : 0.5 * (eddy[j] + fresh[j]);
    const std::vector<double> before = result.velocity;
    result.stresses = advance_column(grid, clear, eddy, clear, ends, step, result.velocity);
    floor_friction = std::sqrt(std::max(0.0, result.stresses.floor) / step.density);
    lid.friction_velocity = std::sqrt(std::abs(result.stresses.top) / step.density);
    double change = 0.0, largest = 0.0;
    for (std::size_t i = 0; i < grid.cells; ++i) {
      change = std::max(change, std::abs(result.velocity[i] - before[i]));
      largest = std::max(largest, std::abs(result.velocity[i]));
    }
    result.change = change / largest;
    if (result.change < 1e-9) break;
  }
  return result;
}

/// The closure's own steady profile in a channel of depth H over clear water, found by quadrature: the stress is
/// tau = rho u*^2 (1 - z / H), and (nu + l^2 |du/dz|) du/dz = tau / rho gives
/// du/dz = 2 (tau / rho) / (nu + sqrt(nu^2 + 4 l^2 tau / rho)), integrated from the floor (u = 0) by composite
/// Simpson over panels finer than a fiftieth of the viscous length or a two-hundredth of the height.
struct ContinuousChannel {
  double depth;              // [m] H
  double friction_velocity;  // [m/s] u*
  double viscosity;          // [m^2/s] nu
  std::function<double(double)> mixing_length;  // [m] l(z), z above the floor

  double gradient(double z) const {
    const double stress = friction_velocity * friction_velocity * (1.0 - z / depth);
    const double l = mixing_length(z);
    return 2.0 * stress / (viscosity + std::sqrt(viscosity * viscosity + 4.0 * l * l * stress));
  }
  /// u at each of the increasing heights `heights`.
  std::vector<double> velocity_at(const std::vector<double>& heights) const {
    std::vector<double> u;
    double z = 0.0, sum = 0.0;
    for (double target : heights) {
      const double panel = std::max(0.02 * viscosity / friction_velocity, 0.005 * z);
      const int panels = std::max(2, 2 * static_cast<int>(std::ceil((target - z) / panel / 2.0)));
      const double width = (target - z) / panels;
      double simpson = gradient(z) + gradient(target);
      for (int k = 1; k < panels; ++k) simpson += (k % 2 == 1 ? 4.0 : 2.0) * gradient(z + k * width);
      sum += simpson * width / 3.0;
      z = target;
      u.push_back(sum);
    }
    return u;
  }
};

/// The constant-stress antiderivative of the closure with l = l0 + kappa z in wall units (y = l+):
/// u+ = (F(y) - F(y0)) / kappa, F(y) = asinh(2 y) - 2 y / (1 + sqrt(1 + 4 y^2)) -> ln(4 y) - 1.
double primitive(double y) { return std::asinh(2.0 * y) - 2.0 * y / (1.0 + std::sqrt(1.0 + 4.0 * y * y)); }
}  // namespace

TEST_CASE("mean-flow column verification: plane Couette flow is linear to rounding") {
  for (const std::size_t cells : {1u, 7u, 64u}) {
    CAPTURE(cells);
    const ColumnGrid grid = grid_of(cells, 0.01);
    ColumnEnds ends;
    ends.top_given = true;
    ends.top_value = 0.3;
    ColumnStep step;
    std::vector<double> u(cells, 0.0);
    const ColumnStresses stresses = laminar_steady(grid, ends, step, u);
    for (std::size_t i = 0; i < cells; ++i) CHECK(std::abs(u[i] - 0.3 * grid.centre(i) / 0.01) <= 1e-13 * 0.3);
    const double exact = 1000.0 * 1e-6 * 0.3 / 0.01;  // rho nu U / H
    CHECK(stresses.floor == doctest::Approx(exact).epsilon(1e-12));
    CHECK(stresses.top == doctest::Approx(exact).epsilon(1e-12));
  }
  // A moving floor and a lid: the same line between them.
  const ColumnGrid grid = grid_of(10, 0.02);
  ColumnEnds ends;
  ends.bottom_value = -0.1;
  ends.top_given = true;
  ends.top_value = 0.2;
  std::vector<double> u(10, 0.0);
  laminar_steady(grid, ends, ColumnStep{}, u);
  for (std::size_t i = 0; i < 10; ++i) CHECK(std::abs(u[i] - (-0.1 + 0.3 * grid.centre(i) / 0.02)) <= 1e-13);
}

TEST_CASE("mean-flow column verification: open-channel Poiseuille flow converges at second order in h") {
  // u = f / nu (H z - z^2 / 2). The discrete steady state has the exact stress at every face (the body force above
  // it), so the gradient between centres is exact and only the floor's half cell, where u_0 = (h / 2) du/dz(0), errs:
  // by f h^2 / (8 nu) at every centre (the exact rise over the half cell is f / nu (H h / 2 - h^2 / 8)).
  const double depth = 0.01, nu = 1e-6, f = 1e-4;
  ColumnStep step;
  step.viscosity = nu;
  step.body_force = f;
  std::vector<double> errors;
  for (const std::size_t cells : {10u, 20u, 40u}) {
    const ColumnGrid grid = grid_of(cells, depth);
    std::vector<double> u(cells, 0.0);
    const ColumnStresses stresses = laminar_steady(grid, ColumnEnds{}, step, u);
    double error = 0.0;
    for (std::size_t i = 0; i < cells; ++i) {
      const double z = grid.centre(i);
      const double exact = f / nu * (depth * z - 0.5 * z * z);
      CHECK(u[i] - exact == doctest::Approx(f * grid.cell_height * grid.cell_height / (8.0 * nu)).epsilon(1e-8));
      error = std::max(error, std::abs(u[i] - exact));
    }
    errors.push_back(error / (f * depth * depth / (2.0 * nu)));
    CHECK(stresses.floor == doctest::Approx(1000.0 * f * depth).epsilon(1e-12));
    CHECK(stresses.top == 0.0);
  }
  const double order_coarse = observed_order(errors[0], errors[1]);
  const double order_fine = observed_order(errors[1], errors[2]);
  std::printf("Poiseuille: relative max error %.3e %.3e %.3e (10, 20, 40 cells), observed order %.4f %.4f\n",
              errors[0], errors[1], errors[2], order_coarse, order_fine);
  CHECK(order_coarse == doctest::Approx(2.0).epsilon(0.05));
  CHECK(order_fine == doctest::Approx(2.0).epsilon(0.05));
}

TEST_CASE("mean-flow column verification: a flow pulled towards a uniform target converges at second order in h") {
  // The profile forcing k (U - u) on a laminar open channel: nu u'' + k (U - u) = 0, u(0) = 0, u'(H) = 0, so u = U (1 -
  // cosh((H - z) / delta) / cosh(H / delta)), delta = sqrt(nu / k): a boundary layer delta thick under a uniform
  // stream. In the steady state the floor carries the whole pull, sum_i rho h k (U - u_i), to rounding.
  const double depth = 0.01, nu = 1e-6, k = 0.04, stream = 0.3;
  const double delta = std::sqrt(nu / k);
  ColumnStep step;
  step.viscosity = nu;
  std::vector<double> errors;
  for (const std::size_t cells : {10u, 20u, 40u, 80u}) {
    const ColumnGrid grid = grid_of(cells, depth);
    const std::vector<double> target(cells, stream);
    step.relaxation_rate = k;
    step.relaxation_target = &target;
    std::vector<double> u(cells, 0.0);
    const ColumnStresses stresses = laminar_steady(grid, ColumnEnds{}, step, u);
    double error = 0.0, pull = 0.0;
    for (std::size_t i = 0; i < cells; ++i) {
      const double z = grid.centre(i);
      const double exact = stream * (1.0 - std::cosh((depth - z) / delta) / std::cosh(depth / delta));
      error = std::max(error, std::abs(u[i] - exact));
      pull += 1000.0 * grid.cell_height * k * (stream - u[i]);
    }
    errors.push_back(error / stream);
    CHECK(stresses.floor == doctest::Approx(pull).epsilon(1e-10));
    // and the continuum's floor stress rho nu U tanh(H / delta) / delta to the grid's order
    CHECK(stresses.floor ==
          doctest::Approx(1000.0 * nu * stream * std::tanh(depth / delta) / delta).epsilon(2.0 / (cells * cells)));
  }
  const double order_coarse = observed_order(errors[1], errors[2]);
  const double order_fine = observed_order(errors[2], errors[3]);
  std::printf("pulled towards a uniform stream: relative max error %.3e %.3e %.3e %.3e (10-80 cells), observed order "
              "%.4f %.4f\n", errors[0], errors[1], errors[2], errors[3], order_coarse, order_fine);
  CHECK(order_coarse == doctest::Approx(2.0).epsilon(0.1));
  CHECK(order_fine == doctest::Approx(2.0).epsilon(0.05));
}

TEST_CASE("mean-flow column verification: the start-up of Couette flow converges at first order in dt") {
  // A lid set moving at U over water at rest: u = U z / H - sum_n 2 U (-1)^(n+1) / (n pi) sin(n pi z / H)
  // exp(-n^2 pi^2 nu t / H^2). Compared at t = 0.05 H^2 / nu on 400 cells (the spatial error, O(h^2) ~ 1e-6 U,
  // is far below the time error); backward Euler's error falls as dt.
  const double depth = 0.01, nu = 1e-6, lid = 0.1;
  const double end = 0.05 * depth * depth / nu;
  const ColumnGrid grid = grid_of(400, depth);
  ColumnEnds ends;
  ends.top_given = true;
  ends.top_value = lid;
  const std::vector<double> clear(grid.cells, 0.0), no_eddy(grid.cells + 1, 0.0);
  std::vector<double> exact(grid.cells);
  for (std::size_t i = 0; i < grid.cells; ++i) {
    const double z = grid.centre(i);
    double u = lid * z / depth;
    for (int n = 1; n <= 200; ++n)
      u -= 2.0 * lid * (n % 2 == 1 ? 1.0 : -1.0) / (n * std::numbers::pi) * std::sin(n * std::numbers::pi * z / depth) *
           std::exp(-n * n * std::numbers::pi * std::numbers::pi * nu * end / (depth * depth));
    exact[i] = u;
  }
  std::vector<double> errors;
  for (const int steps : {10, 20, 40, 80}) {
    ColumnStep step;
    step.viscosity = nu;
    step.dt = end / steps;
    std::vector<double> u(grid.cells, 0.0);
    for (int k = 0; k < steps; ++k) advance_column(grid, clear, no_eddy, clear, ends, step, u);
    double error = 0.0;
    for (std::size_t i = 0; i < grid.cells; ++i) error = std::max(error, std::abs(u[i] - exact[i]));
    errors.push_back(error / lid);
  }
  std::printf("Couette start-up: relative max error %.3e %.3e %.3e %.3e (10, 20, 40, 80 steps), orders %.3f %.3f %.3f\n",
              errors[0], errors[1], errors[2], errors[3], observed_order(errors[0], errors[1]),
              observed_order(errors[1], errors[2]), observed_order(errors[2], errors[3]));
  // Backward Euler is first order: the observed order tends to 1 as dt falls.
  CHECK(observed_order(errors[2], errors[3]) == doctest::Approx(1.0).epsilon(0.1));
  CHECK(observed_order(errors[1], errors[2]) == doctest::Approx(1.0).epsilon(0.15));
  CHECK(errors[3] < 5e-3);
}

namespace {
/// The grid convergence of a turbulent channel over three grids: second order against the closure's own profile,
/// and the log law's error at the two finest grids differing by less than a tenth of the 2 % tolerance.
void check_grid_convergence(const char* name, const std::vector<double>& model_errors,
                            const std::vector<double>& law_errors) {
  const double order_coarse = observed_order(model_errors[0], model_errors[1]);
  const double order_fine = observed_order(model_errors[1], model_errors[2]);
  std::printf("%s: observed order against the closure's own profile %.3f %.3f\n", name, order_coarse, order_fine);
  CHECK(order_coarse == doctest::Approx(2.0).epsilon(0.1));
  CHECK(order_fine == doctest::Approx(2.0).epsilon(0.1));
  CHECK(std::abs(law_errors[1] - law_errors[2]) < 0.002);
}
}  // namespace

TEST_CASE("mean-flow column verification: smooth-floor turbulent open channel, van Driest's log law") {
  // Re_tau = u* H / nu = 1000 (H = 5 cm, u* = 2 cm/s), h+ = 2, 1, 0.5.
  const double depth = 0.05, nu = 1e-6, u_star = 0.02;
  ColumnStep step;
  step.viscosity = nu;
  step.body_force = u_star * u_star / depth;
  MixingLengthClosure closure;
  // Van Driest's model's own log-law constant (constant stress, z+ -> infinity), by quadrature of
  // du+/dz+ = 2 / (1 + sqrt(1 + 4 l+^2)), l+ = kappa z+ (1 - exp(-z+ / 26)): B = 5.28 for kappa = 0.41 (5.22 for
  // kappa = 0.40); the log law's usual B = 5.2 (Pope 2000, section 7.1.4: 5.2 with kappa = 0.41) is 0.08 below.
  {
    ContinuousChannel wall{1e30, 1.0, 1.0, [](double z) { return kKappa * z * (1.0 - std::exp(-z / 26.0)); }};
    std::vector<double> heights;
    for (double z = 1.0; z <= 1e5; z *= 1.25) heights.push_back(z);
    const double b = wall.velocity_at(heights).back() - std::log(heights.back()) / kKappa;
    std::printf("van Driest (kappa 0.41, A+ 26): B = %.4f\n", b);
    CHECK(b == doctest::Approx(5.28).epsilon(0.002));
  }
  const ContinuousChannel model{depth, u_star, nu, [&](double z) {
                                  return kKappa * z * (1.0 - std::exp(-z * u_star / (nu * 26.0)));
                                }};
  std::vector<double> model_errors, law_errors;
  for (const std::size_t cells : {500u, 1000u, 2000u}) {
    CAPTURE(cells);
    const ColumnGrid grid = grid_of(cells, depth);
    const TurbulentSteady steady = turbulent_steady(grid, closure, step, u_star);
    CAPTURE(steady.iterations);
    REQUIRE(steady.change < 1e-9);
    // The floor carries the whole body force: tau_floor = rho f H = rho u*^2.
    CHECK(steady.stresses.floor / (step.density * u_star * u_star) == doctest::Approx(1.0).epsilon(1e-6));
    std::vector<double> heights;
    std::vector<std::size_t> cells_in;
    for (std::size_t i = 0; i < cells; ++i) {
      const double z = grid.centre(i);
      if (z * u_star / nu > 30.0 && z / depth < 0.2) {  // the log layer (Pope 2000, section 7.1.4)
        heights.push_back(z);
        cells_in.push_back(i);
      }
    }
    const std::vector<double> reference = model.velocity_at(heights);
    // Van Driest's profile is still in its buffer blend at z+ = 30 (the damping 1 - exp(-30 / 26) = 0.69): the
    // closure's own continuous profile lies 2.3 % below the log law there at constant stress (2.9 % here with the
    // stress falling as 1 - z / H), 0.7 % at z+ = 40 and within 0.6 % from z+ = 50 on. So the discrete profile is
    // held to the closure's own profile over the whole log layer, and to the log law from z+ = 50.
    double model_error = 0.0, law_error = 0.0, buffer_error = 0.0;
    for (std::size_t k = 0; k < heights.size(); ++k) {
      const double z_plus = heights[k] * u_star / nu;
      const double u_plus = steady.velocity[cells_in[k]] / u_star;
      model_error = std::max(model_error, std::abs(u_plus - reference[k] / u_star));
      const double law = std::log(z_plus) / kKappa + 5.2;
      (z_plus >= 50.0 ? law_error : buffer_error) =
          std::max(z_plus >= 50.0 ? law_error : buffer_error, std::abs(u_plus / law - 1.0));
    }
    model_errors.push_back(model_error);
    law_errors.push_back(law_error);
    std::printf("smooth channel, %zu cells (h+ = %.2f): %d steps; |u+ - model| <= %.3e; log law within %.3f %% "
                "(50 <= z+ <= 0.2 Re_tau), %.3f %% (30 < z+ < 50)\n",
                cells, grid.cell_height * u_star / nu, steady.iterations, model_error, 100.0 * law_error,
                100.0 * buffer_error);
    CHECK(law_error < 0.02);
  }
  check_grid_convergence("smooth channel", model_errors, law_errors);
}

TEST_CASE("mean-flow column verification: smooth-walled turbulent plane Couette flow, the log law at both walls") {
  // A lid at 1 m/s over a smooth floor, H = 5 cm: the stress is the same at every height, so each wall's layer is
  // the constant-stress layer of the log law, u+ = ln z+ / 0.41 + 5.2 from the floor and (U - u)+ from the lid
  // (the mixing length is kappa times the distance to the nearer wall, damped by van Driest's factor of that wall).
  const double depth = 0.05, nu = 1e-6, lid = 1.0;
  ColumnStep step;
  step.viscosity = nu;
  MixingLengthClosure closure;
  std::vector<double> law_errors;
  for (const std::size_t cells : {500u, 1000u, 2000u}) {
    CAPTURE(cells);
    const ColumnGrid grid = grid_of(cells, depth);
    const TurbulentSteady steady = turbulent_steady(grid, closure, step, 0.04, lid);
    CAPTURE(steady.iterations);
    REQUIRE(steady.change < 1e-9);
    // Steady Couette flow: the lid's stress is the floor's.
    CHECK(steady.stresses.top / steady.stresses.floor == doctest::Approx(1.0).epsilon(1e-6));
    const double u_star = std::sqrt(steady.stresses.floor / step.density);
    double floor_error = 0.0, lid_error = 0.0, symmetry = 0.0;
    for (std::size_t i = 0; i < cells; ++i) {
      const double z = grid.centre(i);
      const double z_plus = z * u_star / nu, lid_plus = (depth - z) * u_star / nu;
      const double law_floor = std::log(z_plus) / kKappa + 5.2, law_lid = std::log(lid_plus) / kKappa + 5.2;
      if (z_plus >= 50.0 && z < 0.1 * depth)
        floor_error = std::max(floor_error, std::abs(steady.velocity[i] / u_star / law_floor - 1.0));
      if (lid_plus >= 50.0 && depth - z < 0.1 * depth)
        lid_error = std::max(lid_error, std::abs((lid - steady.velocity[i]) / u_star / law_lid - 1.0));
      // Point symmetry about the centre: u(z) + u(H - z) = U.
      symmetry = std::max(symmetry, std::abs(steady.velocity[i] + steady.velocity[cells - 1 - i] - lid) / lid);
    }
    std::printf("Couette, %zu cells: u* = %.5f m/s (Re_tau %.0f); log law within %.3f %% at the floor, %.3f %% at "
                "the lid (50 <= z+, z < 0.1 H); symmetry %.1e\n",
                cells, u_star, u_star * depth / nu, 100.0 * floor_error, 100.0 * lid_error, symmetry);
    CHECK(floor_error < 0.02);
    CHECK(lid_error < 0.02);
    CHECK(symmetry < 1e-6);
    law_errors.push_back(std::max(floor_error, lid_error));
  }
  CHECK(std::abs(law_errors[1] - law_errors[2]) < 0.002);
}

TEST_CASE("mean-flow column verification: rough-floor turbulent open channel, Nikuradse's rough log law") {
  // k_s = 2.5 mm, k_s+ = 100 (fully rough, above Nikuradse's 70), H = 10 cm (Re_tau = 4000), h+ = 1, 0.5, 0.25.
  const double depth = 0.1, nu = 1e-6, roughness = 2.5e-3;
  const double u_star = 100.0 * nu / roughness;
  ColumnStep step;
  step.viscosity = nu;
  step.body_force = u_star * u_star / depth;
  MixingLengthClosure closure;
  closure.floor = MixingLengthClosure::Floor::kRough;
  closure.roughness = roughness;
  // The floor's mixing length l0 for which the closure's constant-stress profile (u+ = (F(l+) - F(l0+)) / kappa)
  // reaches u+ = ln(z / k_s) / kappa + 8.5 far above: F(l0+) = ln(4 kappa k_s+) - 1 - 8.5 kappa, by bisection.
  double low = 0.0, high = 10.0;
  const double target = std::log(4.0 * kKappa * 100.0) - 1.0 - 8.5 * kKappa;
  for (int k = 0; k < 200; ++k) (primitive(0.5 * (low + high)) < target ? low : high) = 0.5 * (low + high);
  const double floor_length = 0.5 * (low + high) * nu / u_star;
  std::printf("rough floor, k_s+ = 100: l0+ = %.4f (kappa z0+ = %.4f)\n", floor_length * u_star / nu,
              kKappa * 100.0 * std::exp(-kKappa * 8.5));
  const ContinuousChannel model{depth, u_star, nu, [&](double z) { return floor_length + kKappa * z; }};
  std::vector<double> model_errors, law_errors;
  for (const std::size_t cells : {4000u, 8000u, 16000u}) {
    CAPTURE(cells);
    const ColumnGrid grid = grid_of(cells, depth);
    CHECK(mixing_lengths(grid, std::vector<double>(cells, 0.0), closure, u_star, nu)[0] ==
          doctest::Approx(floor_length).epsilon(1e-10));
    const TurbulentSteady steady = turbulent_steady(grid, closure, step, u_star);
    CAPTURE(steady.iterations);
    REQUIRE(steady.change < 1e-9);
    CHECK(steady.stresses.floor / (step.density * u_star * u_star) == doctest::Approx(1.0).epsilon(1e-6));
    std::vector<double> heights;
    std::vector<std::size_t> cells_in;
    for (std::size_t i = 0; i < cells; ++i) {
      const double z = grid.centre(i);
      if (z >= roughness && z <= 0.2 * depth) {
        heights.push_back(z);
        cells_in.push_back(i);
      }
    }
    const std::vector<double> reference = model.velocity_at(heights);
    double model_error = 0.0, law_error = 0.0;
    for (std::size_t k = 0; k < heights.size(); ++k) {
      const double u_plus = steady.velocity[cells_in[k]] / u_star;
      model_error = std::max(model_error, std::abs(u_plus - reference[k] / u_star));
      const double law = std::log(heights[k] / roughness) / kKappa + 8.5;
      law_error = std::max(law_error, std::abs(u_plus / law - 1.0));
    }
    model_errors.push_back(model_error);
    law_errors.push_back(law_error);
    std::printf("rough channel, %zu cells (h+ = %.2f): %d steps; |u+ - model| <= %.3e; rough log law within %.3f %%\n",
                cells, grid.cell_height * u_star / nu, steady.iterations, model_error, 100.0 * law_error);
    CHECK(law_error < 0.02);
  }
  check_grid_convergence("rough channel", model_errors, law_errors);
}

TEST_CASE("mean-flow column verification: a packed bed with linear drag reaches Darcy's velocity inside") {
  // The lower 4 mm of a 5 mm column packed (phi = 0.6), the grains taking a linear drag rho eps K u per unit volume
  // from the water there, as the impulse rho eps h K u dt of the step before (as the coupling hands it over).
  // Steady: deep in the bed the body force meets the drag, u = f / K (Darcy); the shear of the floor and of the
  // clear water above reaches in over Brinkman's length delta = sqrt(nu / K) = 0.1 mm only. The clear layer's stress
  // at the bed's top, rho f (1 mm), drives an excess of about f (1 mm) delta / (eps nu) = 25 f / K there (the
  // floor's deficit is f / K), so 15 lengths from the floor and the bed's top the departure is about 25 exp(-15)
  // = 8e-6 of Darcy's velocity, asserted within twice that. The floor's stress and the drag carry the body force.
  const double depth = 0.005, nu = 1e-6, f = 1e-3, drag = 100.0;  // [m], [m^2/s], [m/s^2], K [1/s]
  const ColumnGrid grid = grid_of(100, depth);                     // h = 0.5 Brinkman lengths
  std::vector<double> phi(grid.cells, 0.0);
  for (std::size_t i = 0; i < 80; ++i) phi[i] = 0.6;
  ColumnStep step;
  step.viscosity = nu;
  step.body_force = f;
  step.dt = 0.5 / drag;  // the lagged drag is stable for K dt < 2
  const ColumnEnds ends;
  const std::vector<double> no_eddy(grid.cells + 1, 0.0);
  std::vector<double> u(grid.cells, 0.0), impulse(grid.cells, 0.0);
  ColumnStresses stresses;
  // The clear layer's diffusion time is (1 mm)^2 / nu = 1 s; 20 s leave exp(-20 pi^2 / 4) of the start.
  const int steps = static_cast<int>(20.0 / step.dt);
  for (int k = 0; k < steps; ++k) {
    for (std::size_t i = 0; i < grid.cells; ++i)
      impulse[i] = step.dt * step.density * (1.0 - phi[i]) * grid.cell_height * (phi[i] > 0.0 ? drag : 0.0) * u[i];
    stresses = advance_column(grid, phi, no_eddy, impulse, ends, step, u);
  }
  const double brinkman = std::sqrt(nu / drag);
  double worst = 0.0, drag_total = 0.0;
  for (std::size_t i = 0; i < grid.cells; ++i) {
    const double z = grid.centre(i);
    if (z > 15.0 * brinkman && z < 0.004 - 15.0 * brinkman) worst = std::max(worst, std::abs(u[i] * drag / f - 1.0));
    drag_total += step.density * (1.0 - phi[i]) * grid.cell_height * (phi[i] > 0.0 ? drag : 0.0) * u[i];
  }
  std::printf("Darcy bed: deep in the bed |u K / f - 1| <= %.3e\n", worst);
  const double excess = f * 0.001 * brinkman / (0.4 * nu) / (f / drag);
  CHECK(worst < 2.0 * excess * std::exp(-15.0));
  double body = 0.0;
  for (std::size_t i = 0; i < grid.cells; ++i) body += step.density * (1.0 - phi[i]) * grid.cell_height * f;
  CHECK(stresses.floor + drag_total == doctest::Approx(body).epsilon(1e-9));
}
