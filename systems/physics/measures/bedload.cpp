#include "systems/physics/measures/bedload.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace riffle {

double sphere_slab_volume(double radius, double centre, double low, double high) {
  const double a = std::clamp(low - centre, -radius, radius);
  const double b = std::clamp(high - centre, -radius, radius);
  if (!(b > a)) return 0.0;
  // The cross-section at s is pi (r^2 - s^2); its integral from a to b.
  const double r2 = radius * radius;
  return std::numbers::pi * (r2 * (b - a) - (b * b * b - a * a * a) / 3.0);
}

double covered_length(std::vector<std::pair<double, double>>& intervals, double period) {
  if (!(period > 0.0)) return 0.0;
  // Wrap each interval into [0, period): one starting before 0 or ending after the period is split in two.
  std::vector<std::pair<double, double>> wrapped;
  wrapped.reserve(intervals.size() + 4);
  for (const auto& interval : intervals) {
    const double length = interval.second - interval.first;
    if (!(length > 0.0)) continue;
    if (length >= period) return period;
    double start = std::fmod(interval.first, period);
    if (start < 0.0) start += period;
    const double end = start + length;
    if (end <= period) {
      wrapped.emplace_back(start, end);
    } else {
      wrapped.emplace_back(start, period);
      wrapped.emplace_back(0.0, end - period);
    }
  }
  std::sort(wrapped.begin(), wrapped.end());
  double covered = 0.0;
  double run_start = 0.0, run_end = -1.0;  // the current merged run; none yet
  bool open = false;
  for (const auto& interval : wrapped) {
    if (open && interval.first <= run_end) {
      run_end = std::max(run_end, interval.second);
      continue;
    }
    if (open) covered += run_end - run_start;
    run_start = interval.first;
    run_end = interval.second;
    open = true;
  }
  if (open) covered += run_end - run_start;
  intervals.swap(wrapped);
  return std::min(covered, period);
}

double shields_number(double tau, double grain_density, double fluid_density, double gravity, double diameter) {
  const double denominator = (grain_density - fluid_density) * std::abs(gravity) * diameter;
  return denominator > 0.0 ? tau / denominator : std::numeric_limits<double>::quiet_NaN();
}

namespace {
double nan() { return std::numeric_limits<double>::quiet_NaN(); }
bool positive(double value) { return value > 0.0; }  // false for NaN
}  // namespace

double dimensionless_grain_size(double diameter, double relative_density, double gravity, double viscosity) {
  if (!positive(diameter) || !positive(relative_density - 1.0) || !positive(std::abs(gravity)) || !positive(viscosity))
    return nan();
  return diameter * std::cbrt(std::abs(gravity) * (relative_density - 1.0) / (viscosity * viscosity));
}

double particle_reynolds_number(double diameter, double relative_density, double gravity, double viscosity) {
  if (!positive(diameter) || !positive(relative_density - 1.0) || !positive(std::abs(gravity)) || !positive(viscosity))
    return nan();
  return std::sqrt((relative_density - 1.0) * std::abs(gravity) * diameter) * diameter / viscosity;
}

double friction_reynolds_number(double shields, double particle_reynolds) {
  return std::sqrt(shields) * particle_reynolds;
}

double shields_threshold_soulsby_whitehouse(double grain_size) {
  if (!positive(grain_size)) return nan();
  return 0.30 / (1.0 + 1.2 * grain_size) + 0.055 * (1.0 - std::exp(-0.020 * grain_size));
}

double shields_threshold_brownlie(double particle_reynolds) {
  if (!positive(particle_reynolds)) return nan();
  const double y = std::pow(particle_reynolds, -0.6);
  return 0.22 * y + 0.06 * std::pow(10.0, -7.7 * y);
}

double bedload_meyer_peter_mueller(double shields) {
  const double excess = shields - 0.047;
  return excess > 0.0 ? 8.0 * excess * std::sqrt(excess) : 0.0;
}

double bedload_wong_parker(double shields) {
  const double excess = shields - 0.0495;
  return excess > 0.0 ? 3.97 * excess * std::sqrt(excess) : 0.0;
}

double bedload_volume_flux(double einstein_number, double diameter, double relative_density, double gravity) {
  return einstein_number * std::sqrt((relative_density - 1.0) * std::abs(gravity) * diameter * diameter * diameter);
}

double einstein_number(double flux, double diameter, double relative_density, double gravity) {
  const double scale = std::sqrt((relative_density - 1.0) * std::abs(gravity) * diameter * diameter * diameter);
  return positive(scale) ? flux / scale : nan();
}

}  // namespace riffle
