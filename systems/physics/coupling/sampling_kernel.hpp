#pragma once
// The grains' sampling kernel (docs/COUPLING.md, "A thin bed's sampling"): the Wendland kernel on R_h = r + r_e,
// optionally squeezed along z to an ellipsoid of half-axes R_h, R_h, R_v. A pair's offset d is measured in the
// metric s^2 = (dx^2 + dy^2 + (R_h/R_v)^2 dz^2), so the weight is the usual w(s) on the kernel of radius R_h and the
// cut is s < R_h: the ellipsoid lies inside the sphere of R_h, so a search of radius R_h finds every pair. With
// R_v = R_h the stretch is exactly 1 and s^2 is |d|^2 bit for bit (x * 1.0 = x).
#include <cstddef>

#include "components/vec.hpp"

namespace riffle {

/// [m] The radius of the kernel a grain samples the water with and spreads its reaction over: r + r_e, and for a
/// `dilute` grain (one the self-induced correction acts on) at least the kernel it has where l0 = r, d/l0 = 2:
/// r + (r_e / l0) max(l0, r), 1.7 d with r_e = 2.4 l0 (docs/COUPLING.md, "The kernel of a dilute grain"). Finer water
/// no longer narrows it, so a dilute grain's coupling tends to the one verified at d/l0 = 2 as l0 shrinks: with
/// r + r_e the kernel closed in on the grain (1.3 d at d/l0 = 3), the water inside it moved with the grain at up to
/// 0.9 of its speed, and the correction's estimate of that disturbance became the difference of two near-equal
/// speeds (a sphere settling in a small box swung by +-30 %). Where r <= l0 it is r + r_e exactly.
inline double coupling_kernel_radius(double radius, double effective_radius, double spacing, bool dilute) {
  if (!dilute || !(radius > spacing)) return radius + effective_radius;
  return radius + effective_radius * (radius / spacing);
}

/// R_h / min(R_v, R_h) [1], >= 1; 1 when R_v <= 0 (isotropic).
inline double sampling_vertical_stretch(double horizontal_radius, double vertical_radius) {
  return vertical_radius > 0.0 && vertical_radius < horizontal_radius ? horizontal_radius / vertical_radius : 1.0;
}

/// s^2 of an offset [m^2]: the squared distance the Wendland kernel on R_h is evaluated at.
inline double sampling_distance_squared(const Vec3& offset, double vertical_stretch) {
  // Eigen's squaredNorm, as the isotropic loops used: the same operations in the same order.
  return Vec3(offset.x(), offset.y(), offset.z() * vertical_stretch).squaredNorm();
}

/// out[k] = sampling_distance_squared((x[k], y[k], z[k]) - centre, vertical_stretch) for k < count, bit for bit, in
/// one vectorised loop (a grain's candidate particles, a run of grid cells at a time).
void squared_offsets(const double* x, const double* y, const double* z, std::size_t count, const Vec3& centre,
                     double vertical_stretch, double* out);

}  // namespace riffle
