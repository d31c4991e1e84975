#include "systems/physics/measures/probe_measures.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "systems/physics/math/not_a_number.hpp"
#include "systems/physics/mps/hydrostatic.hpp"
#include "systems/physics/mps/mps_common.hpp"
#include "systems/physics/mps/mps_kernel.hpp"
#include "systems/physics/measures/pressure_sensor.hpp"

namespace riffle {

std::vector<Vec3> wall_reaction_forces(const Contacts& contacts, std::size_t wall_count) {
  if (!contacts.valid || contacts.wall_pair_force.size() != contacts.wall_pair_wall.size()) return {};
  std::vector<Vec3> forces(wall_count, Vec3::Zero());
  for (std::size_t k = 0; k < contacts.wall_pair_wall.size(); ++k)
    if (contacts.wall_pair_wall[k] < wall_count) forces[contacts.wall_pair_wall[k]] -= contacts.wall_pair_force[k];
  return forces;
}

FluidProbeSettings fluid_probe_settings(const Model& model) {
  FluidProbeSettings settings;
  const MpsConstants& constants = mps_constants(model.fluid);
  settings.spacing = constants.spacing;
  settings.effective_radius = constants.effective_radius;
  settings.density = model.fluid.density;
  settings.gravity = model.gravity;
  settings.reference_number_density = constants.reference_density;
  settings.floor_height = model.tank.origin.z();
  settings.allow_tension = !model.fluid.clamp_negative_pressure;
  for (int axis = 0; axis < 3; ++axis)
    if (model.tank.periodic[static_cast<std::size_t>(axis)]) settings.period[axis] = model.tank.size[axis];
  return settings;
}

namespace {

/// The sums a pressure sensor at a lab position needs over the MPS particles within r_e of it.
struct SensorSums {
  double weighted_pressure = 0.0;  ///< [Pa] sum over fluid j of w_j (p_j + grad p . (x_s - x_j))
  double fluid_weight = 0.0;       ///< [1] sum over fluid j of w_j
  double solid_weight = 0.0;       ///< [1] sum over wall and dummy j of w_j
};

/// `offset` (a difference of two positions) with its nearest image along the axes with a period (> 0); unchanged
/// along the others, and unchanged entirely in a tank without periodic axes.
Vec3 nearest_image(Vec3 offset, const Vec3& period) {
  for (int axis = 0; axis < 3; ++axis)
    if (period[axis] > 0.0) offset[axis] -= period[axis] * std::round(offset[axis] / period[axis]);
  return offset;
}

/// Adds particle j's share to the sums of a sensor at `sensor` (j's nearest image along a periodic axis).
void add_to_sensor(SensorSums& sums, const FluidParticles& particles, std::size_t j, const Vec3& sensor,
                   const WendlandKernel& kernel, const Vec3& gradient, const Vec3& period) {
  const Vec3 offset = nearest_image(sensor - particles.position[j], period);
  const double distance_squared = offset.squaredNorm();
  if (distance_squared >= kernel.effective_radius * kernel.effective_radius) return;
  const double weight = kernel.weight(std::sqrt(distance_squared));
  if (particles.kind[j] == static_cast<std::int32_t>(FluidKind::kFluid)) {
    sums.weighted_pressure += weight * hydrostatic_extrapolation(particles.pressure[j], gradient, offset);
    sums.fluid_weight += weight;
  } else {
    sums.solid_weight += weight;
  }
}

/// [Pa] The sensor's reading from its sums; `dry` (no fluid within r_e) is returned as is.
double sensor_reading(const SensorSums& sums, const FluidProbeSettings& settings, double dry) {
  if (!(sums.fluid_weight > 0.0)) return dry;
  const double full = full_support_density(settings.spacing, settings.effective_radius);
  return sensor_pressure(sums.weighted_pressure, sums.fluid_weight,
                         wetted_fraction(sums.fluid_weight, sums.solid_weight, full), settings.allow_tension);
}

/// Two unit vectors spanning the plane normal to the unit vector `normal`.
std::pair<Vec3, Vec3> tangents(const Vec3& normal) {
  Eigen::Index least = 0;
  normal.cwiseAbs().minCoeff(&least);
  const Vec3 first = normal.cross(Vec3::Unit(least)).normalized();
  return {first, normal.cross(first)};
}

}  // namespace

double fluid_pressure_at(const FluidParticles& particles, const FluidProbeSettings& settings, const TankMotion& tank,
                         const Vec3& point) {
  const Vec3 sensor = point + tank.displacement;
  // In the tank's frame a fluid at rest has grad p = rho (g - a_tank); carrying each p_j along it to the sensor
  // makes the average exact for a hydrostatic field, and is what lets a sensor outside the fluid (on a wall) read.
  const Vec3 gradient = hydrostatic_gradient(settings.density, settings.gravity, tank.acceleration);
  const WendlandKernel kernel{settings.effective_radius};
  SensorSums sums;
  for (std::size_t j = 0; j < particles.size(); ++j)
    add_to_sensor(sums, particles, j, sensor, kernel, gradient, settings.period);
  return sensor_reading(sums, settings, kNaN);
}

double pressure_transducer_reading(const FluidParticles& particles, const FluidProbeSettings& settings,
                                   const TankMotion& tank, const Vec3& point, const Vec3& normal, double diameter) {
  const double radius = 0.5 * diameter;
  const Vec3 centre = point + tank.displacement;
  const Vec3 gradient = hydrostatic_gradient(settings.density, settings.gravity, tank.acceleration);
  const WendlandKernel kernel{settings.effective_radius};
  // One pass over all particles picks those that can reach any point of the disc; each quadrature point then scans
  // only these: O(N + Q M) instead of O(Q N).
  const double reach = radius + settings.effective_radius;
  std::vector<std::size_t> near;
  for (std::size_t j = 0; j < particles.size(); ++j)
    if (nearest_image(particles.position[j] - centre, settings.period).squaredNorm() < reach * reach) near.push_back(j);
  const auto [along, across] = tangents(normal);
  const double spacing = 0.25 * std::min(settings.spacing, radius);
  double reading = 0.0;
  for (const DiscQuadraturePoint& q : disc_quadrature(radius, spacing, 16)) {
    const Vec3 sensor = centre + q.u * along + q.v * across;
    SensorSums sums;
    for (std::size_t j : near) add_to_sensor(sums, particles, j, sensor, kernel, gradient, settings.period);
    reading += q.weight * sensor_reading(sums, settings, 0.0);  // no water near: dry area, 0
  }
  return reading;
}

void WindowMean::add(double time, std::vector<double> values) {
  const double start = readings_.empty() ? time : readings_.back().time;
  readings_.push_back({start, time, std::move(values)});
  while (readings_.size() > 1 && readings_.front().time <= time - window_) readings_.pop_front();
}

std::vector<double> WindowMean::mean() const {
  if (readings_.empty()) return {};
  const double begin = readings_.back().time - window_;
  std::vector<double> sum(readings_.back().values.size(), 0.0);
  double covered = 0.0;
  for (const Reading& reading : readings_) {
    const double overlap = reading.time - std::max(reading.start, begin);
    if (!(overlap > 0.0)) continue;
    for (std::size_t k = 0; k < sum.size(); ++k) sum[k] += overlap * reading.values[k];
    covered += overlap;
  }
  if (!(covered > 0.0)) return readings_.back().values;  // a lone reading (a fresh run's t = 0): itself
  for (double& value : sum) value /= covered;
  return sum;
}

double WindowMean::latest_time() const { return readings_.empty() ? kNaN : readings_.back().time; }

namespace {
/// n of particle `slot` at the current positions: sum of w(r) over every other MPS particle (fluid, wall, dummy)
/// within r_e, as the fluid systems define it.
double number_density_at(const FluidParticles& particles, const WendlandKernel& kernel, std::size_t slot,
                         const Vec3& period) {
  const double radius_squared = kernel.effective_radius * kernel.effective_radius;
  double density = 0.0;
  for (std::size_t j = 0; j < particles.size(); ++j) {
    const double distance_squared =
        nearest_image(particles.position[j] - particles.position[slot], period).squaredNorm();
    if (j != slot && distance_squared < radius_squared) density += kernel.weight(std::sqrt(distance_squared));
  }
  return density;
}
}  // namespace

double wave_gauge_height(const FluidParticles& particles, const FluidProbeSettings& settings, const TankMotion& tank,
                         const Vec3& point, double radius) {
  const Vec3 gauge = point + tank.displacement;
  const double radius_squared = radius * radius;
  std::vector<std::pair<double, std::size_t>> column;  // (z, slot) of the fluid particles over the gauge
  for (std::size_t j = 0; j < particles.size(); ++j) {
    if (particles.kind[j] != static_cast<std::int32_t>(FluidKind::kFluid)) continue;
    const Vec3 offset = nearest_image(particles.position[j] - gauge, settings.period);  // across a periodic seam
    const double dx = offset.x();
    const double dy = offset.y();
    if (dx * dx + dy * dy < radius_squared) column.emplace_back(particles.position[j].z(), j);
  }
  std::sort(column.begin(), column.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first > b.first : a.second < b.second;
  });
  // The highest particle that is not isolated: n >= 0.5 n0 (a particle inside the water has n0, one on a flat
  // surface 0.7-0.8 n0, a drop of spray far less; spray must not make a spike). n is computed here at the current
  // positions, only for the few particles from the top down to the first that passes: the stored number_density
  // belongs to the predicted positions of the last step and is zero before the first one.
  const WendlandKernel kernel{settings.effective_radius};
  for (const auto& [z, j] : column)
    if (number_density_at(particles, kernel, j, settings.period) >= 0.5 * settings.reference_number_density)
      return z + 0.5 * settings.spacing - tank.displacement.z();  // a particle stands for a cube of side l0
  return kNaN;
}

double surge_front_position(const FluidParticles& particles, const FluidProbeSettings& settings,
                            const TankMotion& tank, const Vec3& direction, double below) {
  // Fluid particles sorted by their position along the direction, front first; the first particle low enough
  // that has a neighbour within 1.5 l0 is the front. A neighbour lies within 1.5 l0 along the direction too, so
  // the search scans only the window around it in the sorted order; lone drops are rare, so the walk stops after
  // a few particles and the sort, O(F log F), is the whole cost.
  std::vector<std::pair<double, std::size_t>> order;
  order.reserve(particles.size());
  for (std::size_t j = 0; j < particles.size(); ++j)
    if (particles.kind[j] == static_cast<std::int32_t>(FluidKind::kFluid))
      order.emplace_back(particles.position[j].dot(direction), j);
  std::sort(order.begin(), order.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first > b.first : a.second < b.second;
  });
  const double reach = 1.5 * settings.spacing;
  const double floor = settings.floor_height + tank.displacement.z();
  for (std::size_t a = 0; a < order.size(); ++a) {
    // Named variables, not a structured binding: clang before 16 cannot capture those in a lambda.
    const double along = order[a].first;
    const std::size_t j = order[a].second;
    if (!(particles.position[j].z() - floor < below)) continue;
    auto near = [&](std::size_t b) {
      return (particles.position[order[b].second] - particles.position[j]).squaredNorm() < reach * reach;
    };
    bool connected = false;
    for (std::size_t b = a; b-- > 0 && order[b].first - along < reach && !connected;) connected = near(b);
    for (std::size_t b = a + 1; b < order.size() && along - order[b].first < reach && !connected; ++b)
      connected = near(b);
    if (connected) return along + 0.5 * settings.spacing - tank.displacement.dot(direction);
  }
  return kNaN;
}

}  // namespace riffle
