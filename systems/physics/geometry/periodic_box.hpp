#pragma once
// The geometry of a periodic box (docs/ARCHITECTURE.md, "Periodic boundaries and the halo"): along a periodic axis
// the tank has no walls and a particle leaving through one face comes back through the other; the period is the
// tank's size along that axis. Pure functions: wrap a position into the box, list the image shifts of a point near
// the seam, and build a halo (components/halo.hpp) of the reals within a cutoff of a seam.
#include <array>
#include <vector>

#include "components/halo.hpp"
#include "components/model.hpp"
#include "components/vec.hpp"

namespace riffle {

struct PeriodicBox {
  Vec3 low = Vec3::Zero();     ///< [m] the box's min corner (the tank's origin)
  Vec3 length = Vec3::Zero();  ///< [m] the periods (the tank's size)
  std::array<bool, 3> periodic{false, false, false};

  bool any() const { return periodic[0] || periodic[1] || periodic[2]; }
  /// Whether `point` lies in [low, low + length) along every periodic axis (other axes are not judged).
  bool inside(const Vec3& point) const;
  /// `point` moved by whole periods into [low, low + length) along each periodic axis; other axes unchanged.
  /// Non-finite coordinates are returned as they are (the domain check diagnoses them).
  Vec3 wrap(const Vec3& point) const;
  /// The non-zero shifts s (sums of +-length along periodic axes) such that point + s lies within `cutoff` of the
  /// box, i.e. the images a neighbour search within `cutoff` can meet, in a fixed order (x before y, + before -).
  /// `point` must be inside the box, or less than length - cutoff past a face (a grain between a seam crossing and
  /// the rebuild that wraps it: past the high face the shift is -length, past the low one +length), and the period
  /// longer than 2 cutoff (periodic_cutoff_fits), so that at most one image per axis qualifies: at most 3.
  int image_shifts(const Vec3& point, double cutoff, std::array<Vec3, 3>& shifts) const;
};

PeriodicBox periodic_box(const Model& model);

/// Every shift by -1, 0 or +1 period along each periodic axis, the zero shift first (one element without periodic
/// axes): the images a decomposed run's ghosts may be (systems/physics/ranks/).
std::vector<Vec3> periodic_image_shifts(const PeriodicBox& box);

/// Whether every period exceeds 2 cutoff: then a particle meets at most one image of another, never its own, and
/// each pair across the seam is seen once from each side.
bool periodic_cutoff_fits(const PeriodicBox& box, double cutoff);

/// [m] How far the farthest of `positions` lies beyond a periodic face of `box` (0 when every one is inside; non-finite
/// coordinates are left out): the fluid's r* may lie a step's travel past a face before fluid_correct wraps it, and a
/// halo built there must reach that much further (a particle δ past the high face meets the images of particles up to
/// cutoff + δ from the low one).
double periodic_overshoot(const std::vector<Vec3>& positions, const PeriodicBox& box);

/// Builds `halo` for `positions` (inside the box, or less than `cutoff` beyond a periodic face, where image_shifts
/// still gives the one image back inside: the fluid's r*): for each real within `cutoff` of a periodic face, one ghost
/// per image image_shifts lists, ordered by owner slot then image: a pure function of the positions, so a resumed
/// run rebuilds the same halo from the positions it was built at.
void build_halo(const std::vector<Vec3>& positions, const std::vector<EntityId>& ids, const PeriodicBox& box,
                double cutoff, Halo& halo);

}  // namespace riffle
