#pragma once
// Fickian particle shifting for the MPS water (docs/FLUID.md, "Particle shifting"): after each step every fluid
// particle moves a little down the gradient of the particle concentration, delta r = -D grad C (Lind, Xu, Stansby &
// Rogers 2012, J. Comput. Phys. 231, 1499-1523), which keeps the arrangement near the uniform one the MPS operators
// are exact on. The pure pieces: the concentration gradient's pair term, the diffusivity D (Skillen, Lind, Stansby &
// Rogers 2013, Comput. Methods Appl. Mech. Eng. 265, 163-173: D = A h |u| dt; or Lind et al.'s constant
// D = A h^2), the cap on the shift, the free-surface projection of Khayyer, Gotoh & Shimizu 2017 (J. Comput. Phys.
// 332, 236-256, "optimized particle shifting": no normal component at and next to the free surface) and the Taylor
// correction of the velocity to the shifted position (Lind et al. 2012). Verified in
// tests/unit/systems/physics/mps/particle_shifting_test.cpp; summed over the neighbours by systems/mps/fluid_shift.*.
#include <Eigen/Core>

#include "components/vec.hpp"
#include "systems/physics/geometry/periodic_box.hpp"

namespace riffle {

/// Pair term of the concentration gradient of particle i, -(w'_ij / r_ij) r_ij with `offset` r_ij = r_j - r_i:
/// grad C_i = (1/n0) sum_j of it. C = n / n0, so grad C points toward crowded neighbours (w' < 0: the term is
/// along r_ij); the sum vanishes on the perfect lattice by symmetry, including next to a wall with its dummy layers.
inline Vec3 concentration_gradient_term(double derivative_over_distance, const Vec3& offset) {
  return -derivative_over_distance * offset;
}

/// How the shifting diffusivity D [m^2] (a length squared: it includes the step) is set.
enum class ShiftingLaw {
  kVelocity,  ///< D = A h |u_i| dt (Skillen et al. 2013): the shift scales with the step's displacement
  kConstant,  ///< D = A h^2 (Lind et al. 2012): independent of the flow
};

/// D [m^2] for a particle at `speed` [m/s] over a step `dt` [s]; `smoothing_length` h = r_e / 2 (the Wendland C2
/// kernel's support is 2 h).
double shifting_diffusivity(ShiftingLaw law, double coefficient, double smoothing_length, double speed, double dt);

/// delta r = -D grad C, shortened (direction kept) to at most `max_length` [m] so that no shift carries a particle
/// through the DS distance into a neighbour or a wall.
Vec3 fickian_shift(double diffusivity, const Vec3& concentration_gradient, double max_length);

/// The shift without its component along the unit `normal` (Khayyer et al. 2017's free-surface treatment):
/// (I - n n^T) delta r; a zero normal leaves the shift unchanged.
Vec3 tangential_shift(const Vec3& shift, const Vec3& normal);

/// The shift without its component toward a wall or dummy particle at `offset` (r_j - r_i), when it has one: a
/// shift never brings a fluid particle closer to a wall particle that is already near (fluid_shift's guard).
Vec3 shift_off_wall(const Vec3& shift, const Vec3& offset);

/// The velocity carried to the shifted position, u + (delta r . grad) u to first order (Lind et al. 2012), with
/// `velocity_gradient`(a, b) = d u_a / d x_b.
inline Vec3 shifted_velocity(const Vec3& velocity, const Eigen::Matrix3d& velocity_gradient, const Vec3& shift) {
  return velocity + velocity_gradient * shift;
}

/// A particle's displacement `difference` (a later position less an earlier one) with whole periods taken off along
/// the periodic axes: the correction wraps r^{k+1} into the period while r* may lie outside it, and shifting needs
/// the small step between them.
Vec3 nearest_image_difference(const PeriodicBox& box, const Vec3& difference);

}  // namespace riffle
