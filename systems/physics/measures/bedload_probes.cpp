#include "systems/physics/measures/bedload_probes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include "systems/physics/math/not_a_number.hpp"
#include "systems/physics/measures/bed_statistics.hpp"
#include "systems/physics/measures/bedload.hpp"
#include "systems/physics/mps/mps_common.hpp"
#include "systems/physics/mps/mps_kernel.hpp"

namespace riffle {

namespace {

double sphere_volume(double radius) { return 4.0 / 3.0 * std::numbers::pi * radius * radius * radius; }

/// `value` wrapped into [0, period).
double wrap(double value, double period) {
  double wrapped = std::fmod(value, period);
  if (wrapped < 0.0) wrapped += period;
  return wrapped < period ? wrapped : 0.0;
}

/// The index of `value` among `count` cells of `width` over [0, count width), wrapped.
std::size_t periodic_cell(double value, double width, std::size_t count) {
  const auto cell = static_cast<std::size_t>(std::floor(wrap(value, width * static_cast<double>(count)) / width));
  return std::min(cell, count - 1);
}
}  // namespace

TankFrame tank_frame(const Model& model, const TankMotion* motion) {
  TankFrame frame;
  frame.low = model.tank.origin;
  frame.size = model.tank.size;
  if (motion) {
    frame.displacement = motion->displacement;
    frame.velocity = motion->velocity;
  }
  return frame;
}

std::size_t GrainClasses::index_of(std::int32_t size_class) const {
  const auto found = std::lower_bound(classes.begin(), classes.end(), size_class);
  return found != classes.end() && *found == size_class ? static_cast<std::size_t>(found - classes.begin())
                                                        : classes.size();
}

GrainClasses grain_classes(const Solids& solids) {
  GrainClasses result;
  result.classes = size_classes(solids);
  const std::size_t n = result.classes.size();
  std::vector<double> diameter_sum(n, 0.0), mass(n, 0.0), volume(n, 0.0);
  std::vector<std::size_t> count(n, 0);
  for (std::size_t i = 0; i < solids.size(); ++i) {
    const std::size_t k = result.index_of(solids.size_class[i]);
    diameter_sum[k] += 2.0 * solids.radius[i];
    mass[k] += solids.mass[i];
    volume[k] += sphere_volume(solids.radius[i]);
    ++count[k];
  }
  for (std::size_t k = 0; k < n; ++k) {
    result.diameter.push_back(diameter_sum[k] / static_cast<double>(count[k]));
    result.density.push_back(mass[k] / volume[k]);
  }
  return result;
}

std::vector<double> moving_fractions(const Solids& solids, const GrainClasses& classes, const TankFrame& frame,
                                     double threshold) {
  const std::size_t n = classes.classes.size();
  std::vector<std::size_t> moving(n + 1, 0), total(n + 1, 0);
  for (std::size_t i = 0; i < solids.size(); ++i) {
    if (solids.fixed[i]) continue;  // a rough floor's grains are not the bed's: they never move
    // A class the probe did not know at its start counts in the total only (none come or go in a run).
    const std::size_t k = classes.index_of(solids.size_class[i]);
    const bool moves = (solids.velocity[i] - frame.velocity).norm() > threshold;
    if (k < n) {
      ++total[k];
      if (moves) ++moving[k];
    }
    ++total[n];
    if (moves) ++moving[n];
  }
  std::vector<double> fractions(n + 1);
  for (std::size_t k = 0; k <= n; ++k)
    fractions[k] = total[k] ? static_cast<double>(moving[k]) / static_cast<double>(total[k]) : kNaN;
  return fractions;
}

PackingDensity packing_density(const Solids& solids, const TankFrame& frame, const TopLayerSettings& settings) {
  PackingDensity result;
  const double length = frame.size.x(), width = frame.size.y();
  if (solids.size() == 0 || !(length > 0.0) || !(width > 0.0)) return result;
  const double largest = 2.0 * *std::max_element(solids.radius.begin(), solids.radius.end());
  const double smallest = 2.0 * *std::min_element(solids.radius.begin(), solids.radius.end());
  // Seed 003's layer: centres above 4.5 mm in a bed whose top centres reach 6 mm, 0.75 of its large diameter.
  const double depth = settings.depth > 0.0 ? settings.depth : 0.75 * largest;
  const double floor_z = frame.floor_z();
  // Horizontal tank-frame position of a grain, relative to the footprint's corner.
  auto plan = [&](std::size_t i) {
    return std::pair<double, double>(solids.position[i].x() - frame.displacement.x() - frame.low.x(),
                                     solids.position[i].y() - frame.displacement.y() - frame.low.y());
  };
  std::vector<std::size_t> resting;
  for (std::size_t i = 0; i < solids.size(); ++i)
    if (!((solids.velocity[i] - frame.velocity).norm() > settings.threshold)) resting.push_back(i);
  std::vector<std::size_t> layer;
  if (settings.bottom) {
    for (std::size_t i : resting)
      if (solids.position[i].z() - floor_z > *settings.bottom) layer.push_back(i);
  } else {
    // The local bed top: the highest resting centre in each column, columns about one largest diameter wide.
    const auto nx = static_cast<std::size_t>(std::clamp(std::floor(length / largest), 1.0, 4096.0));
    const auto ny = static_cast<std::size_t>(std::clamp(std::floor(width / largest), 1.0, 4096.0));
    const double cell_x = length / static_cast<double>(nx), cell_y = width / static_cast<double>(ny);
    std::vector<double> top(nx * ny, -std::numeric_limits<double>::infinity());
    std::vector<std::size_t> column(resting.size());
    for (std::size_t r = 0; r < resting.size(); ++r) {
      const auto [x, y] = plan(resting[r]);
      column[r] = periodic_cell(x, cell_x, nx) + nx * periodic_cell(y, cell_y, ny);
      top[column[r]] = std::max(top[column[r]], solids.position[resting[r]].z());
    }
    for (std::size_t r = 0; r < resting.size(); ++r)
      if (solids.position[resting[r]].z() > top[column[r]] - depth) layer.push_back(resting[r]);
  }
  result.grains = layer.size();
  // Rows 1/64 of the smallest diameter apart (at most 2^20): the midpoint rule over rows integrates a disc's chords
  // to 6e-4 of its area; each row's union of chords is exact.
  const auto rows = static_cast<std::size_t>(std::clamp(std::ceil(width / (smallest / 64.0)), 1.0, 1048576.0));
  const double row_spacing = width / static_cast<double>(rows);
  std::vector<std::vector<std::pair<double, double>>> chords(rows);
  for (std::size_t i : layer) {
    const double r = solids.radius[i];
    const auto [x, y] = plan(i);
    // Rows k whose centre line y_k = (k + 1/2) h lies within the disc, counted on the unwrapped line, then wrapped.
    const auto first = static_cast<std::int64_t>(std::ceil((y - r) / row_spacing - 0.5));
    const auto last = static_cast<std::int64_t>(std::floor((y + r) / row_spacing - 0.5));
    for (std::int64_t k = first; k <= last && k - first < static_cast<std::int64_t>(rows); ++k) {
      const double dy = (static_cast<double>(k) + 0.5) * row_spacing - y;
      const double half = std::sqrt(std::max(0.0, r * r - dy * dy));
      const auto row = static_cast<std::size_t>(((k % static_cast<std::int64_t>(rows)) + static_cast<std::int64_t>(rows)) %
                                                static_cast<std::int64_t>(rows));
      chords[row].emplace_back(x - half, x + half);
    }
  }
  double covered = 0.0;
  for (auto& row : chords) covered += covered_length(row, length);
  result.lambda = covered * row_spacing / (length * width);
  return result;
}

std::vector<double> bedload_flux(const Solids& solids, const GrainClasses& classes, const TankFrame& frame) {
  const std::size_t n = classes.classes.size();
  std::vector<double> flux(n + 1, 0.0);
  const double area = frame.area();
  if (!(area > 0.0)) return flux;
  for (std::size_t i = 0; i < solids.size(); ++i) {
    const double q = sphere_volume(solids.radius[i]) * (solids.velocity[i].x() - frame.velocity.x());
    const std::size_t k = classes.index_of(solids.size_class[i]);
    if (k < n) flux[k] += q;
    flux[n] += q;
  }
  for (double& value : flux) value /= area;
  return flux;
}

std::vector<ProfileLayer> velocity_profile(const Solids* solids, const FluidParticles* fluid, const TankFrame& frame,
                                           double thickness, std::size_t count) {
  std::vector<ProfileLayer> layers(count);
  std::vector<double> fluid_sum(count, 0.0), grain_volume(count, 0.0), grain_momentum(count, 0.0);
  const double floor_z = frame.floor_z();
  for (std::size_t k = 0; k < count; ++k) {
    layers[k].z_low = static_cast<double>(k) * thickness;
    layers[k].z_high = static_cast<double>(k + 1) * thickness;
  }
  auto layer_index = [&](double height) -> std::int64_t {
    return static_cast<std::int64_t>(std::floor(height / thickness));
  };
  if (fluid) {
    for (std::size_t j = 0; j < fluid->size(); ++j) {
      if (fluid->kind[j] != static_cast<std::int32_t>(FluidKind::kFluid)) continue;
      const double height = fluid->position[j].z() - floor_z;
      if (!(height >= 0.0)) continue;
      const std::int64_t k = layer_index(height);
      if (k < 0 || k >= static_cast<std::int64_t>(count)) continue;
      ++layers[static_cast<std::size_t>(k)].fluid_particles;
      fluid_sum[static_cast<std::size_t>(k)] += fluid->velocity[j].x() - frame.velocity.x();
    }
  }
  if (solids) {
    for (std::size_t i = 0; i < solids->size(); ++i) {
      const double r = solids->radius[i];
      const double centre = solids->position[i].z() - floor_z;
      const double ux = solids->velocity[i].x() - frame.velocity.x();
      const std::int64_t first = std::max<std::int64_t>(0, layer_index(centre - r));
      const std::int64_t last = std::min<std::int64_t>(static_cast<std::int64_t>(count) - 1, layer_index(centre + r));
      for (std::int64_t k = first; k <= last; ++k) {
        const auto layer = static_cast<std::size_t>(k);
        const double volume = sphere_slab_volume(r, centre, layers[layer].z_low, layers[layer].z_high);
        grain_volume[layer] += volume;
        grain_momentum[layer] += volume * ux;
      }
    }
  }
  const double layer_volume = frame.area() * thickness;
  for (std::size_t k = 0; k < count; ++k) {
    ProfileLayer& layer = layers[k];
    layer.fluid_ux = layer.fluid_particles ? fluid_sum[k] / static_cast<double>(layer.fluid_particles) : kNaN;
    layer.grain_ux = grain_volume[k] > 0.0 ? grain_momentum[k] / grain_volume[k] : kNaN;
    layer.solid_fraction = layer_volume > 0.0 ? grain_volume[k] / layer_volume : kNaN;
  }
  return layers;
}

ShearSettings shear_settings(const Model& model) {
  ShearSettings settings;
  settings.density = model.fluid.density;
  settings.kinematic_viscosity = model.fluid.kinematic_viscosity;
  if (model.fluid.spacing > 0.0) {
    const MpsConstants& constants = mps_constants(model.fluid);  // the constants fluid_predict uses
    settings.spacing = constants.spacing;
    settings.effective_radius = constants.effective_radius;
    settings.number_density = constants.reference_density;
    settings.laplacian_lambda = constants.laplacian_lambda;
  }
  return settings;
}

BedShear bed_shear_stress(const Solids* solids, const FluidParticles* fluid, const ShearSettings& settings,
                          const TankFrame& frame) {
  BedShear shear;
  if (solids)
    for (std::size_t i = 0; i < solids->size(); ++i)
      shear.grains_fx += solids->drag_force[i].x() + solids->pressure_force[i].x() + solids->viscous_force[i].x() +
                         solids->added_mass_force[i].x() + solids->history_force[i].x();
  if (fluid && settings.spacing > 0.0 && settings.number_density > 0.0 && settings.laplacian_lambda > 0.0) {
    // The boundary particles below the floor plane (rest positions: they move with the tank), binned on a plan
    // grid of cells r_e wide, so each fluid particle near the floor visits only its 3 x 3 cells.
    const double re = settings.effective_radius;
    const double floor_rest = frame.low.z();
    std::vector<std::size_t> boundary;
    for (std::size_t j = 0; j < fluid->size(); ++j)
      if (fluid->kind[j] != static_cast<std::int32_t>(FluidKind::kFluid) && fluid->rest_position[j].z() < floor_rest)
        boundary.push_back(j);
    if (!boundary.empty()) {
      double x_min = std::numeric_limits<double>::infinity(), y_min = x_min, x_max = -x_min, y_max = -x_min,
             z_top = -x_min;
      for (std::size_t j : boundary) {
        x_min = std::min(x_min, fluid->position[j].x());
        x_max = std::max(x_max, fluid->position[j].x());
        y_min = std::min(y_min, fluid->position[j].y());
        y_max = std::max(y_max, fluid->position[j].y());
        z_top = std::max(z_top, fluid->position[j].z());
      }
      const auto nx = static_cast<std::int64_t>(std::min(4096.0, std::floor((x_max - x_min) / re) + 1.0));
      const auto ny = static_cast<std::int64_t>(std::min(4096.0, std::floor((y_max - y_min) / re) + 1.0));
      auto cell_of = [&](double value, double low, std::int64_t cells) {
        return std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor((value - low) / re)), 0, cells - 1);
      };
      std::vector<std::vector<std::size_t>> cells(static_cast<std::size_t>(nx * ny));
      for (std::size_t j : boundary)
        cells[static_cast<std::size_t>(cell_of(fluid->position[j].x(), x_min, nx) +
                                       nx * cell_of(fluid->position[j].y(), y_min, ny))]
            .push_back(j);
      const WendlandKernel kernel{re};
      // nu <lap u>_i = nu 2D/(lambda0 n0) sum_j (u_j - u_i) w_ij (D = 3), as fluid_predict applies it; times the
      // particle's mass rho l0^3 it is the force on fluid particle i, and its reaction is on the floor.
      const double factor = settings.density * settings.spacing * settings.spacing * settings.spacing *
                            settings.kinematic_viscosity * 6.0 /
                            (settings.laplacian_lambda * settings.number_density);
      double sum = 0.0;
      for (std::size_t i = 0; i < fluid->size(); ++i) {
        if (fluid->kind[i] != static_cast<std::int32_t>(FluidKind::kFluid)) continue;
        const Vec3& xi = fluid->position[i];
        if (!(xi.z() < z_top + re)) continue;
        const std::int64_t cx = static_cast<std::int64_t>(std::floor((xi.x() - x_min) / re));
        const std::int64_t cy = static_cast<std::int64_t>(std::floor((xi.y() - y_min) / re));
        for (std::int64_t by = std::max<std::int64_t>(0, cy - 1); by <= std::min(ny - 1, cy + 1); ++by)
          for (std::int64_t bx = std::max<std::int64_t>(0, cx - 1); bx <= std::min(nx - 1, cx + 1); ++bx)
            for (std::size_t j : cells[static_cast<std::size_t>(bx + nx * by)]) {
              const double distance = (fluid->position[j] - xi).norm();
              if (distance < re) sum += kernel.weight(distance) * (fluid->velocity[i].x() - fluid->velocity[j].x());
            }
      }
      shear.floor_fx = factor * sum;
    }
  }
  const double area = frame.area();
  shear.tau = area > 0.0 ? (shear.grains_fx + shear.floor_fx) / area : kNaN;
  return shear;
}

namespace {
/// Index among the scene's lids (the order of FluidSummary::lid_force) of the one that drives the flow: the first
/// lid with a velocity (seed 003's plane Couette has one moving lid; a lid at rest is a no-slip wall).
std::optional<std::size_t> driving_lid(const Model& model, const ParticleBoxModel** box_out = nullptr) {
  std::size_t index = 0;
  for (const ParticleBoxModel& box : model.fluid.wall_boxes) {
    if (!box.lid) continue;
    if (box.lid_velocity != 0.0) {
      if (box_out) *box_out = &box;
      return index;
    }
    ++index;
  }
  return std::nullopt;
}
}  // namespace

std::optional<double> lid_shear_stress(const Model& model, const World& world) {
  const ParticleBoxModel* box = nullptr;
  const std::optional<std::size_t> lid = driving_lid(model, &box);
  if (!lid || !world.fluid_summary || *lid >= world.fluid_summary->lid_force.size() || !(box->lid_area > 0.0))
    return std::nullopt;
  return world.fluid_summary->lid_force[*lid].x() / box->lid_area;
}

bool model_has_lid(const Model& model) { return model.fluid.enabled && driving_lid(model).has_value(); }

std::vector<double> RunningMean::add(double time, const std::vector<double>& values) {
  if (!last_time_ || integral_.size() != values.size()) {
    integral_.assign(values.size(), 0.0);
    covered_ = 0.0;
  } else if (time > *last_time_) {
    const double held = time - *last_time_;
    for (std::size_t k = 0; k < values.size(); ++k) integral_[k] += held * values[k];
    covered_ += held;
  }
  last_time_ = time;
  last_ = values;
  if (!(covered_ > 0.0)) return values;
  std::vector<double> mean(values.size());
  for (std::size_t k = 0; k < values.size(); ++k) mean[k] = integral_[k] / covered_;
  return mean;
}

}  // namespace riffle
