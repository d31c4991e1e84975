// The grain's self-induced disturbance (systems/physics/coupling/self_induced.hpp) against independent evaluations: <1/r>
// and <rho_s rho_w> of two Wendland kernels by direct quadrature in real space, the Oseen factor's limits (Stokes
// at Re_R -> 0, Oseen's far wake 1/Re_R decay), the mode fit of the build-up, and the drag/disturbance solve.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "systems/physics/coupling/self_induced.hpp"

using namespace riffle;

namespace {
constexpr double kPi = 3.14159265358979323846;
double wendland(double q) { return q < 1.0 ? std::pow(1.0 - q, 4) * (1.0 + 4.0 * q) : 0.0; }
}  // namespace

TEST_CASE("R <1/r> of two unit Wendland kernels by a real-space sum matches the Fourier-space value") {
  // <1/|x - y|> = int int rho(x) rho(y) / |x - y|: by the shell theorem, the potential of the kernel's radial
  // density at radius s is 4 pi [ (1/s) int_0^s rho r^2 dr + int_s^1 rho r dr ]; then average it over rho.
  const int n = 4000;
  const double norm = 2.0 * kPi / 21.0;  // int w dV on R = 1
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
    const double potential = 4.0 * kPi * (0.5 * (inner[i] + inner[i + 1]) / s + 0.5 * (outer[i] + outer[i + 1]));
    average += 4.0 * kPi * s * s * wendland(s) / norm * potential * h;
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
  const double norm = 2.0 * kPi / 21.0;
  CHECK(self_induced_overlap() == doctest::Approx(4.0 * kPi * sum / (norm * norm)).epsilon(1e-8));
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
