// Verification: sloshing in a rectangular tank. The free decay of the first mode against linear potential theory,
// omega^2 = g k tanh(k h), k = pi / L, and the seed's shaken tank (A = 1 cm, f = 1.7 Hz, 6 cm of water, L = 0.24 m)
// for a few periods: stable, no particle lost, density held.
//
// Sizes (CTest time): thin slabs. The free decay is a slab periodic along y, 6 l0 wide (the mode is uniform in y; a
// period of at least 2 r_e, so that no particle sees its own image), at l0 = 6, 4 and 3 mm (10, 15, 20 layers of
// depth), five periods each. Between walls, a slab 3 l0 wide is all wall layer (every particle within r_e of both
// walls) and its mode is slow by 3.3, 2.9, 3.8 and 5.0 % at l0 = 8, 6, 4 and 3 mm: the walls' share grows with
// the slab's thinning, not a property of the open water (periodic: +1.5, -0.3, -0.2, +0.2 %). The shaken tank is a
// slab 3 l0 wide between walls at 7.5 mm (8 layers), three periods: stability and volume, not a frequency.
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "tests/support/fluid_support.hpp"

namespace riffle {
namespace {

using test::kG;

double mean_x(const test::FluidRun& run) {
  double sum = 0.0;
  for (std::size_t i = 0; i < run.fluid_count(); ++i) sum += run.world.fluid->position[i].x();
  return sum / static_cast<double>(run.fluid_count());
}

struct DecayFit {
  double omega = 0.0, damping = 0.0, residual = 0.0, amplitude = 0.0;
};

/// Residual of the linear least squares for A, B, c at one (omega, zeta).
DecayFit fit_at(const std::vector<double>& t, const std::vector<double>& x, double omega, double zeta) {
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> basis(t.size());
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double envelope = std::exp(-zeta * omega * t[i]);
    basis[i] = Eigen::Vector3d(envelope * std::sin(omega * t[i]), envelope * std::cos(omega * t[i]), 1.0);
    normal += basis[i] * basis[i].transpose();
    rhs += basis[i] * x[i];
  }
  const Eigen::Vector3d c = normal.ldlt().solve(rhs);
  double residual = 0.0;
  for (std::size_t i = 0; i < t.size(); ++i) residual += std::pow(x[i] - basis[i].dot(c), 2);
  return {omega, zeta, std::sqrt(residual / static_cast<double>(t.size())), std::hypot(c[0], c[1])};
}

/// Least-squares fit of x(t) = exp(-zeta omega t) (A sin omega t + B cos omega t) + c: a coarse scan over omega
/// (steps of 1 %) and zeta (0 .. 0.1), then a fine one (0.05 %) around the best.
DecayFit fit_damped_sine(const std::vector<double>& t, const std::vector<double>& x, double omega_low,
                         double omega_high) {
  DecayFit best;
  best.residual = std::numeric_limits<double>::infinity();
  for (double omega = omega_low; omega <= omega_high; omega += 0.01 * omega_low)
    for (double zeta = 0.0; zeta <= 0.1; zeta += 0.005) {
      const DecayFit fit = fit_at(t, x, omega, zeta);
      if (fit.residual < best.residual) best = fit;
    }
  const DecayFit coarse = best;
  for (double omega = coarse.omega * 0.985; omega <= coarse.omega * 1.015; omega += 5.0e-4 * coarse.omega)
    for (double zeta = std::max(0.0, coarse.damping - 0.005); zeta <= coarse.damping + 0.005; zeta += 0.0005) {
      const DecayFit fit = fit_at(t, x, omega, zeta);
      if (fit.residual < best.residual) best = fit;
    }
  return best;
}

struct FreeDecay {
  double theory = 0.0, tolerance = 0.0;
  DecayFit fit;
  std::size_t outside = 0;
  std::int64_t steps = 0;
  double ke_start = 0.0, ke_end = 0.0;
};

/// First-mode free decay in a 0.12 m long tank with 6 cm of water (kh = pi/2), five periods, in a slab 6 l0 wide
/// periodic along y.
FreeDecay free_decay(double l0) {
  const double length = 0.12, depth = 0.06, width = 6 * l0;
  const double k = std::numbers::pi / length;
  FreeDecay result;
  const double omega = result.theory = std::sqrt(kG * k * std::tanh(k * depth));  // 15.35 rad/s, f = 2.443 Hz
  Model model = test::fluid_model(Vec3(length, width, 2 * depth), l0,
                                  {ParticleBoxModel{Vec3::Zero(), Vec3(length, width, depth)}});
  model.tank.periodic = {false, true, false};
  model.dt = 1.0e-3 * std::sqrt(l0 / 0.005);  // 1 ms at 5 mm (amendment 3), scaled with sqrt(l0/g)
  // Start from the flat surface with the velocity of the first standing mode at its zero crossing: potential
  // phi = B cos(kx) cosh(kz), surface elevation eta0 cos(kx) sin(omega t), B = eta0 omega / (k sinh(kh)).
  // eta0 = 3 mm: k eta0 = 0.08, so the amplitude correction to the frequency, O((k eta0)^2), is below 1 %.
  const double eta0 = 0.003;
  const double b = eta0 * omega / (k * std::sinh(k * depth));
  test::FluidRun run(std::move(model), [&](World& world) {
    FluidParticles& fluid = *world.fluid;
    for (std::size_t i = 0; i < fluid_slot_count(fluid); ++i) {
      const Vec3& r = fluid.position[i];
      fluid.velocity[i] = Vec3(-b * k * std::sin(k * r.x()) * std::cosh(k * r.z()), 0.0,
                               b * k * std::cos(k * r.x()) * std::sinh(k * r.z()));
    }
  });
  // The centre of mass moves along x at the mode's frequency (x_c - L/2 = -(2 L eta0 / (pi^2 h)) sin(omega t)
  // for the linear mode; the odd modes 3, 5, ... add a little at higher frequencies, which the fit ignores).
  std::vector<double> times, positions;
  const double period = 2.0 * std::numbers::pi / omega;
  while (run.world.time < 5.0 * period) {
    if (!run.step()) FAIL(run.diagnosis());
    if (result.steps++ == 0) result.ke_start = run.world.fluid_summary->kinetic_energy;
    times.push_back(run.world.time);
    positions.push_back(mean_x(run) - 0.5 * length);
  }
  result.ke_end = run.world.fluid_summary->kinetic_energy;
  result.outside = run.count_outside_tank(0.5 * l0);
  result.fit = fit_damped_sine(times, positions, 0.7 * omega, 1.3 * omega);
  // Tolerance: the discrete fluid's depth and length are known to about half a spacing (the Dirichlet surface sits
  // at the surface-particle centres, l0/2 below the real surface, test 1; the walls' Neumann condition is imposed
  // between the wall layer at l0/2 outside and the first fluid layer at l0/2 inside). Linear theory gives
  // d ln(omega)/d ln(h) = kh / (2 sinh(kh) cosh(kh)) and d ln(omega)/d ln(L) = -(1/2)(1 + kh/(sinh cosh)); add the
  // amplitude correction (k eta0)^2 = 0.6 % and the fit's frequency step (0.05 %, rounded up to 0.1 %).
  const double kh = k * depth, sc = std::sinh(kh) * std::cosh(kh);
  result.tolerance = kh / (2.0 * sc) * (0.5 * l0 / depth) + 0.5 * (1.0 + kh / sc) * (0.5 * l0 / length) +
                     std::pow(k * eta0, 2) + 0.001;
  return result;
}

/// The first mode's frequency at one l0 against linear theory, within the tolerance that the resolution allows
/// (half a spacing on the depth and the length, plus the amplitude and fit terms: free_decay). The tolerance
/// shrinks in proportion to l0, so passing at 6, 4 and 3 mm says the error falls at least as fast as the
/// discretisation's half-spacing uncertainty: the frequency converges to the theory's, not to a value of its own.
FreeDecay check_first_mode_frequency(double l0) {
  const FreeDecay decay = free_decay(l0);
  MESSAGE("l0 " << l0 << " m: fitted omega " << decay.fit.omega << " rad/s vs " << decay.theory << ": relative "
                << decay.fit.omega / decay.theory - 1.0 << ", tolerance " << decay.tolerance << ", damping ratio "
                << decay.fit.damping << ", fit residual / amplitude " << decay.fit.residual / decay.fit.amplitude);
  CHECK(decay.outside == 0);
  CHECK(decay.fit.residual < 0.2 * decay.fit.amplitude);
  CHECK(std::abs(decay.fit.omega / decay.theory - 1.0) < decay.tolerance);
  return decay;
}

}  // namespace

// With the prototype's density relaxation (6-12 /s) the first-mode frequency came out about 5 % below linear theory
// at l0 = 6 and 4 mm, and the mode's energy leaked into particle-scale noise; the default 48 /s holds it.
// At 6 mm the same run also checks the mode itself: the amplitude started.
TEST_CASE("first sloshing mode frequency within the resolution tolerance of linear theory, l0 = 6 mm") {
  const FreeDecay decay = check_first_mode_frequency(0.006);
  MESSAGE("first mode at 6 mm: amplitude " << decay.fit.amplitude << " m, KE " << decay.ke_start << " -> "
                                           << decay.ke_end << " J, " << decay.steps << " steps");
  // The amplitude is that of the mode started: 2 L eta0 / (pi^2 h) = 1.2 mm, within a factor 2 after the start.
  CHECK(decay.fit.amplitude > 0.6e-3);
  CHECK(decay.fit.amplitude < 2.4e-3);
}
TEST_CASE("first sloshing mode frequency within the resolution tolerance of linear theory, l0 = 4 mm") {
  check_first_mode_frequency(0.004);
}
TEST_CASE("first sloshing mode frequency within the resolution tolerance of linear theory, l0 = 3 mm") {
  check_first_mode_frequency(0.003);
}

namespace {

struct Shaken {
  std::size_t count = 0, final_count = 0, outside_max = 0;
  std::int64_t steps = 0;
  double density_min = 1.0, density_max = 1.0, volume_error = 0.0;
};

/// The seed's shaken tank (L = 0.24 m, 6 cm of water, x = -A sin(2 pi f t), A = 1 cm, f = 1.7 Hz, a one-period
/// ramp) at l0 = 7.5 mm for three periods.
Shaken shaken_tank() {
  const double length = 0.24, depth = 0.06, l0 = 0.0075, width = 3 * l0;
  Model model = test::fluid_model(Vec3(length, width, 3 * depth), l0,
                                  {ParticleBoxModel{Vec3::Zero(), Vec3(length, width, depth)}});
  model.dt = 1.0e-3 * std::sqrt(l0 / 0.005);
  model.tank.motion.kind = TankMotionModel::Kind::kSinusoidal;
  model.tank.motion.amplitude = 0.01;
  model.tank.motion.frequency = 1.7;
  model.tank.motion.ramp_time = 1.0 / 1.7;  // one period (the seed's gradual start; prototype section 5)
  test::FluidRun run(std::move(model));
  Shaken result;
  result.count = run.fluid_count();
  const double volume0 = static_cast<double>(result.count) * l0 * l0 * l0;
  while (run.world.time < 3.0 / 1.7 - 1e-12) {
    if (!run.step()) FAIL(run.diagnosis());
    ++result.steps;
    const FluidSummary& summary = *run.world.fluid_summary;
    result.density_min = std::min(result.density_min, summary.mean_density_ratio);
    result.density_max = std::max(result.density_max, summary.mean_density_ratio);
    result.volume_error = std::max(result.volume_error, std::abs(summary.volume / volume0 - 1.0));
    result.outside_max = std::max(result.outside_max, run.count_outside_tank(0.5 * l0));
  }
  result.final_count = run.fluid_count();
  MESSAGE("shaken tank: " << result.steps << " steps, " << result.count << " particles, outside the tank at most "
                          << result.outside_max << ", mean n/n0 in [" << result.density_min << ", "
                          << result.density_max << "], max |V/V0 - 1| " << result.volume_error);
  return result;
}

}  // namespace

TEST_CASE("shaken tank at the seed forcing stays stable and keeps its particles") {
  const Shaken shaken = shaken_tank();
  // Particles: none may leave the tank (beyond the wall-particle plane, l0/2 outside the inner boundary).
  CHECK(shaken.outside_max == 0);
  CHECK(shaken.final_count == shaken.count);
  // No collapse or blow-up of the density: mean n/n0 within the still-water surface threshold band (beta = 0.93
  // defines a particle that has lost 7 % of its neighbours as surface; an interior mean beyond 1 +- 0.07 would mean
  // the interior is no longer a liquid).
  CHECK(shaken.density_min > 0.93);
  CHECK(shaken.density_max < 1.07);
}

// At the prototype's density relaxation rate (gamma/dt = 12 /s) the interior mean n/n0 reached 1.018 in the third
// period (1.019 at l0 = 5 mm) and the particle volume fell by 1.3 %; with 24 /s (now the default) it stays within
// 0.7 %, with 48 /s within 0.3 %.
TEST_CASE("shaken tank holds mean n/n0 and volume within 1 percent") {
  const Shaken shaken = shaken_tank();
  // Incompressibility: the required 1 % on the interior mean n/n0 and on the particle volume (numerics 6.2: 1 %).
  CHECK(shaken.density_min > 0.99);
  CHECK(shaken.density_max < 1.01);
  CHECK(shaken.volume_error < 0.01);
}

}  // namespace riffle
