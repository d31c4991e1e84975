#include "systems/physics/coupling/self_induced.hpp"

#include <cmath>
#include <vector>

namespace riffle {

namespace {

constexpr double kPi = 3.14159265358979323846;

/// The normalised Wendland kernel's radial Fourier transform W(kappa), kappa = k R, squared, on a uniform grid
/// (Simpson in q = r / R), with its integral and the Oseen table built from it.
struct KernelTransform {
  static constexpr double kStep = 0.05;    // in kappa
  static constexpr int kPoints = 2401;     // kappa up to 120: W^2 has fallen below 1e-13 of its peak there
  static constexpr double kLogLow = -3.0;  // Oseen table: log10 Re_R from -3 to 4, 20 per decade
  static constexpr double kLogHigh = 4.0;
  static constexpr int kTable = 141;
  std::vector<double> squared;  ///< W(kappa)^2
  double integral = 0.0;        ///< int_0^inf W^2 d kappa
  std::vector<double> oseen;    ///< phi at the table's Re_R

  KernelTransform() {
    constexpr int kIntervals = 1000;  // Simpson in q
    const auto weight = [](double q) {
      const double m = 1.0 - q;
      return m * m * m * m * (1.0 + 4.0 * q);
    };
    const double norm = 2.0 * kPi / 21.0;  // int w dV for R = 1 (numerics 1.2)
    squared.resize(kPoints);
    for (int i = 0; i < kPoints; ++i) {
      const double kappa = i * kStep;
      double sum = 0.0;
      for (int j = 0; j <= kIntervals; ++j) {
        const double q = static_cast<double>(j) / kIntervals;
        const double sinc = kappa * q > 1e-8 ? std::sin(kappa * q) / (kappa * q) : 1.0;
        const double simpson = (j == 0 || j == kIntervals) ? 1.0 : (j % 2 == 1 ? 4.0 : 2.0);
        sum += simpson * weight(q) * sinc * q * q;
      }
      const double transform = 4.0 * kPi * sum / (3.0 * kIntervals) / norm;
      squared[static_cast<std::size_t>(i)] = transform * transform;
    }
    integral = integrate([](double) { return 1.0; });
    oseen.resize(kTable);
    for (int n = 0; n < kTable; ++n) {
      const double reynolds = std::pow(10.0, kLogLow + (kLogHigh - kLogLow) * n / (kTable - 1));
      oseen[static_cast<std::size_t>(n)] =
          integrate([&](double kappa) { return oseen_angular(kappa > 0.0 ? reynolds / kappa : 1e300); }) /
          (4.0 / 3.0 * integral);
    }
  }

  /// int_0^inf W^2 f(kappa) d kappa (Simpson; the grid has an odd number of points).
  template <class F>
  double integrate(F&& f) const {
    double sum = 0.0;
    for (int i = 0; i < kPoints; ++i) {
      const double simpson = (i == 0 || i == kPoints - 1) ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0);
      sum += simpson * squared[static_cast<std::size_t>(i)] * f(i * kStep);
    }
    return sum * kStep / 3.0;
  }

  /// int_{-1}^{1} (1 - c^2) / (1 + b^2 c^2) dc, b = Re_R / kappa: the projector's component along the slip over
  /// the Oseen symbol's real part, mu k^2 / (mu^2 k^4 + rho^2 (v.k)^2) = 1 / (mu k^2 (1 + b^2 c^2)).
  static double oseen_angular(double b) {
    if (b < 1e-3) return 4.0 / 3.0 - 4.0 / 15.0 * b * b;
    if (b > 1e6) return kPi / b;  // the c-integral of 1 / (1 + b^2 c^2)
    return -2.0 / (b * b) + 2.0 * (1.0 + b * b) * std::atan(b) / (b * b * b);
  }
};

const KernelTransform& kernel_transform() {
  static const KernelTransform transform;
  return transform;
}

}  // namespace

double self_induced_inverse_distance() {
  // <1/r> = int rho_w(x) rho_s(y) / |x - y| = 4 pi int W^2 / k^2 d^3k / (2 pi)^3 = (2 / pi) int W^2 dk.
  return 2.0 / kPi * kernel_transform().integral;
}

double self_induced_overlap() {
  // int w^2 dV / (int w dV)^2 for R = 1, by Simpson in q.
  constexpr int kIntervals = 2000;
  double sum = 0.0;
  for (int j = 0; j <= kIntervals; ++j) {
    const double q = static_cast<double>(j) / kIntervals;
    const double m = 1.0 - q;
    const double w = m * m * m * m * (1.0 + 4.0 * q);
    const double simpson = (j == 0 || j == kIntervals) ? 1.0 : (j % 2 == 1 ? 4.0 : 2.0);
    sum += simpson * w * w * q * q;
  }
  const double norm = 2.0 * kPi / 21.0;
  return 4.0 * kPi * sum / (3.0 * kIntervals) / (norm * norm);
}

double self_induced_oseen_factor(double reynolds_r) {
  const KernelTransform& table = kernel_transform();
  if (!(reynolds_r > 0.0)) return 1.0;
  const double position = (std::log10(reynolds_r) - KernelTransform::kLogLow) /
                          (KernelTransform::kLogHigh - KernelTransform::kLogLow) * (KernelTransform::kTable - 1);
  if (position <= 0.0) {  // below the table: phi = 1 - O(Re_R), linear to the first entry
    return 1.0 - (1.0 - table.oseen.front()) * reynolds_r / std::pow(10.0, KernelTransform::kLogLow);
  }
  if (position >= KernelTransform::kTable - 1)  // above: phi ~ 1 / Re_R
    return table.oseen.back() * std::pow(10.0, KernelTransform::kLogHigh) / reynolds_r;
  const auto n = static_cast<std::size_t>(position);
  const double t = position - static_cast<double>(n);
  return (1.0 - t) * table.oseen[n] + t * table.oseen[n + 1];
}

double self_induced_buildup(double time) {
  const KernelTransform& table = kernel_transform();
  return table.integrate([&](double kappa) { return 1.0 - std::exp(-kappa * kappa * time); }) / table.integral;
}

}  // namespace riffle
