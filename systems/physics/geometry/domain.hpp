#pragma once
// The domain every particle must stay in, grains and MPS particles alike: the tank at rest, widened by the motion
// amplitude and tank.domain_margin. A grain outside it is lost (a diagnosis, never a silent drop); a fluid particle
// outside it, or flying alone far from the tank, is removed with `[fluid] escape = "remove"` (fluid_escape_kind).
#include "components/model.hpp"
#include "components/vec.hpp"

namespace riffle {

/// The box a particle centre must stay in: the tank at rest, widened by the motion amplitude and the margin.
struct DomainBox {
  Vec3 low, high;
  bool contains(const Vec3& point) const {
    return (point.array() >= low.array()).all() && (point.array() <= high.array()).all();
  }
};
DomainBox domain_box(const Model& model);
/// The box a grain's centre must stay in: domain_box, widened by one period either side along the tank's periodic
/// axes. A grain that crosses a periodic face keeps its path past it (its ghosts and pairs stay valid, ghost = owner +
/// period) until the next neighbour-list rebuild wraps it back, at most a skin and a sub-step's travel later;
/// nothing is lost through a seam, and a grain a whole period out has been thrown there by a blow-up.
DomainBox grain_domain_box(const Model& model);

/// [m] Euclidean distance from `point` to the axis-aligned box [low, high]; 0 inside or on it.
double distance_outside_box(const Vec3& low, const Vec3& high, const Vec3& point);

/// Why a fluid particle counts as escaped (systems/mps/fluid_escape.hpp).
enum class FluidEscapeKind {
  kNone,        ///< in the water, or non-finite (a bug to diagnose, never removed)
  kLeftDomain,  ///< its centre is outside the domain box
  kFlewFree,    ///< no other MPS particle within r_e (number density 0) and farther than escape_distance outside the
                ///< tank's inner box [tank_low, tank_high] (where the tank is now)
};
FluidEscapeKind fluid_escape_kind(const Vec3& position, const Vec3& velocity, double number_density,
                                  const DomainBox& domain, const Vec3& tank_low, const Vec3& tank_high,
                                  double escape_distance);

}  // namespace riffle
