#include "systems/physics/coupling/voidage_grid.hpp"

#include <algorithm>
#include <cmath>

#include "systems/physics/geometry/cell_index.hpp"

namespace riffle {

CloudInCellStencil VoidageGrid::stencil(const Vec3& point) const {
  CloudInCellStencil result{};
  std::array<std::array<std::int64_t, 2>, 3> index{};  // per axis, the nodes of corner bit 0 and 1
  std::array<double, 3> fraction{};
  for (int axis = 0; axis < 3; ++axis) {
    const auto a = static_cast<std::size_t>(axis);
    const double scaled = (point[axis] - origin_[axis]) / cell_[a];
    if (wraps_[a]) {
      // Along a periodic axis the cell is taken modulo the period: the last cell's upper node is node 0.
      const double whole = std::isfinite(scaled) ? std::floor(scaled) : 0.0;
      fraction[a] = std::isfinite(scaled) ? scaled - whole : 0.0;
      const std::int64_t n = nodes_[a];
      const std::int64_t base = ((static_cast<std::int64_t>(std::clamp(whole, -1e15, 1e15)) % n) + n) % n;
      index[a] = {base, (base + 1) % n};
      continue;
    }
    // A non-finite grain lands on node 0.
    const double top = static_cast<double>(nodes_[a] - 2);
    const double clamped = clamp_to_cells(scaled, top);
    const auto base = static_cast<std::int64_t>(std::floor(clamped));
    fraction[a] = clamped - std::floor(clamped);
    index[a] = {base, base + 1};
  }
  result.fraction = fraction;
  for (int corner = 0; corner < 8; ++corner) {
    const std::int64_t x = index[0][static_cast<std::size_t>(corner & 1)],
                       y = index[1][static_cast<std::size_t>((corner >> 1) & 1)],
                       z = index[2][static_cast<std::size_t>((corner >> 2) & 1)];
    result.node[static_cast<std::size_t>(corner)] = static_cast<std::size_t>((z * nodes_[1] + y) * nodes_[0] + x);
    result.weight[static_cast<std::size_t>(corner)] = ((corner & 1) ? fraction[0] : 1.0 - fraction[0]) *
                                                      (((corner >> 1) & 1) ? fraction[1] : 1.0 - fraction[1]) *
                                                      (((corner >> 2) & 1) ? fraction[2] : 1.0 - fraction[2]);
  }
  return result;
}

void VoidageGrid::build(std::span<const Vec3> grain_positions, std::span<const double> grain_volumes,
                        std::span<const Vec3> fluid_positions, std::size_t fluid_count, double fluid_particle_volume,
                        double cell_size, const Vec3& bound_low, const Vec3& bound_high, const PeriodicBox& box) {
  build(grain_positions, grain_volumes, fluid_positions, fluid_count, fluid_particle_volume, Vec3::Constant(cell_size),
        bound_low, bound_high, box);
}

void VoidageGrid::build(std::span<const Vec3> grain_positions, std::span<const double> grain_volumes,
                        std::span<const Vec3> fluid_positions, std::size_t fluid_count, double fluid_particle_volume,
                        const Vec3& cell_size, const Vec3& bound_low, const Vec3& bound_high, const PeriodicBox& box) {
  Vec3 asked = cell_size;
  Vec3 low = Vec3::Constant(1e300), high = Vec3::Constant(-1e300);
  for (const Vec3& p : grain_positions) low = low.cwiseMin(p), high = high.cwiseMax(p);
  for (std::size_t k = 0; k < fluid_count; ++k) low = low.cwiseMin(fluid_positions[k]), high = high.cwiseMax(fluid_positions[k]);
  if (low[0] > high[0]) low = high = Vec3::Zero();
  // Anchored (over ranks): the anchor's lattice, started at its last node at or below these points' lowest corner, so
  // a rank far from the anchor holds only the cells around its own points.
  if (anchor_)
    for (int axis = 0; axis < 3; ++axis) {
      const double anchor = (*anchor_)[axis];
      low[axis] = low[axis] > anchor ? anchor + std::floor((low[axis] - anchor) / asked[axis]) * asked[axis] : anchor;
      high[axis] = std::max(high[axis], low[axis]);
    }
  // Within the bounds (unchanged while every point is inside them; a NaN coordinate leaves the bound).
  for (int axis = 0; axis < 3; ++axis) {
    low[axis] = low[axis] >= bound_low[axis] ? std::min(low[axis], bound_high[axis]) : bound_low[axis];
    high[axis] = high[axis] <= bound_high[axis] ? std::max(high[axis], low[axis]) : bound_high[axis];
  }
  // Nodes per axis in doubles, capped before the conversion, at most 4096 each.
  auto axis_nodes = [&](int axis) {
    const double span = (high[axis] - (low[axis] - asked[axis])) / asked[axis];
    return clamp_to_cells(std::floor(span), 4093.0) + 3.0;
  };
  // Along a periodic axis the grid spans the whole period in whole cells (at least 4, so that the smoothing's reach
  // of one node either side of a grain's cell never folds back onto it), however few points there are.
  auto nodes_along = [&](int axis) {
    const auto a = static_cast<std::size_t>(axis);
    if (!box.periodic[a]) return axis_nodes(axis);
    return std::max(4.0, clamp_to_cells(std::floor(box.length[axis] / asked[axis]), 4096.0));
  };
  auto total_nodes = [&] { return nodes_along(0) * nodes_along(1) * nodes_along(2); };
  // A stray particle far from the others (still inside a wide domain), or a long period with few points, must not
  // make the grid huge: above voidage_node_limit the cells double until it fits. That changes the field, but only for
  // a grid that big, which no valid scene builds (64 nodes per particle; the seed scenes use well under one).
  const double limit = voidage_node_limit(grain_positions.size() + fluid_count);
  while (total_nodes() > limit && asked.maxCoeff() < 1e300) asked *= 2.0;
  const bool fits = total_nodes() <= limit;  // not with an infinite coordinate
  origin_ = low - asked;
  for (int axis = 0; axis < 3; ++axis) {
    const auto a = static_cast<std::size_t>(axis);
    nodes_[a] = fits ? static_cast<std::int64_t>(nodes_along(axis)) : 2;
    cell_[a] = asked[axis];
    wraps_[a] = box.periodic[a] && fits;
    if (!wraps_[a]) continue;
    // Whole cells per period, from the period's low face.
    cell_[a] = box.length[axis] / static_cast<double>(nodes_[a]);
    origin_[axis] = box.low[axis];
  }
  const std::size_t total = static_cast<std::size_t>(nodes_[0] * nodes_[1] * nodes_[2]);
  smoothed_ = false;
  solid_.assign(total, 0.0);
  fluid_.assign(total, 0.0);
  for (std::size_t grain = 0; grain < grain_positions.size(); ++grain) {
    const CloudInCellStencil s = stencil(grain_positions[grain]);
    for (int c = 0; c < 8; ++c) solid_[s.node[static_cast<std::size_t>(c)]] += grain_volumes[grain] * s.weight[static_cast<std::size_t>(c)];
  }
  for (std::size_t k = 0; k < fluid_count; ++k) {
    const CloudInCellStencil s = stencil(fluid_positions[k]);
    for (int c = 0; c < 8; ++c) fluid_[s.node[static_cast<std::size_t>(c)]] += fluid_particle_volume * s.weight[static_cast<std::size_t>(c)];
  }
}

namespace {

/// The integral over [low, high] of the cloud-in-cell weight max(0, 1 - |x - centre| / cell) of a node at `centre`:
/// `cell` for a node whose whole support is inside, less where the interval cuts it.
double clipped_tent_integral(double centre, double cell, double low, double high) {
  // The tent's integral from -infinity to x.
  const auto below = [&](double x) {
    const double u = (x - centre) / cell;
    if (u <= -1.0) return 0.0;
    if (u <= 0.0) return 0.5 * cell * (1.0 + u) * (1.0 + u);
    if (u < 1.0) return cell * (1.0 - 0.5 * (1.0 - u) * (1.0 - u));
    return cell;
  };
  return high > low ? below(high) - below(low) : 0.0;
}

}  // namespace

void VoidageGrid::fill_box_volume(const Vec3& low, const Vec3& high) {
  // Per axis, each node's share of the box; a wrapping axis has no faces, so every node has its whole cell.
  std::array<std::vector<double>, 3> share;
  for (std::size_t a = 0; a < 3; ++a) {
    share[a].resize(static_cast<std::size_t>(nodes_[a]));
    for (std::int64_t i = 0; i < nodes_[a]; ++i)
      share[a][static_cast<std::size_t>(i)] =
          wraps_[a] ? cell_[a]
                    : clipped_tent_integral(origin_[static_cast<int>(a)] + static_cast<double>(i) * cell_[a], cell_[a],
                                            low[static_cast<int>(a)], high[static_cast<int>(a)]);
  }
  for (std::int64_t z = 0; z < nodes_[2]; ++z)
    for (std::int64_t y = 0; y < nodes_[1]; ++y)
      for (std::int64_t x = 0; x < nodes_[0]; ++x)
        fluid_[static_cast<std::size_t>((z * nodes_[1] + y) * nodes_[0] + x)] =
            share[0][static_cast<std::size_t>(x)] * share[1][static_cast<std::size_t>(y)] *
            share[2][static_cast<std::size_t>(z)];
  smoothed_ = false;
}

double VoidageGrid::solid_fraction(const Vec3& point) const {
  const CloudInCellStencil s = stencil(point);
  double fraction = 0.0, weight = 0.0;
  for (int c = 0; c < 8; ++c) {
    const std::size_t node = s.node[static_cast<std::size_t>(c)];
    if (fluid_[node] <= 0.0) continue;
    fraction += s.weight[static_cast<std::size_t>(c)] * solid_[node] / fluid_[node];
    weight += s.weight[static_cast<std::size_t>(c)];
  }
  return weight > 0.0 ? fraction / weight : 0.0;
}

namespace {

/// One binomial (1/4, 1/2, 1/4) pass along `axis` of a field of nodes[0] x nodes[1] x nodes[2] values (x fastest),
/// zero beyond the ends, in place: each line is filtered with a running copy of the value below.
void binomial_pass(std::vector<double>& field, const std::array<std::int64_t, 3>& nodes, int axis, bool wraps) {
  const std::array<std::int64_t, 3> stride{1, nodes[0], nodes[0] * nodes[1]};
  const auto a = static_cast<std::size_t>(axis), b = (a + 1) % 3, c = (a + 2) % 3;
  const std::int64_t length = nodes[a], step = stride[a];
  for (std::int64_t j = 0; j < nodes[c]; ++j)
    for (std::int64_t i = 0; i < nodes[b]; ++i) {
      double* line = field.data() + i * stride[b] + j * stride[c];
      // Along a periodic axis the line is a ring: node 0's lower neighbour is the last node, and the last node's
      // upper neighbour is node 0 as it was before the pass.
      const double first = line[0];
      double below = wraps ? line[(length - 1) * step] : 0.0;
      for (std::int64_t k = 0; k < length; ++k) {
        const double here = line[k * step];
        const double above = k + 1 < length ? line[(k + 1) * step] : (wraps ? first : 0.0);
        line[k * step] = 0.25 * below + 0.5 * here + 0.25 * above;
        below = here;
      }
    }
}

}  // namespace

double hard_sphere_structure_factor(double solid_fraction) {
  const double phi = std::clamp(solid_fraction, 0.0, 1.0);
  const double open = 1.0 - phi;
  return open * open * open * open / (1.0 + phi * (4.0 + phi * (4.0 + phi * (-4.0 + phi))));
}

double self_corrected_solid_fraction(double others, double own) {
  double phi = others;
  for (int iteration = 0; iteration < 3; ++iteration) phi = others + own * (1.0 - hard_sphere_structure_factor(phi));
  return phi;
}

void VoidageGrid::smooth() {
  for (int axis = 0; axis < 3; ++axis) {
    binomial_pass(solid_, nodes_, axis, wraps_[static_cast<std::size_t>(axis)]);
    binomial_pass(fluid_, nodes_, axis, wraps_[static_cast<std::size_t>(axis)]);
  }
  smoothed_ = true;
}

GrainSolidFraction VoidageGrid::grain_fraction(const Vec3& point, double volume) const {
  const CloudInCellStencil s = stencil(point);
  // The grain's own deposit at the two nodes of its cell along each axis, after the smoothing: with trilinear weights
  // (w0, w1) on (b, b + 1), the filter leaves w0/2 + w1/4 at b and w0/4 + w1/2 at b + 1 (and the rest outside the
  // cell, which the read back does not reach).
  std::array<std::array<double, 2>, 3> own_axis{};
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const double w0 = 1.0 - s.fraction[axis], w1 = s.fraction[axis];
    own_axis[axis] = smoothed_ ? std::array<double, 2>{0.5 * w0 + 0.25 * w1, 0.25 * w0 + 0.5 * w1} : std::array<double, 2>{w0, w1};
  }
  GrainSolidFraction result;
  double weight = 0.0;
  for (int c = 0; c < 8; ++c) {
    const std::size_t node = s.node[static_cast<std::size_t>(c)];
    if (fluid_[node] <= 0.0) continue;
    const double w = s.weight[static_cast<std::size_t>(c)];
    const double own = volume * own_axis[0][static_cast<std::size_t>(c & 1)] *
                       own_axis[1][static_cast<std::size_t>((c >> 1) & 1)] * own_axis[2][static_cast<std::size_t>((c >> 2) & 1)];
    result.included += w * solid_[node] / fluid_[node];
    result.own += w * own / fluid_[node];
    weight += w;
  }
  if (weight > 0.0) result.included /= weight, result.own /= weight;
  return result;
}

}  // namespace riffle
