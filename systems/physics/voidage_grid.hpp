#pragma once
// The local voidage field (numerics.md 5.3, in grid form): grain volumes and fluid-particle volumes (l0^3 each, the
// quadrature of the space the water fills) are deposited on the nodes of a uniform grid with cloud-in-cell
// (trilinear) weights; the solid fraction at a node is their ratio, and a grain reads it back by trilinear
// interpolation over the nodes that hold water. The cost is linear in the particle counts (the kernel form of
// numerics 5.3 costs hundreds of grain pairs per grain at R_eps = 2 d_max), walls and the free surface truncate
// both deposits alike, and each grain sees a fraction averaged over about two cells in each direction.
// Deposits run in slot order, so the field does not depend on the thread count.
#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "components/vec.hpp"

namespace riffle {

/// Cloud-in-cell (trilinear) weights of a point on a uniform grid of nodes: the 8 corners of its cell.
struct CloudInCellStencil {
  std::array<std::size_t, 8> node;
  std::array<double, 8> weight;  ///< sum to 1
};

/// The most nodes a VoidageGrid over `points` grains and fluid particles may have: 64 per point, at least 4e6.
inline double voidage_node_limit(std::size_t points) { return std::max(64.0 * static_cast<double>(points), 4.0e6); }

class VoidageGrid {
 public:
  /// Grid of nodes spaced `cell_size` covering every point given (grains and fluid) within the box [low, high] (the
  /// domain: a point outside it has left the domain, which fails the step, and is deposited on the nearest edge node
  /// instead of stretching the grid to wherever it flew).
  void build(const std::vector<Vec3>& grain_positions, const std::vector<double>& grain_volumes,
             const std::vector<Vec3>& fluid_positions, std::size_t fluid_count, double fluid_particle_volume,
             double cell_size, const Vec3& low, const Vec3& high);

  /// Solid volume fraction at `point`: interpolated over the surrounding nodes that hold water; 0 if none does.
  double solid_fraction(const Vec3& point) const;

  /// The nodes and weights of `point` (clamped into the grid).
  CloudInCellStencil stencil(const Vec3& point) const;
  std::size_t node_count() const { return solid_.size(); }
  /// Fluid volume deposited on `node` [m^3].
  double fluid_volume(std::size_t node) const { return fluid_[node]; }

 private:
  Vec3 origin_ = Vec3::Zero();
  double cell_size_ = 1.0;
  std::array<std::int64_t, 3> nodes_{1, 1, 1};
  std::vector<double> solid_, fluid_;
};

}  // namespace riffle
