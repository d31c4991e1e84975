#include "systems/physics/measures/pressure_sensor.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace riffle {

namespace {
}  // namespace

double full_support_density(double spacing, double effective_radius) {
  const double ratio = effective_radius / spacing;
  return 4.0 * std::numbers::pi * ratio * ratio * ratio / 42.0;
}

double wetted_fraction(double fluid_weight, double solid_weight, double full_weight) {
  const double room = full_weight - solid_weight;
  if (!(room > 0.0)) return 0.0;
  return std::clamp(fluid_weight / room, 0.0, 1.0);
}

double sensor_pressure(double weighted_pressure, double weight, double wet_fraction, bool allow_tension) {
  if (wet_fraction < kWetFractionThreshold) return 0.0;
  const double pressure = weighted_pressure / weight;
  return allow_tension ? pressure : std::max(pressure, 0.0);
}

std::vector<DiscQuadraturePoint> disc_quadrature(double radius, double spacing, int max_rings) {
  if (!(radius > 0.0)) return {{0.0, 0.0, 1.0}};  // a disc of no size is its centre
  const double ratio = spacing > 0.0 ? std::ceil(radius / spacing - 1e-9) : max_rings;
  const int rings = static_cast<int>(std::clamp(ratio, 1.0, static_cast<double>(std::max(max_rings, 1))));
  const double width = radius / rings;
  std::vector<DiscQuadraturePoint> points;
  for (int k = 0; k < rings; ++k) {
    const double inner = k * width, outer = (k + 1) * width;
    const double area_share = (outer * outer - inner * inner) / (radius * radius);
    // The area centroid radius of the annulus, 2/3 (r_o^3 - r_i^3) / (r_o^2 - r_i^2): the disc's first ring puts
    // its points at 2/3 of its radius.
    const double centroid =
        2.0 / 3.0 * (outer * outer * outer - inner * inner * inner) / (outer * outer - inner * inner);
    const int count = std::max(4, static_cast<int>(std::ceil(2.0 * std::numbers::pi * centroid / width - 1e-9)));
    // Every other ring turned by half a step, so no two rings' points line up along a radius.
    const double turn = (k % 2 == 0) ? 0.0 : 0.5;
    for (int m = 0; m < count; ++m) {
      const double angle = 2.0 * std::numbers::pi * (m + turn) / count;
      points.push_back({centroid * std::cos(angle), centroid * std::sin(angle), area_share / count});
    }
  }
  return points;
}

}  // namespace riffle
