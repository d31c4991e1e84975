#include "systems/physics/coupling/lubrication.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace riffle {

namespace {


/// (4/3) sinh(alpha) sum_n n (n + 1) / ((2n - 1)(2n + 3)) [ratio_n - 1], alpha = acosh(1 + h/a): Brenner's form
/// for both boundary conditions, which differ only in ratio_n.
template <class Ratio>
double brenner_series(double gap_over_radius, Ratio&& ratio) {
  const double alpha = std::acosh(1.0 + gap_over_radius);
  double sum = 0.0;
  // The terms fall off as exp(-2 n alpha): about 20 / alpha of them reach 1e-15 (1e5 at h/a = 1e-8).
  for (int n = 1; n < 1000000; ++n) {
    const double nn = static_cast<double>(n);
    const double term = nn * (nn + 1.0) / ((2.0 * nn - 1.0) * (2.0 * nn + 3.0)) * (ratio(nn, alpha) - 1.0);
    sum += term;
    if (n > 5 && std::abs(term) < 1e-15 * std::abs(sum)) break;
  }
  return 4.0 / 3.0 * std::sinh(alpha) * sum;
}

}  // namespace

double brenner_wall_resistance(double gap_over_radius) {
  return brenner_series(gap_over_radius, [](double n, double alpha) {
    const double k = 2.0 * n + 1.0;
    const double numerator = 2.0 * std::sinh(k * alpha) + k * std::sinh(2.0 * alpha);
    const double denominator = 4.0 * std::pow(std::sinh((n + 0.5) * alpha), 2) - k * k * std::pow(std::sinh(alpha), 2);
    return numerator / denominator;
  });
}

double brenner_free_surface_resistance(double gap_over_radius) {
  return brenner_series(gap_over_radius, [](double n, double alpha) {
    const double k = 2.0 * n + 1.0;
    const double numerator = 4.0 * std::pow(std::cosh((n + 0.5) * alpha), 2) + k * k * std::pow(std::sinh(alpha), 2);
    const double denominator = 2.0 * std::sinh(k * alpha) - k * std::sinh(2.0 * alpha);
    return numerator / denominator;
  });
}

double cox_brenner_wall_resistance(double gap_over_radius) {
  return 1.0 / gap_over_radius - 0.2 * std::log(gap_over_radius) + 0.9713;
}

double reflection_wall_resistance(double gap_over_radius) {
  const double s = 1.0 / (1.0 + gap_over_radius);
  const double s2 = s * s, s3 = s2 * s, s4 = s2 * s2, s5 = s4 * s, s11 = s5 * s5 * s, s12 = s11 * s;
  return 1.0 / (1.0 - 9.0 / 8.0 * s + 0.5 * s3 - 0.57 * s4 + 0.2 * s5 + 0.035 * s11 - 0.04 * s12);
}

double wall_resistance(double gap_over_radius) {
  return gap_over_radius < kWallFormSwitch ? cox_brenner_wall_resistance(gap_over_radius)
                                           : reflection_wall_resistance(gap_over_radius);
}

double faxen_wall_resistance_tangential(double gap_over_radius) {
  const double s = 1.0 / (1.0 + std::max(gap_over_radius, kFaxenSmallestGap));
  const double s3 = s * s * s, s4 = s3 * s, s5 = s4 * s;
  return 1.0 / (1.0 - 9.0 / 16.0 * s + 1.0 / 8.0 * s3 - 45.0 / 256.0 * s4 - 1.0 / 16.0 * s5);
}

double wall_lubrication_coefficient(double radius, double gap, double viscosity, double roughness, double cutoff) {
  if (!(gap < cutoff) || !(gap > 0.0)) return 0.0;
  const double film = std::max(gap, roughness);
  return 6.0 * std::numbers::pi * viscosity * radius * std::max(0.0, wall_resistance(film / radius) - 1.0);
}

double pair_lubrication_coefficient(double radius_1, double radius_2, double gap, double viscosity, double roughness,
                                    double cutoff) {
  if (!(gap < cutoff) || !(gap > 0.0)) return 0.0;
  const double film = std::max(gap, roughness);
  const double a = reduced_radius(radius_1, radius_2);
  const double b = radius_2 / radius_1;
  const double log_coefficient = (1.0 + 7.0 * b + b * b) / (5.0 * (1.0 + b) * (1.0 + b));
  return 6.0 * std::numbers::pi * viscosity * std::max(0.0, a * a / film + log_coefficient * a * std::log(a / film));
}

double swept_coefficient(double coefficient_at_gap, double singular, double gap, double approach_speed, double dt,
                         double roughness, double cutoff) {
  // Antiderivative of phi(x) = 1/max(x, h_r) for 0 < x < cut-off, 0 in contact and beyond: 0, then x/h_r, then
  // 1 + ln(x/h_r), then constant.
  const auto primitive = [&](double x) {
    if (x <= 0.0) return 0.0;
    if (x <= roughness) return x / roughness;
    return 1.0 + std::log(std::min(x, cutoff) / roughness);
  };
  const auto phi = [&](double x) { return x > 0.0 && x < cutoff ? 1.0 / std::max(x, roughness) : 0.0; };
  const double sweep = std::abs(approach_speed) * dt;
  // A sweep short against the film (the usual case in a bed): the mean of 1/h over it is 1/h within (s/h)^2/12
  // = 1e-5, so the two logarithms are skipped.
  if (sweep < 0.01 * std::max(gap, roughness) && gap - 0.5 * sweep > 0.0 && gap + 0.5 * sweep < cutoff)
    return coefficient_at_gap;
  const double mean = sweep > 0.0 ? (primitive(gap + 0.5 * sweep) - primitive(gap - 0.5 * sweep)) / sweep : phi(gap);
  return std::max(0.0, coefficient_at_gap + singular * (mean - phi(gap)));
}

}  // namespace riffle
