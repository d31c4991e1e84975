// The grain's self-induced disturbance (systems/physics/coupling/self_induced.hpp) against independent evaluations: <1/r>
// and <rho_s rho_w> of two Wendland kernels by direct quadrature in real space, the Oseen factor's limits (Stokes
// at Re_R -> 0, Oseen's far wake 1/Re_R decay), the mode fit of the build-up, and the drag/disturbance solve.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "systems/physics/coupling/self_induced.hpp"
#include "systems/physics/math/counter_random.hpp"

using namespace riffle;

namespace {
double wendland(double q) { return q < 1.0 ? std::pow(1.0 - q, 4) * (1.0 + 4.0 * q) : 0.0; }
}  // namespace

TEST_CASE("R <1/r> of two unit Wendland kernels by a real-space sum matches the Fourier-space value") {
  // <1/|x - y|> = int int rho(x) rho(y) / |x - y|: by the shell theorem, the potential of the kernel's radial
  // density at radius s is 4 pi [ (1/s) int_0^s rho r^2 dr + int_s^1 rho r dr ]; then average it over rho.
  const int n = 4000;
  const double norm = 2.0 * std::numbers::pi / 21.0;  // int w dV on R = 1
  std::vector<double> inner(n + 1, 0.0), outer(n + 1, 0.0);
  const double h = 1.0 / n;
  for (int i = 1; i <= n; ++i) {
    const double a = (i - 0.5) * h;
    inner[i] = inner[i - 1] + wendland(a) / norm * a * a * h;
  }
  for (int i = n - 1; i >= 0; --i) {
    const double a = (i + 0.5) * h;
    outer[i] = outer[i + 1] + wendland(a) / norm * a * h;
  }
  double average = 0.0;
  for (int i = 0; i < n; ++i) {
    const double s = (i + 0.5) * h;
    const double potential = 4.0 * std::numbers::pi * (0.5 * (inner[i] + inner[i + 1]) / s + 0.5 * (outer[i] + outer[i + 1]));
    average += 4.0 * std::numbers::pi * s * s * wendland(s) / norm * potential * h;
  }
  CHECK(self_induced_inverse_distance() == doctest::Approx(average).epsilon(1e-4));
  CHECK(self_induced_inverse_distance() == doctest::Approx(2.1482).epsilon(2e-4));  // also a Monte Carlo estimate
}

TEST_CASE("R^3 <rho_s rho_w> of the Wendland kernel is 1.2 (int w^2 / (int w)^2)") {
  // By a midpoint sum in q, independent of the Simpson rule the code uses.
  double sum = 0.0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const double q = (i + 0.5) / n;
    sum += wendland(q) * wendland(q) * q * q / n;
  }
  const double norm = 2.0 * std::numbers::pi / 21.0;
  CHECK(self_induced_overlap() == doctest::Approx(4.0 * std::numbers::pi * sum / (norm * norm)).epsilon(1e-8));
}

TEST_CASE("the Oseen factor is 1 in Stokes flow, falls monotonically, and decays as 1/Re_R in the far wake") {
  CHECK(self_induced_oseen_factor(0.0) == 1.0);
  CHECK(self_induced_oseen_factor(1e-4) == doctest::Approx(1.0).epsilon(1e-3));
  double last = 1.0;
  for (double re = 1e-3; re < 1e5; re *= 1.7) {
    const double phi = self_induced_oseen_factor(re);
    CHECK(phi <= last);
    CHECK(phi > 0.0);
    last = phi;
  }
  // Far wake: the angular integral tends to pi kappa / Re_R, so phi -> (3 pi / 4) int W^2 kappa / int W^2 / Re_R.
  const double ratio = self_induced_oseen_factor(2000.0) * 2000.0 / (self_induced_oseen_factor(4000.0) * 4000.0);
  CHECK(ratio == doctest::Approx(1.0).epsilon(0.01));
  // Independent values (python quadrature of the same integrals, tools-free): 0.8493 at 1, 0.3456 at 10.
  CHECK(self_induced_oseen_factor(1.0) == doctest::Approx(0.8493).epsilon(2e-3));
  CHECK(self_induced_oseen_factor(10.0) == doctest::Approx(0.3456).epsilon(2e-3));
}

TEST_CASE("the three lags reproduce the build-up of the regularised Stokeslet within 0.04") {
  double sum = 0.0;
  for (double a : SelfInducedModes::amplitude) sum += a;
  CHECK(sum == doctest::Approx(1.0).epsilon(1e-8));
  for (double t = 1e-3; t < 30.0; t *= 1.5) {
    double fit = 1.0;
    for (int m = 0; m < SelfInducedModes::kCount; ++m)
      fit -= SelfInducedModes::amplitude[m] * std::exp(-t / SelfInducedModes::time[m]);
    CHECK(std::abs(fit - self_induced_buildup(t)) < 0.042);
  }
  CHECK(self_induced_buildup(1e-6) < 1e-3);
  CHECK(self_induced_buildup(1e4) > 0.99);
}

TEST_CASE("a point Stokeslet builds as erfc(1 / (2 sqrt T)) at distance r, and the wall's lag is half built with it") {
  // Independent of the closed form: (2/pi) int_0^inf sin q / q (1 - exp(-q^2 T)) dq by the midpoint rule up to
  // q = 12 / sqrt(T) (the exponential is below e^-144 beyond; the rest of sin q / q is zero there).
  for (double t : {0.02, 0.1, 0.3, 1.0, 3.0, 10.0}) {
    CAPTURE(t);
    const double top = 12.0 / std::sqrt(t);
    const int steps = 400000;
    const double h = top / steps;
    double sum = 0.0;
    for (int k = 0; k < steps; ++k) {
      const double q = (k + 0.5) * h;
      sum += std::sin(q) / q * std::exp(-q * q * t) * h;
    }
    CHECK(stokeslet_point_buildup(t) == doctest::Approx(1.0 - 2.0 / std::numbers::pi * sum).epsilon(1e-6));
  }
  CHECK(stokeslet_point_buildup(kStokesletHalfRiseTime) == doctest::Approx(0.5).epsilon(1e-4));
  // The lag of time T_w (Stokes) is half built at the half-rise time; the Oseen reduction shortens it as the modes'.
  CHECK(1.0 - std::exp(-kStokesletHalfRiseTime / self_induced_wall_time(0.0)) == doctest::Approx(0.5).epsilon(1e-12));
  CHECK(self_induced_wall_time(10.0) == doctest::Approx(self_induced_wall_time(0.0) /
                                                        (1.0 + 10.0 * self_induced_wall_time(0.0))));
  CHECK(stokeslet_point_buildup(0.0) == 0.0);
  CHECK(stokeslet_point_buildup(1e6) > 0.999);
}

TEST_CASE("the unsteady Oseen build-up is the Stokes one at Re_R = 0 and tends to the steady Oseen factor") {
  for (double t : {1e-3, 0.01, 0.1, 1.0, 10.0})
    CHECK(self_induced_oseen_buildup(t, 0.0) == doctest::Approx(self_induced_buildup(t)).epsilon(3e-3));
  for (double re : {1.0, 3.0, 10.0, 100.0})
    CHECK(self_induced_oseen_buildup(1e3, re) == doctest::Approx(self_induced_oseen_factor(re)).epsilon(5e-3));
  // Independent values: a python quadrature of the unsteady symbol itself, Re[(1 - exp(-z T)) / z] with
  // z = kappa^2 + i Re_R kappa c, over kappa (to 120) and c (801 points), not its rate's closed angular integral.
  CHECK(self_induced_oseen_buildup(0.2, 1.0) == doctest::Approx(0.4891).epsilon(3e-3));
  CHECK(self_induced_oseen_buildup(1.0, 1.0) == doctest::Approx(0.7280).epsilon(3e-3));
  CHECK(self_induced_oseen_buildup(0.1, 2.9) == doctest::Approx(0.3510).epsilon(3e-3));
  CHECK(self_induced_oseen_buildup(1.0, 2.9) == doctest::Approx(0.6300).epsilon(3e-3));
  CHECK(self_induced_oseen_buildup(0.05, 10.0) == doctest::Approx(0.2153).epsilon(3e-3));
  CHECK(self_induced_oseen_buildup(0.2, 10.0) == doctest::Approx(0.3284).epsilon(3e-3));
}

TEST_CASE("with two speeds the modes build up to the far field's Oseen disturbance, not beyond it") {
  // The same speed twice: the one-speed fit.
  for (double re : {0.0, 0.3, 1.7, 20.0}) {
    const auto one = self_induced_mode_amplitudes(re);
    const auto two = self_induced_two_speed_amplitudes(re, re);
    for (std::size_t m = 0; m < one.size(); ++m) CHECK(two[m] == doctest::Approx(one[m]).epsilon(1e-12));
  }
  // A grain settling at Re 1 after a long fall (d/l0 = 2, R = 1.7 d): the kernel's water moves with the disturbance
  // (Re_near 0.6), the far field passes at Re_R 1.65. The step response of the modes, each mode's time at its own
  // speed, against the unsteady Oseen build-up at Re_R (the continuum's, which the MPS water was measured to follow):
  // once the near modes are built (nu t / R^2 >= 1) within the mode fit's own bound, and at most phi(Re_R) for ever.
  const double near = 0.6, far = 1.65;
  const auto b = self_induced_two_speed_amplitudes(near, far);
  const double phi = self_induced_oseen_factor(far);
  CHECK(b[0] + b[1] + b[2] == doctest::Approx(phi).epsilon(0.01));
  for (double t : {1.0, 1.65, 3.0, 10.0, 100.0}) {
    CAPTURE(t);
    double response = 0.0;
    for (int m = 0; m < SelfInducedModes::kCount; ++m)
      response += b[static_cast<std::size_t>(m)] *
                  (1.0 - std::exp(-t / self_induced_mode_time(m, m + 1 == SelfInducedModes::kCount ? far : near)));
    CHECK(std::abs(response - self_induced_oseen_buildup(t, far)) < 0.045);
    CHECK(response <= phi * (1.0 + 1e-9));
  }
  // Where the near modes alone hold more than the far field's phi (high Re), the slow mode carries nothing.
  const auto fast = self_induced_two_speed_amplitudes(12.7, 17.0);
  CHECK(fast[2] == 0.0);
}

TEST_CASE("the modes' amplitudes sum to the Oseen factor and follow the unsteady build-up at every Re_R") {
  const auto stokes = self_induced_mode_amplitudes(0.0);
  for (int m = 0; m < SelfInducedModes::kCount; ++m)
    CHECK(stokes[static_cast<std::size_t>(m)] == doctest::Approx(SelfInducedModes::amplitude[static_cast<std::size_t>(m)]).epsilon(0.05));
  for (double re = 1e-3; re < 3e4; re *= 1.9) {
    CAPTURE(re);
    const auto b = self_induced_mode_amplitudes(re);
    const double phi = self_induced_oseen_factor(re);
    CHECK(b[0] + b[1] + b[2] == doctest::Approx(phi).epsilon(0.01));
    for (double amplitude : b) CHECK(amplitude >= 0.0);
    // The fit's worst departure over T = 1e-3 to 100: within 0.04 of the Stokes disturbance (the Stokes fit's own
    // bound, the 1/sqrt(T) tail three exponentials do not follow) and within a quarter of phi.
    if (re > 1e3) continue;  // beyond, phi < 1 %: the build-up is over within a mode's time
    double worst = 0.0;
    for (double t = 1e-3; t <= 100.0; t *= 1.4) {
      double fit = 0.0;
      for (int m = 0; m < SelfInducedModes::kCount; ++m)
        fit += b[static_cast<std::size_t>(m)] * (1.0 - std::exp(-t / self_induced_mode_time(m, re)));
      worst = std::max(worst, std::abs(fit - self_induced_oseen_buildup(t, re)));
    }
    CHECK(worst < 0.045);
    CHECK(worst < 0.25 * phi);
  }
}

TEST_CASE("the drag and its disturbance solve to the fixed point along the slip") {
  // gain(x) = 0.4 (1 + 0.15 x^0.687): x (1 - gain) = rhs; check the residual and a constant-gain closed form.
  const auto gain = [](double x) { return 0.4 * (1.0 + 0.15 * std::pow(x, 0.687)) / (1.0 + 0.3 * x); };
  for (double rhs : {1e-6, 0.01, 0.3, 1.0, 5.0}) {
    const double x = solve_self_induced_slip(rhs, gain);
    CHECK(x * (1.0 - gain(x)) == doctest::Approx(rhs).epsilon(1e-10));
  }
  CHECK(solve_self_induced_slip(2.0, [](double) { return 0.5; }) == doctest::Approx(4.0).epsilon(1e-12));
  CHECK(solve_self_induced_slip(0.0, [](double) { return 0.5; }) == 0.0);
  // A gain past 1 (no physical grain) is clipped at 0.95: finite, 20 times the right-hand side.
  CHECK(solve_self_induced_slip(1.0, [](double) { return 3.0; }) == doctest::Approx(20.0).epsilon(1e-9));
}

TEST_CASE("next to a no-slip plane the regularised disturbance tends to Lorentz's reflection and falls towards it") {
  // Far from the plane the image system at the grain is Lorentz's (1907) reflection: the mobilities of a sphere
  // 1 - 9a/(8h) along the normal and 1 - 9a/(16h) along the plane, with the blob's 4/3 <1/r> R in place of 1/a.
  const double free = 4.0 / 3.0 * self_induced_inverse_distance();
  for (double h : {3.0, 5.0, 8.0, 20.0}) {
    const SelfInducedWallFactors f = self_induced_wall_factors(h);
    // The blob's finite size adds O((R/h)^3) (the reflection's next term is (a/h)^3 / 2 along the normal).
    CHECK(1.0 - f.normal == doctest::Approx(1.5 / (h * free)).epsilon(0.03 + 0.5 / (h * h)));
    CHECK(1.0 - f.tangential == doctest::Approx(0.75 / (h * free)).epsilon(0.03 + 0.5 / (h * h)));
  }
  // The wall holds the water: the disturbance along the normal is smaller than along the plane, both fall as the
  // grain nears the plane and stay positive.
  double last_normal = 1.0, last_tangential = 1.0;
  for (double h = 8.0; h > 0.06; h *= 0.8) {
    const SelfInducedWallFactors f = self_induced_wall_factors(h);
    CHECK(f.normal < f.tangential);
    CHECK(f.normal <= last_normal + 0.01);
    CHECK(f.tangential <= last_tangential + 0.01);
    CHECK(f.normal > 0.0);
    last_normal = f.normal;
    last_tangential = f.tangential;
  }
  CHECK(self_induced_wall_factors(1e9).normal == doctest::Approx(1.0).epsilon(1e-6));
}

namespace {

/// A point of the Wendland kernel on R = 1 at height h by rejection from its radial density q^2 w(q) (below 0.06),
/// pseudo-random numbers named by (sample, lane).
Vec3 rejected_kernel_point(std::uint64_t sample, std::uint32_t& lane, double h) {
  for (;;) {
    const double q = counter_uniform(7, sample, 0, lane++);
    const double m = 1.0 - q;
    if (0.06 * counter_uniform(7, sample, 0, lane++) > q * q * m * m * m * m * (1.0 + 4.0 * q)) continue;
    const double cosine = 2.0 * counter_uniform(7, sample, 0, lane++) - 1.0;
    const double angle = 2.0 * 3.14159265358979323846 * counter_uniform(7, sample, 0, lane++);
    const double sine = std::sqrt(1.0 - cosine * cosine);
    return {q * sine * std::cos(angle), q * sine * std::sin(angle), h + q * cosine};
  }
}

/// 8 pi mu times the velocity along the normal at x for a unit normal force at y above the no-slip plane z = 0:
/// Blake's (1971) Green's function written out for its zz component, R = x - y* with y* = y mirrored, h = y_z:
/// G_zz = 1/r + r_z^2/r^3 - 1/R - R_z^2/R^3 - 2 h (h (1/R^3 - 3 R_z^2/R^5) - R_z/R^3 + 3 R_z^3/R^5).
double blake_normal(const Vec3& x, const Vec3& y) {
  const Vec3 r = x - y;
  const Vec3 big(x.x() - y.x(), x.y() - y.y(), x.z() + y.z());
  const double h = y.z(), m = r.norm(), n = big.norm();
  const double rz = big.z();
  return 1.0 / m + r.z() * r.z() / (m * m * m) - 1.0 / n - rz * rz / (n * n * n) -
         2.0 * h * (h * (1.0 / (n * n * n) - 3.0 * rz * rz / std::pow(n, 5)) - rz / (n * n * n) +
                    3.0 * rz * rz * rz / std::pow(n, 5));
}

}  // namespace

TEST_CASE("Blake's image system stops the water on the plane, and the table agrees with a pseudo-random estimate") {
  // No slip: the normal velocity of a normal force vanishes on z = 0, wherever the force is.
  for (const Vec3& y : {Vec3(0.0, 0.0, 1.0), Vec3(0.3, -0.2, 0.4)})
    for (const Vec3& x : {Vec3(1.0, 0.5, 0.0), Vec3(-2.0, 1.0, 0.0), Vec3(0.1, 0.0, 0.0)})
      CHECK(std::abs(blake_normal(x, y)) < 1e-12);
  // The table's normal factor against plain Monte Carlo over pairs of kernel points (the standard error from the
  // samples; the table's own quadrature is Halton's, through the kernel's inverse cumulative).
  const double free = 4.0 / 3.0 * self_induced_inverse_distance();
  for (double h : {0.5, 1.5}) {
    double sum = 0.0, squares = 0.0;
    int count = 0;
    for (std::uint64_t k = 0; k < 100000; ++k) {
      std::uint32_t lane = 0;
      const Vec3 x = rejected_kernel_point(2 * k, lane, h);
      const Vec3 y = rejected_kernel_point(2 * k + 1, lane, h);
      if (x.z() <= 0.0 || y.z() <= 0.0) continue;
      const double g = blake_normal(x, y) / free;
      sum += g;
      squares += g * g;
      ++count;
    }
    const double mean = sum / count;
    const double error = std::sqrt((squares / count - mean * mean) / count);
    CHECK(std::abs(self_induced_wall_factors(h).normal - mean) < 4.0 * error + 0.01);
  }
}

TEST_CASE("a settling suspension's share of the own disturbance is the hard-sphere structure factor S(0)") {
  // A lone grain keeps all of it, exactly (the settling cases run bit for bit as before).
  CHECK(self_induced_suspension_share(0.0) == 1.0);
  CHECK(self_induced_suspension_share(-0.1) == 1.0);
  // First order: the neighbours a grain excludes, none within a diameter, 8 phi of the own term (Batchelor 1972).
  for (double phi : {1e-4, 1e-3}) CHECK((1.0 - self_induced_suspension_share(phi)) / phi == doctest::Approx(8.0).epsilon(0.05));
  // Second order: the virial expansion of the hard-sphere structure factor, S(0) = 1 - 8 phi + 34 phi^2 + O(phi^3)
  // (Carnahan & Starling's compressibility, and Percus-Yevick's, agree to this order).
  const double small = 1e-3;
  CHECK((self_induced_suspension_share(small) - 1.0 + 8.0 * small) / (small * small) == doctest::Approx(34.0).epsilon(0.05));
  // Against Percus-Yevick's (1 - phi)^4 / (1 + 2 phi)^2, an independent theory, within 2 % where the correction acts
  // (eps > 0.8; the two part by 4 % at phi = 0.3).
  for (double phi : {0.05, 0.1, 0.2}) {
    CAPTURE(phi);
    const double percus_yevick = std::pow(1.0 - phi, 4) / std::pow(1.0 + 2.0 * phi, 2);
    CHECK(self_induced_suspension_share(phi) == doctest::Approx(percus_yevick).epsilon(0.02));
  }
  // Falls as the suspension thickens, and stays positive where the correction acts (eps > 0.8) and beyond.
  double previous = 1.0;
  for (double phi = 0.01; phi < 0.74; phi += 0.01) {
    const double share = self_induced_suspension_share(phi);
    CHECK(share < previous);
    CHECK(share > 0.0);
    previous = share;
  }
}

TEST_CASE("the Brinkman screening is the kernels' mean of exp(-r / l_B) / r over their mean of 1 / r") {
  // The screened symbol 1 / (k^2 + l_B^-2) is the Yukawa potential exp(-r / l_B) / (4 pi r) in real space: pairs of
  // kernel points by plain Monte Carlo (an independent route to the Fourier-space table).
  CHECK(self_induced_brinkman_factor(0.0) == 1.0);
  CHECK(self_induced_brinkman_factor(1e-3) == doctest::Approx(1.0).epsilon(2e-3));
  for (double beta : {0.5, 2.0, 5.0}) {
    double screened = 0.0, plain = 0.0;
    for (std::uint64_t k = 0; k < 200000; ++k) {
      std::uint32_t lane = 0;
      const Vec3 x = rejected_kernel_point(2 * k, lane, 10.0);
      const Vec3 y = rejected_kernel_point(2 * k + 1, lane, 10.0);
      const double r = (x - y).norm();
      screened += std::exp(-beta * r) / r;
      plain += 1.0 / r;
    }
    CAPTURE(beta);
    CHECK(self_induced_brinkman_factor(beta) == doctest::Approx(screened / plain).epsilon(0.02));
  }
  CHECK(self_induced_brinkman_factor(2.0) < self_induced_brinkman_factor(0.5));
}
