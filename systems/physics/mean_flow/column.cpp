#include "systems/physics/mean_flow/column.hpp"

#include "systems/physics/measures/bedload.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace riffle {

namespace {

/// The water's share of cell i.
double water_share(const std::vector<double>& solid_fraction, std::size_t i) { return 1.0 - solid_fraction[i]; }

/// The water's share at face j (0 the floor, cells the top): the mean of the two cells it separates, the cell's own
/// at the floor and the top.
double face_water_share(const std::vector<double>& solid_fraction, std::size_t j) {
  const std::size_t cells = solid_fraction.size();
  if (j == 0) return water_share(solid_fraction, 0);
  if (j >= cells) return water_share(solid_fraction, cells - 1);
  return 0.5 * (water_share(solid_fraction, j - 1) + water_share(solid_fraction, j));
}

/// The constant-stress profile of the closure over a floor whose mixing length is l0: in wall units (y = l+ =
/// kappa (z+ + l0+ / kappa)), du+/dy = (1 / kappa) 2 / (1 + sqrt(1 + 4 y^2)) (the root of (1 + y^2 du+/dz+) du+/dz+
/// = 1), whose antiderivative is F(y) = asinh(2 y) - 2 y / (1 + sqrt(1 + 4 y^2)), F(y) -> ln(4 y) - 1 far above.
double constant_stress_primitive(double y) {
  const double root = std::sqrt(1.0 + 4.0 * y * y);
  return std::asinh(2.0 * y) - 2.0 * y / (1.0 + root);
}

/// [m] The rough floor's mixing length l0: the one whose profile, with the molecular viscosity that the momentum
/// step adds to l^2 |du/dz|, has Nikuradse's law u+ = ln(z / k_s) / kappa + B_r far above the floor. From F above,
/// u+ -> (ln(4 kappa z+) - 1 - F(l0+)) / kappa, so F(l0+) = ln(4 kappa k_s+) - 1 - kappa B_r: l0 -> kappa z0
/// (z0 = k_s exp(-kappa B_r)) when k_s+ is large, but at k_s+ = 100 the viscosity alone would lower B_r by 0.9 with
/// l0 = kappa z0. Solved by Newton in s = ln l0+ (F(e^s) is convex and increasing in s, and the start kappa z0+
/// lies above the root, so the iterates fall monotonically onto it). Below k_s+ ~ 55 no l0 >= 0 reaches B_r (the
/// floor is no longer fully rough): l0 = 0. Without a friction velocity or a viscosity, kappa z0.
double rough_floor_length(const MixingLengthClosure& closure, double friction_velocity, double viscosity) {
  const double kappa = closure.von_karman;
  const double inviscid = kappa * closure.roughness * std::exp(-kappa * closure.rough_wall_constant);
  if (!(friction_velocity > 0.0) || !(viscosity > 0.0) || !(inviscid > 0.0)) return inviscid;
  const double unit = viscosity / friction_velocity;  // [m] the viscous length
  const double target = std::log(4.0 * kappa * closure.roughness / unit) - 1.0 - kappa * closure.rough_wall_constant;
  if (!(target > 0.0)) return 0.0;
  double s = std::log(inviscid / unit);
  for (int iteration = 0; iteration < 60; ++iteration) {
    const double y = std::exp(s);
    const double slope = 2.0 * y / (1.0 + std::sqrt(1.0 + 4.0 * y * y));  // dF/ds = y dF/dy
    const double change = (constant_stress_primitive(y) - target) / slope;
    s -= change;
    if (std::abs(change) < 1e-14) break;
  }
  return std::exp(s) * unit;
}

void check_sizes(const ColumnGrid& grid, std::size_t cell_values, std::size_t face_values, const char* what) {
  if (grid.cells == 0 || !(grid.cell_height > 0.0)) throw std::invalid_argument(std::string(what) + ": empty grid");
  if (cell_values != grid.cells || (face_values != 0 && face_values != grid.cells + 1))
    throw std::invalid_argument(std::string(what) + ": profile sizes do not match the grid");
}
}  // namespace

CellSpan sphere_cells(const ColumnGrid& grid, double centre, double radius) {
  const double from = (centre - radius - grid.bottom) / grid.cell_height;
  const double to = (centre + radius - grid.bottom) / grid.cell_height;
  // (written so that a centre that is not a number, a grain blown up, gives no cells)
  if (!(to > 0.0) || !(from < static_cast<double>(grid.cells))) return {};
  return {static_cast<std::size_t>(std::max(0.0, std::floor(from))),
          std::min(grid.cells - 1, static_cast<std::size_t>(std::floor(to))), false};
}

double deposit_sphere(const ColumnGrid& grid, double centre, double radius, double weight,
                      std::vector<double>& per_cell) {
  const CellSpan span = sphere_cells(grid, centre, radius);
  if (span.empty) return 0.0;
  double inside = 0.0;
  for (std::size_t i = span.first; i <= span.last; ++i) {
    const double volume = sphere_slab_volume(radius, centre, grid.face(i), grid.face(i + 1));
    per_cell[i] += weight * volume;
    inside += volume;
  }
  return inside;
}

double profile_at(const ColumnGrid& grid, const std::vector<double>& values, double z, const ColumnEnds& ends) {
  check_sizes(grid, values.size(), 0, "profile_at");
  const std::size_t cells = grid.cells;
  if (std::isnan(z)) return z;  // a height that is not a number reads none (and indexes nothing)
  const double position = (std::clamp(z, grid.bottom, grid.top()) - grid.bottom) / grid.cell_height - 0.5;
  if (position <= 0.0) {  // between the floor (position -1/2) and the first centre
    const double t = (position + 0.5) / 0.5;
    return ends.bottom_value + t * (values[0] - ends.bottom_value);
  }
  const double last = static_cast<double>(cells - 1);
  if (position >= last) {
    if (!ends.top_given) return values[cells - 1];
    const double t = (position - last) / 0.5;
    return values[cells - 1] + t * (ends.top_value - values[cells - 1]);
  }
  const auto i = static_cast<std::size_t>(position);
  const double t = position - static_cast<double>(i);
  return values[i] + t * (values[i + 1] - values[i]);
}

double bed_surface(const ColumnGrid& grid, const std::vector<double>& solid_fraction) {
  check_sizes(grid, solid_fraction.size(), 0, "bed_surface");
  const double largest = *std::max_element(solid_fraction.begin(), solid_fraction.end());
  if (!(largest > 0.0)) return grid.bottom;
  const double half = 0.5 * largest;
  std::size_t i = grid.cells - 1;
  while (solid_fraction[i] < half) --i;  // stops at the largest value at the latest
  if (i + 1 == grid.cells) return grid.top();
  const double above = solid_fraction[i + 1];
  return grid.centre(i) + grid.cell_height * (solid_fraction[i] - half) / (solid_fraction[i] - above);
}

std::vector<double> mixing_lengths(const ColumnGrid& grid, const std::vector<double>& solid_fraction,
                                   const MixingLengthClosure& closure, double floor_friction_velocity,
                                   double viscosity, const TopWall& top) {
  check_sizes(grid, solid_fraction.size(), 0, "mixing_lengths");
  const double packed = closure.max_solid_fraction;
  // Every cell at or below the highest packed one counts as packed: no turbulence leaks into the bed's pores.
  std::size_t packed_below = 0;  // cells [0, packed_below) count as packed
  for (std::size_t i = grid.cells; i-- > 0;)
    if (solid_fraction[i] >= packed) {
      packed_below = i + 1;
      break;
    }
  const bool rough = closure.floor == MixingLengthClosure::Floor::kRough;
  // A floor buried under a packed bed is no longer the water's wall: the bed is, and its mixing length starts at 0.
  const double floor_length =
      rough && packed_below == 0 ? rough_floor_length(closure, floor_friction_velocity, viscosity) : 0.0;
  std::vector<double> lengths(grid.cells + 1, 0.0);
  double integral = 0.0;
  lengths[0] = floor_length;
  for (std::size_t j = 1; j <= grid.cells; ++j) {
    const double phi = j - 1 < packed_below ? packed : std::min(solid_fraction[j - 1], packed);
    integral += closure.von_karman * grid.cell_height * (packed - phi) / packed;
    lengths[j] = floor_length + integral;
  }
  if (!rough && packed_below == 0) {
    const double scale = floor_friction_velocity / (viscosity * closure.van_driest);  // 1 / (nu A+ / u*)
    for (std::size_t j = 0; j <= grid.cells; ++j)
      lengths[j] *= 1.0 - std::exp(-(grid.face(j) - grid.bottom) * scale);
  }
  if (top.wall) {
    const double scale = top.friction_velocity / (viscosity * closure.van_driest);
    for (std::size_t j = 0; j <= grid.cells; ++j) {
      const double below_lid = grid.top() - grid.face(j);
      lengths[j] = std::min(lengths[j], closure.von_karman * below_lid) * (1.0 - std::exp(-below_lid * scale));
    }
  }
  return lengths;
}

double face_gradient(const ColumnGrid& grid, const std::vector<double>& velocity, const ColumnEnds& ends,
                     std::size_t j) {
  const std::size_t cells = grid.cells;
  const double half = 0.5 * grid.cell_height;
  if (j == 0) return (velocity[0] - ends.bottom_value) / half;
  if (j >= cells) return ends.top_given ? (ends.top_value - velocity[cells - 1]) / half : 0.0;
  return (velocity[j] - velocity[j - 1]) / grid.cell_height;
}

std::vector<double> eddy_viscosities(const ColumnGrid& grid, const std::vector<double>& velocity,
                                     const std::vector<double>& velocity_y, const std::vector<double>& lengths,
                                     const ColumnEnds& ends_x, const ColumnEnds& ends_y) {
  check_sizes(grid, velocity.size(), lengths.size(), "eddy_viscosities");
  const bool two = !velocity_y.empty();
  if (two) check_sizes(grid, velocity_y.size(), 0, "eddy_viscosities");
  std::vector<double> viscosity(grid.cells + 1, 0.0);
  for (std::size_t j = 0; j <= grid.cells; ++j) {
    const double gx = face_gradient(grid, velocity, ends_x, j);
    const double gy = two ? face_gradient(grid, velocity_y, ends_y, j) : 0.0;
    viscosity[j] = lengths[j] * lengths[j] * std::sqrt(gx * gx + gy * gy);
  }
  return viscosity;
}

ColumnStresses advance_column(const ColumnGrid& grid, const std::vector<double>& solid_fraction,
                              const std::vector<double>& eddy_viscosity, const std::vector<double>& impulse,
                              const ColumnEnds& ends, const ColumnStep& step, std::vector<double>& velocity) {
  const std::size_t cells = grid.cells;
  check_sizes(grid, solid_fraction.size(), eddy_viscosity.size(), "advance_column");
  check_sizes(grid, velocity.size(), 0, "advance_column");
  check_sizes(grid, impulse.size(), 0, "advance_column");
  const bool relaxed = step.relaxation_rate > 0.0;
  if (relaxed && (step.relaxation_target == nullptr || step.relaxation_target->size() != cells))
    throw std::invalid_argument("advance_column: a relaxation needs a target per cell");
  const double h = grid.cell_height;
  // Face conductances D_j = rho eps_j (nu + nu_t,j) / distance: h between centres, h/2 from the floor or the lid.
  std::vector<double> conductance(cells + 1, 0.0);
  for (std::size_t j = 0; j <= cells; ++j) {
    const bool wall = j == 0 || (j == cells && ends.top_given);
    if (j == cells && !ends.top_given) continue;  // a free top carries no stress
    const double distance = wall ? 0.5 * h : h;
    conductance[j] = step.density * face_water_share(solid_fraction, j) * (step.viscosity + eddy_viscosity[j]) /
                     distance;
  }
  // a_i u_{i-1} + b_i u_i + c_i u_{i+1} = r_i, solved by the Thomas algorithm (diagonally dominant: b > |a| + |c|).
  std::vector<double> upper(cells, 0.0), rhs(cells, 0.0);
  double previous_upper = 0.0;
  double previous_rhs = 0.0;
  for (std::size_t i = 0; i < cells; ++i) {
    const double mass = step.density * water_share(solid_fraction, i) * h;
    const double lower = i > 0 ? -step.dt * conductance[i] : 0.0;
    double diagonal = mass + step.dt * (conductance[i] + conductance[i + 1]);
    const double above = i + 1 < cells ? -step.dt * conductance[i + 1] : 0.0;
    double right = mass * velocity[i] + step.dt * mass * step.body_force - impulse[i];
    if (relaxed) {
      diagonal += step.dt * mass * step.relaxation_rate;
      right += step.dt * mass * step.relaxation_rate * (*step.relaxation_target)[i];
    }
    if (i == 0) right += step.dt * conductance[0] * ends.bottom_value;
    if (i + 1 == cells && ends.top_given) right += step.dt * conductance[cells] * ends.top_value;
    const double pivot = diagonal - lower * previous_upper;
    upper[i] = above / pivot;
    rhs[i] = (right - lower * previous_rhs) / pivot;
    previous_upper = upper[i];
    previous_rhs = rhs[i];
  }
  velocity[cells - 1] = rhs[cells - 1];
  for (std::size_t i = cells - 1; i-- > 0;) velocity[i] = rhs[i] - upper[i] * velocity[i + 1];
  ColumnStresses stresses;
  stresses.floor = conductance[0] * (velocity[0] - ends.bottom_value);
  if (ends.top_given) stresses.top = conductance[cells] * (ends.top_value - velocity[cells - 1]);
  return stresses;
}

double column_momentum(const ColumnGrid& grid, const std::vector<double>& solid_fraction,
                       const std::vector<double>& velocity, double density) {
  double momentum = 0.0;
  for (std::size_t i = 0; i < grid.cells; ++i)
    momentum += density * water_share(solid_fraction, i) * grid.cell_height * velocity[i];
  return momentum;
}

double column_shear_stress(const ColumnGrid& grid, const std::vector<double>& solid_fraction,
                           const std::vector<double>& eddy_viscosity, const std::vector<double>& velocity,
                           const ColumnEnds& ends, double density, double viscosity, double z) {
  if (std::isnan(z)) return z;
  const double position = std::clamp((z - grid.bottom) / grid.cell_height, 0.0, static_cast<double>(grid.cells));
  const auto j = static_cast<std::size_t>(std::lround(position));
  return density * face_water_share(solid_fraction, j) * (viscosity + eddy_viscosity[j]) *
         face_gradient(grid, velocity, ends, j);
}

}  // namespace riffle
