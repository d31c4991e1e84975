#include "engine/setup/fluid_layout.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace riffle {

namespace {

Vec3 lattice_position(const Vec3& origin, double spacing, std::int64_t i, std::int64_t j, std::int64_t k) {
  return origin + spacing * Vec3(static_cast<double>(i) + 0.5, static_cast<double>(j) + 0.5,
                                 static_cast<double>(k) + 0.5);
}

void count(FluidLayout& layout, FluidKind kind) {
  switch (kind) {
    case FluidKind::kFluid: ++layout.fluid; break;
    case FluidKind::kWall: ++layout.wall; break;
    case FluidKind::kDummy: ++layout.dummy; break;
  }
}

}  // namespace

std::int64_t dummy_layer_count(double spacing, double effective_radius) {
  if (!(spacing > 0.0) || !(effective_radius > 0.0))
    throw std::invalid_argument("dummy_layer_count: spacing and effective radius must be positive");
  return std::max<std::int64_t>(0, static_cast<std::int64_t>(std::ceil(effective_radius / spacing - 1e-9)) - 1);
}

bool LatticeRange::overlaps(const LatticeRange& other) const {
  for (std::size_t a = 0; a < 3; ++a)
    if (std::max(first[a], other.first[a]) > std::min(last[a], other.last[a])) return false;
  return true;
}

LatticeRange lattice_range(const Vec3& lattice_origin, const Vec3& low, const Vec3& high, double spacing) {
  if (!(spacing > 0.0)) throw std::invalid_argument("lattice_range: spacing must be positive");
  constexpr double kTolerance = 1e-9;
  LatticeRange range;
  for (int axis = 0; axis < 3; ++axis) {
    // Cell centres origin + (i + 1/2) l0 inside [low, high].
    const auto a = static_cast<std::size_t>(axis);
    range.first[a] =
        static_cast<std::int64_t>(std::ceil((low[axis] - lattice_origin[axis]) / spacing - 0.5 - kTolerance));
    range.last[a] =
        static_cast<std::int64_t>(std::floor((high[axis] - lattice_origin[axis]) / spacing - 0.5 + kTolerance));
  }
  return range;
}

FluidLayout fluid_box_layout(const Vec3& lattice_origin, const Vec3& low, const Vec3& high, double spacing) {
  if (!(spacing > 0.0)) throw std::invalid_argument("fluid_box_layout: spacing must be positive");
  const LatticeRange range = lattice_range(lattice_origin, low, high, spacing);
  FluidLayout layout;
  for (std::int64_t k = range.first[2]; k <= range.last[2]; ++k)
    for (std::int64_t j = range.first[1]; j <= range.last[1]; ++j)
      for (std::int64_t i = range.first[0]; i <= range.last[0]; ++i) {
        layout.particles.push_back({lattice_position(lattice_origin, spacing, i, j, k), FluidKind::kFluid, {i, j, k}, -1});
        ++layout.fluid;
      }
  return layout;
}

BoxGrid box_grid(const Vec3& lattice_origin, const Vec3& low, const Vec3& high, double spacing, bool fit_extent) {
  if (!(spacing > 0.0)) throw std::invalid_argument("box_grid: spacing must be positive");
  BoxGrid grid;
  grid.spacing = spacing;
  if (!fit_extent) {
    const LatticeRange range = lattice_range(lattice_origin, low, high, spacing);
    for (std::size_t a = 0; a < 3; ++a) grid.count[a] = std::max<std::int64_t>(0, range.last[a] - range.first[a] + 1);
    grid.first = lattice_position(lattice_origin, spacing, range.first[0], range.first[1], range.first[2]);
    return grid;
  }
  constexpr double kTolerance = 1e-9;
  for (int axis = 0; axis < 3; ++axis) {
    const auto a = static_cast<std::size_t>(axis);
    const double size = high[axis] - low[axis];
    const double n = std::max(1.0, std::round(size / spacing));
    grid.count[a] = static_cast<std::int64_t>(n);
    auto on_lattice_face = [&](double face) {
      const double cells = (face - lattice_origin[axis]) / spacing;
      return std::abs(cells - std::round(cells)) <= kTolerance;
    };
    if (on_lattice_face(low[axis]))
      grid.first[axis] = low[axis] + 0.5 * spacing;
    else if (on_lattice_face(high[axis]))
      grid.first[axis] = high[axis] - (n - 0.5) * spacing;
    else
      grid.first[axis] = 0.5 * (low[axis] + high[axis]) - 0.5 * (n - 1.0) * spacing;
  }
  return grid;
}

double grid_distance(const BoxGrid& a, const BoxGrid& b) {
  const double spacing = a.spacing;
  double squared = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    const auto k = static_cast<std::size_t>(axis);
    // a's particle i minus b's particle j: c + (i - j) l0, c = a.first - b.first, i - j in [-(nb - 1), na - 1].
    const double c = a.first[axis] - b.first[axis];
    const double lowest = -static_cast<double>(b.count[k] - 1), highest = static_cast<double>(a.count[k] - 1);
    const double offset = std::clamp(std::round(-c / spacing), lowest, highest);
    const double gap = c + offset * spacing;
    squared += gap * gap;
  }
  return std::sqrt(squared);
}

FluidLayout grid_layout(const BoxGrid& grid, const Vec3& lattice_origin, FluidKind kind) {
  FluidLayout layout;
  if (grid.empty()) return layout;
  layout.particles.reserve(static_cast<std::size_t>(grid.size()));
  for (std::int64_t k = 0; k < grid.count[2]; ++k)
    for (std::int64_t j = 0; j < grid.count[1]; ++j)
      for (std::int64_t i = 0; i < grid.count[0]; ++i) {
        const Vec3 position = grid.first + grid.spacing * Vec3(static_cast<double>(i), static_cast<double>(j),
                                                               static_cast<double>(k));
        std::array<std::int64_t, 3> cell{};
        for (std::size_t a = 0; a < 3; ++a)
          cell[a] = static_cast<std::int64_t>(
              std::floor((position[static_cast<int>(a)] - lattice_origin[static_cast<int>(a)]) / grid.spacing));
        layout.particles.push_back({position, kind, cell, -1});
        count(layout, kind);
      }
  return layout;
}

FluidLayout tank_wall_layout(const Vec3& origin, const Vec3& size, const std::vector<std::string>& open_faces,
                             double spacing, double effective_radius, const std::array<bool, 3>& periodic) {
  const std::int64_t layers = 1 + dummy_layer_count(spacing, effective_radius);
  std::array<std::int64_t, 3> cells{};
  for (int axis = 0; axis < 3; ++axis) {
    const double ratio = size[axis] / spacing;
    const double rounded = std::round(ratio);
    if (!(rounded >= 1.0) || std::abs(ratio - rounded) > 1e-6)
      throw std::invalid_argument("tank_wall_layout: the tank size along each axis must be a positive integer "
                                  "multiple of the particle spacing");
    cells[static_cast<std::size_t>(axis)] = static_cast<std::int64_t>(rounded);
  }
  std::array<bool, 6> closed{};
  for (std::size_t face = 0; face < 6; ++face)
    closed[face] = !periodic[face / 2] &&
                   std::find(open_faces.begin(), open_faces.end(), kTankFaceNames[face]) == open_faces.end();
  for (const std::string& name : open_faces)
    if (std::find(kTankFaceNames.begin(), kTankFaceNames.end(), name) == kTankFaceNames.end())
      throw std::invalid_argument("tank_wall_layout: unknown face '" + name + "'");

  // Lattice range of the shell: `layers` cells beyond every closed face, none beyond an open one.
  std::array<std::int64_t, 3> first{}, last{};
  for (std::size_t a = 0; a < 3; ++a) {
    first[a] = closed[2 * a] ? -layers : 0;
    last[a] = cells[a] - 1 + (closed[2 * a + 1] ? layers : 0);
  }
  FluidLayout layout;
  for (std::int64_t k = first[2]; k <= last[2]; ++k)
    for (std::int64_t j = first[1]; j <= last[1]; ++j)
      for (std::int64_t i = first[0]; i <= last[0]; ++i) {
        const std::array<std::int64_t, 3> cell{i, j, k};
        std::int64_t depth = 0;
        std::int32_t face = -1;
        for (std::size_t a = 0; a < 3; ++a) {
          const std::int64_t below = -cell[a];                // layers beyond the min face
          const std::int64_t above = cell[a] - cells[a] + 1;  // layers beyond the max face
          if (below > 0) {
            depth = std::max(depth, below);
            if (face < 0) face = static_cast<std::int32_t>(2 * a);
          } else if (above > 0) {
            depth = std::max(depth, above);
            if (face < 0) face = static_cast<std::int32_t>(2 * a + 1);
          }
        }
        if (depth == 0) continue;  // inside the tank
        const FluidKind kind = depth == 1 ? FluidKind::kWall : FluidKind::kDummy;
        layout.particles.push_back({lattice_position(origin, spacing, i, j, k), kind, cell, face});
        count(layout, kind);
      }
  return layout;
}

std::size_t append_layout(FluidParticles& particles, const FluidLayout& layout) {
  const std::size_t first = particles.size();
  for (const LatticeParticle& particle : layout.particles) particles.add(particle.position, Vec3::Zero(), particle.kind);
  return first;
}

}  // namespace riffle
