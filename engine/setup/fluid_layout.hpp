#pragma once
// Initial MPS particle layouts on one cubic lattice of spacing l0 (numerics.md Secs. 1.1 and 3.1): pure functions
// that place fluid particles in a box and the wall and dummy particles of a box tank; `append_layout` adds them to
// a FluidParticles component.
//
// The lattice is cell-centred on the tank's inner min corner: lattice cell (i, j, k) has its particle at
// origin + (i + 1/2, j + 1/2, k + 1/2) l0, so fluid cells 0 .. n-1 put the first fluid layer l0/2 inside each
// wall, the wall layer (cell -1 or n) l0/2 outside it, and ceil(r_e/l0) - 1 dummy layers behind. Fluid and walls
// of one tank therefore share one perfect lattice, and every interior particle sees the lattice constants n0.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "components/fluid.hpp"
#include "components/model.hpp"

namespace riffle {

struct LatticeParticle {
  Vec3 position;                      ///< [m]
  FluidKind kind = FluidKind::kFluid;
  std::array<std::int64_t, 3> cell{};  ///< integer lattice coordinates (i, j, k)
  std::int32_t face = -1;             ///< wall and dummy: index into kTankFaceNames of the face owning it; fluid: -1
};

struct FluidLayout {
  std::vector<LatticeParticle> particles;  ///< in (k, j, i) lexicographic order of the lattice cells
  std::size_t fluid = 0, wall = 0, dummy = 0;  ///< counts per kind
};

/// Number of dummy layers behind the wall layer: ceil(r_e / l0) - 1 (numerics 3.1), so that a fluid particle on
/// the wall sees full support: 2 for r_e = 2.6 l0, 3 for r_e = 3.1 l0. A ratio within 1e-9 of an integer counts
/// as that integer (w(r_e) = 0, so a layer at exactly r_e adds nothing).
std::int64_t dummy_layer_count(double spacing, double effective_radius);

/// The lattice cells whose centres lie in the box [low, high] (to 1e-9 l0): cells first[a] .. last[a] along axis
/// a. Scenes check boxes with it (emptiness, overlaps) before any particle is placed.
struct LatticeRange {
  std::array<std::int64_t, 3> first{}, last{};
  bool empty() const { return last[0] < first[0] || last[1] < first[1] || last[2] < first[2]; }
  bool overlaps(const LatticeRange& other) const;
};
LatticeRange lattice_range(const Vec3& lattice_origin, const Vec3& low, const Vec3& high, double spacing);

/// Fluid particles on the lattice anchored at `lattice_origin` whose centres lie in the box [low, high] (to 1e-9
/// l0). With low = lattice_origin and high - low = n l0 this is n_x n_y n_z particles, the first layer l0/2 from
/// each face of the box.
FluidLayout fluid_box_layout(const Vec3& lattice_origin, const Vec3& low, const Vec3& high, double spacing);

/// The particles of one scene box as a regular grid: centres first + (i, j, k) l0 for i < count[0], j < count[1],
/// k < count[2]. Snapped (fit_extent = false): the tank lattice's cells of lattice_range, so that a box is exactly
/// fluid_box_layout's particles. Fit to its extent (fit_extent = true): n_a = max(1, round(size_a / l0)) particles
/// at spacing l0 along axis a, placed per axis by the first rule that applies:
///   - the low face lies on a face of the tank lattice (origin + i l0, to 1e-9 l0): first centre low + l0/2, so a
///     box standing on the floor or against a wall keeps the tank lattice's l0 gap to the wall layer; the high face
///     of the particles' cells is within l0/2 of the given one;
///   - else the high face does: last centre high - l0/2, the low face within l0/2;
///   - else centred: the cells' faces are each within l0/4 of the given ones (a box thinner than l0/2 gets one
///     particle, its faces (l0 - size)/2 < l0/2 out).
/// The spacing stays l0 (the number density of the box's interior is the lattice's n0); for a size of at least l0/2
/// the cells n l0 differ from it by at most l0/2 in all, and each face by at most l0/2 (a thinner box is one layer
/// of l0, its anchored face exact, the other l0 - size out).
struct BoxGrid {
  Vec3 first = Vec3::Zero();              ///< [m] the centre of particle (0, 0, 0)
  std::array<std::int64_t, 3> count{};    ///< particles per axis (all >= 1 unless the box is empty)
  double spacing = 0.0;                   ///< [m] l0
  bool empty() const { return count[0] < 1 || count[1] < 1 || count[2] < 1; }
  double size() const { return static_cast<double>(count[0]) * static_cast<double>(count[1]) * static_cast<double>(count[2]); }
};
BoxGrid box_grid(const Vec3& lattice_origin, const Vec3& low, const Vec3& high, double spacing, bool fit_extent);

/// The smallest distance between a particle of `a` and one of `b` (both of the same spacing), exact and O(1): the
/// grids are Cartesian products, so the squared distance separates into per-axis minima of |c + k l0| over the
/// integer offsets k the two index ranges allow. Two snapped boxes share a lattice point exactly when it is 0 (and
/// are otherwise at least l0 apart), so "closer than l0/2" is the geometric form of "they share lattice points".
double grid_distance(const BoxGrid& a, const BoxGrid& b);

/// The particles of `grid`, all of `kind`, in (k, j, i) order; `cell` is the nearest cell of the tank lattice
/// anchored at `lattice_origin` (exact for a snapped box).
FluidLayout grid_layout(const BoxGrid& grid, const Vec3& lattice_origin, FluidKind kind);

/// Wall and dummy particles of a box tank with inner min corner `origin` and inner size `size` (each an integer
/// multiple of l0 to 1e-6, otherwise std::invalid_argument). Every closed face gets one wall layer at l0/2 outside
/// the inner boundary and dummy_layer_count() dummy layers behind it; open faces (names of kTankFaceNames) get
/// none, and the walls of the other faces stop at the open face. Edges and corners are filled too: a particle's
/// kind comes from its depth (the largest number of layers it lies outside the inner box along any axis: 1 =
/// wall, more = dummy), its face is the first closed face it lies beyond. Each lattice cell of the shell is
/// visited once, so there are no duplicates by construction. Closed form, with L_a^- and L_a^+ the layers (0 if
/// the face is open) and n_a = size_a / l0: count(L) = prod_a (n_a + L_a^- + L_a^+) - prod_a n_a, walls are
/// count(1), dummies count(1 + dummy layers) - count(1).
/// Along a `periodic` axis ([tank] periodic) neither face gets a layer, as if both were open: the water there meets
/// the images of the water across the seam (the halo, docs/ARCHITECTURE.md), and the shell of the other faces runs
/// the whole period, so that it too joins its images across the seam without a gap (the size is whole cells).
FluidLayout tank_wall_layout(const Vec3& origin, const Vec3& size, const std::vector<std::string>& open_faces,
                             double spacing, double effective_radius,
                             const std::array<bool, 3>& periodic = {false, false, false});

/// Appends every particle of `layout` at rest to `particles`, in layout order; returns the first new slot.
std::size_t append_layout(FluidParticles& particles, const FluidLayout& layout);

}  // namespace riffle
