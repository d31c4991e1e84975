#pragma once
// The local voidage field (numerics.md 5.3, in grid form): grain volumes and fluid-particle volumes (l0^3 each, the
// quadrature of the space the water fills) are deposited on the nodes of a uniform grid with cloud-in-cell
// (trilinear) weights; the solid fraction at a node is their ratio, and a grain reads it back by trilinear
// interpolation over the nodes that hold water. The cost is linear in the particle counts (the kernel form of
// numerics 5.3 costs hundreds of grain pairs per grain at R_eps = 2 d_max), walls and the free surface truncate
// both deposits alike, and each grain sees a fraction averaged over about two cells in each direction (three once
// smooth() has run). Deposits run in slot order, so the field does not depend on the thread count.
#include <algorithm>
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "components/vec.hpp"
#include "systems/physics/geometry/periodic_box.hpp"

namespace riffle {

/// The voidage grid's cell width over the averaging radius R_eps: the self-corrected estimate (smoothed) and the
/// trilinear cloud-in-cell one ((2 pi / 21)^(1/3)). The grains' voidage and the scene's budget both size the grid
/// from it.
inline constexpr double kSmoothVoidageCell = 0.668, kCloudInCellVoidageCell = 0.668;
inline constexpr double voidage_cell_ratio(bool self_corrected) {
  return self_corrected ? kSmoothVoidageCell : kCloudInCellVoidageCell;
}

/// Cloud-in-cell (trilinear) weights of a point on a uniform grid of nodes: the 8 corners of its cell.
struct CloudInCellStencil {
  std::array<std::size_t, 8> node;
  std::array<double, 8> weight;  ///< sum to 1
  std::array<double, 3> fraction;  ///< the point's place in its cell along each axis, [0, 1]: corner bit 1's weight
};

/// A grain's solid fraction read back at its own centre: all grains' deposits, and its own deposit alone
/// (read the same way), so `included - own` is the fraction of the other grains (systems/coupling/solid_voidage.hpp).
struct GrainSolidFraction {
  double included = 0.0;  ///< [1] every grain's volume, the grain's own included; 0 where no node around holds water
  double own = 0.0;       ///< [1] the grain's own volume alone
};

/// Hard spheres' structure factor at zero wavenumber, S(0) = (1 - phi)^4 / (1 + 4 phi + 4 phi^2 - 4 phi^3 + phi^4)
/// (the Carnahan-Starling compressibility, Carnahan & Starling 1969): 1 for a dilute suspension, 0.006 at phi = 0.6.
/// phi is clamped to [0, 1].
double hard_sphere_structure_factor(double solid_fraction);

/// The self-corrected solid fraction at a grain (docs/COUPLING.md, "The voidage at a grain"): the other grains'
/// fraction `others` plus the grain's own `own` times 1 - S(0) at the result (three fixed-point iterations from
/// `others`). The expected kernel sum over the other grains of a random arrangement is phi - own (1 - S(0)): a
/// grain's neighbours are missing from its excluded volume. A lone grain (others = 0) reads 0 exactly.
double self_corrected_solid_fraction(double others, double own);

/// The most nodes a VoidageGrid over `points` grains and fluid particles may have: 64 per point, at least 4e6.
inline double voidage_node_limit(std::size_t points) { return std::max(64.0 * static_cast<double>(points), 4.0e6); }

class VoidageGrid {
 public:
  /// Grid of nodes spaced `cell_size` covering every point given (grains and fluid) within the box [low, high] (the
  /// domain: a point outside it has left the domain, which fails the step, and is deposited on the nearest edge node
  /// instead of stretching the grid to wherever it flew). Along a periodic axis of `box` the grid wraps: it spans
  /// the period with n = max(4, floor(period / cell_size)) cells of period / n (so slightly larger than asked),
  /// node n is node 0, and the deposits, the smoothing and the read back run across the seam (docs/COUPLING.md);
  /// other axes are as without a period.
  void build(std::span<const Vec3> grain_positions, std::span<const double> grain_volumes,
             std::span<const Vec3> fluid_positions, std::size_t fluid_count, double fluid_particle_volume,
             double cell_size, const Vec3& low, const Vec3& high, const PeriodicBox& box = PeriodicBox{});
  /// The same with a cell size per axis (a voidage kernel narrower across a bed than along it).
  void build(std::span<const Vec3> grain_positions, std::span<const double> grain_volumes,
             std::span<const Vec3> fluid_positions, std::size_t fluid_count, double fluid_particle_volume,
             const Vec3& cell_size, const Vec3& low, const Vec3& high, const PeriodicBox& box = PeriodicBox{});

  /// The same from lists (a brace list included).
  void build(const std::vector<Vec3>& grain_positions, const std::vector<double>& grain_volumes,
             const std::vector<Vec3>& fluid_positions, std::size_t fluid_count, double fluid_particle_volume,
             double cell_size, const Vec3& low, const Vec3& high, const PeriodicBox& box = PeriodicBox{}) {
    build(std::span<const Vec3>(grain_positions), std::span<const double>(grain_volumes),
          std::span<const Vec3>(fluid_positions), fluid_count, fluid_particle_volume, cell_size, low, high, box);
  }
  void build(const std::vector<Vec3>& grain_positions, const std::vector<double>& grain_volumes,
             const std::vector<Vec3>& fluid_positions, std::size_t fluid_count, double fluid_particle_volume,
             const Vec3& cell_size, const Vec3& low, const Vec3& high, const PeriodicBox& box = PeriodicBox{}) {
    build(std::span<const Vec3>(grain_positions), std::span<const double>(grain_volumes),
          std::span<const Vec3>(fluid_positions), fluid_count, fluid_particle_volume, cell_size, low, high, box);
  }

  /// From the next build on, the nodes lie on the lattice that starts from `low` (whole cells from it, the grid
  /// starting at the last of them at or below the points' lowest corner) instead of starting at the points' lowest
  /// corner: over MPI ranks each rank holds only the points near its boxes, and its nodes must lie where one grid
  /// over every rank's points puts them (coupling_ranks.hpp, lowest_corner_over_ranks), to rounding.
  void anchor_lattice(const Vec3& low) { anchor_ = low; }

  /// Replaces the fluid deposit by the volume of the box [low, high] each node's weight covers (docs/COUPLING.md,
  /// "A thin bed's voidage"): exactly what a fluid filling the box with a fine quadrature would deposit, without the
  /// aliasing of the water's lattice against cells narrower than a few l0. For water that fills the box around the
  /// grains (a sealed box, a bed well under the free surface). Call after build, before smooth.
  void fill_box_volume(const Vec3& low, const Vec3& high);

  /// Solid volume fraction at `point`: interpolated over the surrounding nodes that hold water; 0 if none does.
  double solid_fraction(const Vec3& point) const;

  /// Smooths both deposits with one binomial (1/4, 1/2, 1/4) pass along each axis: the kernel of deposit, filter and
  /// read back becomes a smooth bump (a quadratic-spline-like filter between two trilinear ones) instead of a tent
  /// whose peak is wherever a node falls. Call once, after build; the deposits stay on the grid (the build leaves a
  /// free node at each end of every axis).
  void smooth();

  /// The solid fraction at the centre `point` of a grain of `volume`, and that grain's own share of it (its deposit
  /// alone, through the same weights, smoothing and read back; exact up to rounding).
  GrainSolidFraction grain_fraction(const Vec3& point, double volume) const;

  /// The nodes and weights of `point` (clamped into the grid).
  CloudInCellStencil stencil(const Vec3& point) const;
  std::size_t node_count() const { return solid_.size(); }
  /// Fluid volume deposited on `node` [m^3].
  double fluid_volume(std::size_t node) const { return fluid_[node]; }

 private:
  std::optional<Vec3> anchor_;  ///< anchor_lattice's corner, if set
  Vec3 origin_ = Vec3::Zero();
  std::array<double, 3> cell_{1.0, 1.0, 1.0};  ///< per axis: the cell asked for, or period / n along a periodic axis
  std::array<bool, 3> wraps_{false, false, false};
  std::array<std::int64_t, 3> nodes_{1, 1, 1};
  bool smoothed_ = false;
  std::vector<double> solid_, fluid_;
};

}  // namespace riffle
