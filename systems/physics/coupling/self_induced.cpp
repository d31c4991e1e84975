#include "systems/physics/coupling/self_induced.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <vector>

#include <Eigen/Dense>

#include "components/vec.hpp"

namespace riffle {

namespace {


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
  std::vector<double> brinkman; ///< the Brinkman screening at the table's R / l_B (same log grid, -3 to 4)

  KernelTransform() {
    constexpr int kIntervals = 1000;  // Simpson in q
    const auto weight = [](double q) {
      const double m = 1.0 - q;
      return m * m * m * m * (1.0 + 4.0 * q);
    };
    const double norm = 2.0 * std::numbers::pi / 21.0;  // int w dV for R = 1 (numerics 1.2)
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
      const double transform = 4.0 * std::numbers::pi * sum / (3.0 * kIntervals) / norm;
      squared[static_cast<std::size_t>(i)] = transform * transform;
    }
    integral = integrate([](double) { return 1.0; });
    // 1 - s = int W^2 b^2 / (kappa^2 + b^2) / int W^2, b = R / l_B: a peak of width b at kappa = 0, narrower than
    // the grid for small b, so W^2(0) = 1 is taken out and its part integrated exactly (b atan(kappa_max / b)).
    brinkman.resize(kTable);
    const double kappa_max = (kPoints - 1) * kStep;
    for (int n = 0; n < kTable; ++n) {
      const double b = std::pow(10.0, kLogLow + (kLogHigh - kLogLow) * n / (kTable - 1));
      std::size_t i = 0;
      double smooth = 0.0;
      for (int j = 0; j < kPoints; ++j, ++i) {
        const double simpson = (j == 0 || j == kPoints - 1) ? 1.0 : (j % 2 == 1 ? 4.0 : 2.0);
        const double kappa = j * kStep;
        smooth += simpson * (squared[i] - 1.0) * b * b / (kappa * kappa + b * b);
      }
      const double screened = smooth * kStep / 3.0 + b * std::atan(kappa_max / b);
      brinkman[static_cast<std::size_t>(n)] = std::max(0.0, 1.0 - screened / integral);
    }
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
    if (b > 1e6) return std::numbers::pi / b;  // the c-integral of 1 / (1 + b^2 c^2)
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
  return 2.0 / std::numbers::pi * kernel_transform().integral;
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
  const double norm = 2.0 * std::numbers::pi / 21.0;
  return 4.0 * std::numbers::pi * sum / (3.0 * kIntervals) / (norm * norm);
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

namespace {

/// The radical inverse of `index` in base `base` (Halton's sequence).
double radical_inverse(std::uint64_t index, std::uint64_t base) {
  double inverse = 1.0 / static_cast<double>(base), factor = inverse, value = 0.0;
  for (; index > 0; index /= base, factor *= inverse) value += static_cast<double>(index % base) * factor;
  return value;
}

/// q = r / R of the normalised Wendland kernel's radial distribution (density 4 pi q^2 w(q) / norm) at cumulative
/// probability `u`: the inverse of its cumulative, tabulated on a fine grid in q and interpolated.
double wendland_radius_at(double u) {
  static const std::vector<double> cumulative = [] {
    constexpr int kIntervals = 4096;
    std::vector<double> c(kIntervals + 1, 0.0);
    const auto density = [](double q) {
      const double m = 1.0 - q;
      return q * q * m * m * m * m * (1.0 + 4.0 * q);
    };
    for (int j = 1; j <= kIntervals; ++j) {  // Simpson on each interval (midpoint rule's error is visible)
      const double a = static_cast<double>(j - 1) / kIntervals, b = static_cast<double>(j) / kIntervals;
      c[static_cast<std::size_t>(j)] = c[static_cast<std::size_t>(j - 1)] +
                                       (b - a) / 6.0 * (density(a) + 4.0 * density(0.5 * (a + b)) + density(b));
    }
    for (double& value : c) value /= c.back();
    return c;
  }();
  const auto upper = std::upper_bound(cumulative.begin(), cumulative.end(), u);
  if (upper == cumulative.begin()) return 0.0;
  if (upper == cumulative.end()) return 1.0;
  const auto j = static_cast<std::size_t>(upper - cumulative.begin());
  const double t = (u - cumulative[j - 1]) / (cumulative[j] - cumulative[j - 1]);
  return (static_cast<double>(j - 1) + t) / static_cast<double>(cumulative.size() - 1);
}

/// A point of the kernel on R = 1 centred at height h, from three numbers in [0, 1).
Vec3 kernel_point(double u_radius, double u_cosine, double u_angle, double height) {
  const double q = wendland_radius_at(u_radius);
  const double cosine = 2.0 * u_cosine - 1.0;
  const double sine = std::sqrt(std::max(0.0, 1.0 - cosine * cosine));
  const double angle = 2.0 * std::numbers::pi * u_angle;
  return {q * sine * std::cos(angle), q * sine * std::sin(angle), height + q * cosine};
}

/// 8 pi mu G_ii (i = z along the normal, x along the plane) at x for a unit force at y, the no-slip plane z = 0:
/// the Stokeslet, less its mirror image, plus Blake's (1971) Stokes doublet and source dipole at the image point.
/// With `free` false only the image system.
std::array<double, 2> blake_diagonal(const Vec3& x, const Vec3& y, bool free) {
  const double h = y.z();
  const Vec3 r = x - y;
  const Vec3 image(x.x() - y.x(), x.y() - y.y(), x.z() + h);
  const double n = image.norm(), n3 = n * n * n, n5 = n3 * n * n;
  std::array<double, 2> g{};  // {zz, xx}
  if (free) {
    const double m = r.norm(), m3 = m * m * m;
    g[0] += 1.0 / m + r.z() * r.z() / m3;
    g[1] += 1.0 / m + r.x() * r.x() / m3;
  }
  g[0] -= 1.0 / n + image.z() * image.z() / n3;
  g[1] -= 1.0 / n + image.x() * image.x() / n3;
  // 2 h D_jj d/dR_j [h R_i / |R|^3 - delta_i3 / |R| - R_i R_3 / |R|^3], D = diag(1, 1, -1), at i = j.
  const auto derivative = [&](int i) {
    const double ri = image[i], r3 = image.z();
    const double di3 = i == 2 ? 1.0 : 0.0;
    return h * (1.0 / n3 - 3.0 * ri * ri / n5) + di3 * ri / n3 - (r3 + ri * di3) / n3 + 3.0 * ri * r3 * ri / n5;
  };
  g[0] += -2.0 * h * derivative(2);
  g[1] += 2.0 * h * derivative(0);
  return g;
}

/// The wall factors' table: log-spaced in h / R from kLow to kHigh.
struct WallFactorTable {
  static constexpr double kLow = 0.05, kHigh = 6.0;
  static constexpr int kPoints = 40;
  // Where the plane cuts the kernels the integrand has the free Stokeslet's 1/r: 8192 points leave about 1 %;
  // beyond, the image part alone is smooth and 2048 points give four digits.
  static constexpr int kSamplesCut = 8192, kSamplesWhole = 2048;
  std::array<SelfInducedWallFactors, kPoints> factors{};
  WallFactorTable() {
    for (int n = 0; n < kPoints; ++n) {
      const double height = height_at(n);
      factors[static_cast<std::size_t>(n)] =
          self_induced_wall_quadrature(height, height < 1.0 ? kSamplesCut : kSamplesWhole);
    }
  }
  static double height_at(int n) {
    return kLow * std::pow(kHigh / kLow, static_cast<double>(n) / (kPoints - 1));
  }
};

}  // namespace

SelfInducedWallFactors self_induced_wall_quadrature(double height_over_radius, int samples) {
  const double h = height_over_radius;
  // Far from the plane (h >= 1) neither kernel is cut, so the free part is the exact <S_ii> = 4/3 <1/r> and only
  // the smooth image part is integrated; nearer, both parts over the kernels' halves in the water.
  const double free = 4.0 / 3.0 * self_induced_inverse_distance();
  const bool cut = h < 1.0;
  std::array<double, 2> sum{};
  int kept = 0;
  for (int k = 1; k <= samples; ++k) {
    const auto index = static_cast<std::uint64_t>(k);
    const Vec3 x = kernel_point(radical_inverse(index, 2), radical_inverse(index, 3), radical_inverse(index, 5), h);
    const Vec3 y = kernel_point(radical_inverse(index, 7), radical_inverse(index, 11), radical_inverse(index, 13), h);
    if (x.z() <= 0.0 || y.z() <= 0.0 || (x - y).squaredNorm() == 0.0) continue;
    const std::array<double, 2> g = blake_diagonal(x, y, cut);
    sum[0] += g[0];
    sum[1] += g[1];
    ++kept;
  }
  if (kept == 0) return {};
  const double normal = sum[0] / kept + (cut ? 0.0 : free);
  const double tangential = sum[1] / kept + (cut ? 0.0 : free);
  return {normal / free, tangential / free};
}

SelfInducedWallFactors self_induced_wall_factors(double height_over_radius) {
  static const WallFactorTable table;
  using T = WallFactorTable;
  if (!(height_over_radius > T::kLow)) return table.factors.front();
  if (height_over_radius >= T::kHigh) {  // the reflection's tail: 1 - f falls as 1 / h
    const SelfInducedWallFactors& end = table.factors.back();
    const double ratio = T::kHigh / height_over_radius;
    return {1.0 - (1.0 - end.normal) * ratio, 1.0 - (1.0 - end.tangential) * ratio};
  }
  const double position = std::log(height_over_radius / T::kLow) / std::log(T::kHigh / T::kLow) * (T::kPoints - 1);
  const auto n = std::min(static_cast<std::size_t>(position), static_cast<std::size_t>(T::kPoints - 2));
  const double t = position - static_cast<double>(n);
  const SelfInducedWallFactors& a = table.factors[n];
  const SelfInducedWallFactors& b = table.factors[n + 1];
  return {(1.0 - t) * a.normal + t * b.normal, (1.0 - t) * a.tangential + t * b.tangential};
}

double self_induced_suspension_share(double solid_fraction) {
  if (!(solid_fraction > 0.0)) return 1.0;
  const double p = std::min(solid_fraction, 0.74);
  const double q = 1.0 - p;
  const double p2 = p * p;
  return (q * q) * (q * q) / (1.0 + 4.0 * p + 4.0 * p2 - 4.0 * p2 * p + p2 * p2);
}

double self_induced_brinkman_factor(double kernel_over_screening) {
  const KernelTransform& table = kernel_transform();
  if (!(kernel_over_screening > 0.0)) return 1.0;
  const double position = (std::log10(kernel_over_screening) - KernelTransform::kLogLow) /
                          (KernelTransform::kLogHigh - KernelTransform::kLogLow) * (KernelTransform::kTable - 1);
  if (position <= 0.0) return table.brinkman.front();  // 1 - O(R / l_B): within 1e-3 of 1 there
  if (position >= KernelTransform::kTable - 1) return 0.0;
  const auto n = static_cast<std::size_t>(position);
  const double t = position - static_cast<double>(n);
  return (1.0 - t) * table.brinkman[n] + t * table.brinkman[n + 1];
}

double self_induced_buildup(double time) {
  const KernelTransform& table = kernel_transform();
  return table.integrate([&](double kappa) { return 1.0 - std::exp(-kappa * kappa * time); }) / table.integral;
}

namespace {

/// (sin b - b cos b) / b^3, its series below b = 0.1 (the next term, b^6 / 45360, is below 1e-10 there).
double oseen_direction_average(double b) {
  if (b < 0.1) {
    const double b2 = b * b;
    return 1.0 / 3.0 - b2 / 30.0 + b2 * b2 / 840.0;
  }
  return (std::sin(b) - b * std::cos(b)) / (b * b * b);
}

/// d psi / dT at (T, Re_R): the trapezoidal rule over the kernel's transform up to kappa = 40 (W^2 < 4e-11 beyond)
/// and where exp(-kappa^2 T) > e^-50.
double oseen_buildup_rate(double time, double reynolds_r) {
  const KernelTransform& table = kernel_transform();
  constexpr double kKappaMax = 40.0;
  const double kappa_cut = time > 0.0 ? std::min(kKappaMax, std::sqrt(50.0 / time)) : kKappaMax;
  const int last = static_cast<int>(kappa_cut / KernelTransform::kStep);
  double sum = 0.0;
  for (int i = 1; i <= last; ++i) {  // kappa = 0 contributes nothing (kappa^2)
    const double kappa = i * KernelTransform::kStep;
    const double term = table.squared[static_cast<std::size_t>(i)] * kappa * kappa * std::exp(-kappa * kappa * time) *
                        3.0 * oseen_direction_average(reynolds_r * kappa * time);
    sum += i == last ? 0.5 * term : term;
  }
  return sum * KernelTransform::kStep / table.integral;
}

/// psi(T_k, Re_R) on the grid T_0 = 0, T_k = 10^(-5 + (k - 1) / 20) up to 10^3: the rate integrated by the
/// trapezoidal rule.
struct OseenBuildupCurve {
  static constexpr int kPoints = 162;
  std::array<double, kPoints> time{};
  std::array<double, kPoints> value{};
  explicit OseenBuildupCurve(double reynolds_r) {
    double previous_rate = oseen_buildup_rate(0.0, reynolds_r);
    for (int k = 1; k < kPoints; ++k) {
      time[static_cast<std::size_t>(k)] = std::pow(10.0, -5.0 + (k - 1) / 20.0);
      const double rate = oseen_buildup_rate(time[static_cast<std::size_t>(k)], reynolds_r);
      value[static_cast<std::size_t>(k)] =
          value[static_cast<std::size_t>(k - 1)] +
          0.5 * (rate + previous_rate) * (time[static_cast<std::size_t>(k)] - time[static_cast<std::size_t>(k - 1)]);
      previous_rate = rate;
    }
  }
  double at(double t) const {
    if (!(t > 0.0)) return 0.0;
    if (t >= time.back()) return value.back();
    const auto upper = static_cast<std::size_t>(std::upper_bound(time.begin(), time.end(), t) - time.begin());
    const double f = (t - time[upper - 1]) / (time[upper] - time[upper - 1]);
    return (1.0 - f) * value[upper - 1] + f * value[upper];
  }
};

/// b >= 0 with sum b = phi minimising |A b - psi|^2 (A_km = 1 - exp(-T_k / T_m)): every support of the three modes
/// is tried, each an equality-constrained least-squares problem (its KKT system), the best feasible one kept.
std::array<double, SelfInducedModes::kCount> fit_mode_amplitudes(double reynolds_r) {
  constexpr int kModes = SelfInducedModes::kCount;
  const OseenBuildupCurve curve(reynolds_r);
  const double phi = self_induced_oseen_factor(reynolds_r);
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d projected = Eigen::Vector3d::Zero();
  double psi_squares = 0.0;
  for (int k = 1; k < OseenBuildupCurve::kPoints; ++k) {
    const double t = curve.time[static_cast<std::size_t>(k)];
    if (t < 1e-3 * (1.0 - 1e-12) || t > 1e2 * (1.0 + 1e-12)) continue;
    Eigen::Vector3d row;
    for (int m = 0; m < kModes; ++m) row[m] = 1.0 - std::exp(-t / self_induced_mode_time(m, reynolds_r));
    normal += row * row.transpose();
    projected += row * curve.value[static_cast<std::size_t>(k)];
    psi_squares += curve.value[static_cast<std::size_t>(k)] * curve.value[static_cast<std::size_t>(k)];
  }
  std::array<double, kModes> best{};
  double best_residual = std::numeric_limits<double>::infinity();
  for (int support = 1; support < (1 << kModes); ++support) {
    std::array<int, kModes> members{};
    int size = 0;
    for (int m = 0; m < kModes; ++m)
      if (support & (1 << m)) members[static_cast<std::size_t>(size++)] = m;
    Eigen::MatrixXd kkt = Eigen::MatrixXd::Zero(size + 1, size + 1);
    Eigen::VectorXd rhs(size + 1);
    for (int i = 0; i < size; ++i) {
      for (int j = 0; j < size; ++j) kkt(i, j) = normal(members[static_cast<std::size_t>(i)], members[static_cast<std::size_t>(j)]);
      kkt(i, size) = kkt(size, i) = 1.0;
      rhs[i] = projected[members[static_cast<std::size_t>(i)]];
    }
    rhs[size] = phi;
    const Eigen::VectorXd solution = kkt.fullPivLu().solve(rhs);
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    bool feasible = true;
    for (int i = 0; i < size; ++i) {
      b[members[static_cast<std::size_t>(i)]] = solution[i];
      feasible = feasible && solution[i] >= 0.0;
    }
    if (!feasible) continue;
    const double residual = b.dot(normal * b) - 2.0 * b.dot(projected) + psi_squares;
    if (residual < best_residual) {
      best_residual = residual;
      for (int m = 0; m < kModes; ++m) best[static_cast<std::size_t>(m)] = b[m];
    }
  }
  return best;
}

/// The amplitudes at Re_R = 0 and at log10 Re_R = -2 to 4, eight per decade.
struct ModeAmplitudeTable {
  static constexpr double kLogLow = -2.0;
  static constexpr double kLogHigh = 4.0;
  static constexpr int kLogPoints = 49;
  std::array<std::array<double, SelfInducedModes::kCount>, kLogPoints + 1> amplitudes{};
  ModeAmplitudeTable() {
    amplitudes[0] = fit_mode_amplitudes(0.0);
    for (int n = 0; n < kLogPoints; ++n)
      amplitudes[static_cast<std::size_t>(n + 1)] =
          fit_mode_amplitudes(std::pow(10.0, kLogLow + (kLogHigh - kLogLow) * n / (kLogPoints - 1)));
  }
};

}  // namespace

double self_induced_oseen_buildup(double time, double reynolds_r) {
  return OseenBuildupCurve(reynolds_r).at(time);
}

double stokeslet_point_buildup(double time) {
  if (time <= 0.0) return 0.0;
  return std::erfc(0.5 / std::sqrt(time));
}

namespace {
/// A Stokes build-up time T shortened by convection at Re: T / (1 + T Re), the same for the modes and the walls.
double oseen_shortened_time(double stokes_time, double reynolds) {
  return stokes_time / (1.0 + stokes_time * std::max(reynolds, 0.0));
}
}  // namespace

double self_induced_wall_time(double reynolds_r) {
  return oseen_shortened_time(kStokesletHalfRiseTime / std::numbers::ln2, reynolds_r);
}

double self_induced_mode_time(int mode, double reynolds_r) {
  return oseen_shortened_time(SelfInducedModes::time[static_cast<std::size_t>(mode)], reynolds_r);
}

std::array<double, SelfInducedModes::kCount> self_induced_mode_amplitudes(double reynolds_r) {
  static const ModeAmplitudeTable table;
  using Table = ModeAmplitudeTable;
  std::array<double, SelfInducedModes::kCount> result{};
  const auto blend = [&](std::size_t a, std::size_t b, double f) {
    for (std::size_t m = 0; m < result.size(); ++m)
      result[m] = (1.0 - f) * table.amplitudes[a][m] + f * table.amplitudes[b][m];
  };
  if (!(reynolds_r > 0.0)) return table.amplitudes[0];
  const double low = std::pow(10.0, Table::kLogLow);
  if (reynolds_r <= low) {
    blend(0, 1, reynolds_r / low);
    return result;
  }
  const double position =
      (std::log10(reynolds_r) - Table::kLogLow) / (Table::kLogHigh - Table::kLogLow) * (Table::kLogPoints - 1);
  if (position >= Table::kLogPoints - 1) {  // beyond: the last fit's shares of phi
    const double scale = self_induced_oseen_factor(reynolds_r) / self_induced_oseen_factor(std::pow(10.0, Table::kLogHigh));
    for (std::size_t m = 0; m < result.size(); ++m) result[m] = scale * table.amplitudes.back()[m];
    return result;
  }
  const auto n = static_cast<std::size_t>(position);
  blend(n + 1, n + 2, position - static_cast<double>(n));
  return result;
}

std::array<double, SelfInducedModes::kCount> self_induced_two_speed_amplitudes(double reynolds_near, double reynolds_r) {
  std::array<double, SelfInducedModes::kCount> amplitudes = self_induced_mode_amplitudes(reynolds_near);
  const std::array<double, SelfInducedModes::kCount> far = self_induced_mode_amplitudes(reynolds_r);
  const double far_total = far[0] + far[1] + far[2];
  amplitudes[2] = std::max(0.0, far_total - amplitudes[0] - amplitudes[1]);
  return amplitudes;
}

}  // namespace riffle
