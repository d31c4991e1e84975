#pragma once
// MPS particle operators (numerics.md Sec. 2; seed 000 Eqs. 4-12), written once as the per-pair terms and the
// per-particle closures that the fluid systems sum in their pair loops (each system fuses several operators in one
// walk over a particle's neighbours, so the sums stay in the systems and the terms live here). Verified on lattices
// in tests/unit/systems/physics/mps/mps_operators_test.cpp, which sums these same functions over the pair geometry of fluid_pair_batch.
#include <Eigen/Core>

#include "components/vec.hpp"

namespace riffle {

/// HS source term of pair ij, share (w'_ij / r_ij) r_ij . u_ij (seed Eq. 5: (1/n0) Dn/Dt = -div u in the continuum),
/// with share 1 for a fluid neighbour and 2 for a wall or dummy one (it stands for its mirror image too).
/// `offset` = r_j - r_i, `relative_velocity` = u_j - u_i.
inline double density_rate_term(bool fluid_partner, double derivative_over_distance, const Vec3& offset,
                                const Vec3& relative_velocity) {
  const double share = fluid_partner ? 1.0 : 2.0;
  return share * derivative_over_distance * offset.dot(relative_velocity);
}

/// HL Laplacian coefficient with the HS-consistent closure a_ij = -2 w'_ij / r_ij (numerics 2.5):
/// <lap p>_i = (1/n0) sum_j a_ij (p_j - p_i).
inline double laplacian_coefficient(double derivative_over_distance) { return -2.0 * derivative_over_distance; }

/// Term of pair ij of the gradient sum, (p_j - p_base) (w_ij / r_ij^2) r_ij (seed Eq. 8); the gradient is
/// (D / n0) C_i times the sum (C_i from gradient_correction_matrix, or the identity without correction).
inline Vec3 gradient_term(double pressure_difference, double weight_over_squared, const Vec3& offset) {
  return (pressure_difference * weight_over_squared) * offset;
}

/// The GC moment sum_j (w_ij / r_ij^2) r_ij r_ij^T (symmetric: six entries) and n_i = sum_j w_ij of one particle.
struct GradientMoment {
  double xx = 0.0, xy = 0.0, xz = 0.0, yy = 0.0, yz = 0.0, zz = 0.0;
  double density = 0.0;

  void add(double weight, double weight_over_squared, const Vec3& offset) {
    const Vec3 scaled = weight_over_squared * offset;
    xx += scaled[0] * offset[0];
    xy += scaled[0] * offset[1];
    xz += scaled[0] * offset[2];
    yy += scaled[1] * offset[1];
    yz += scaled[1] * offset[2];
    zz += scaled[2] * offset[2];
    density += weight;
  }
  Eigen::Matrix3d matrix() const {
    Eigen::Matrix3d moment;
    moment << xx, xy, xz, xy, yy, yz, xz, yz, zz;
    return moment;
  }
};

/// GC matrix C_i = (1/D) A_i^{-1}, A_i = (1/n0) sum_j (r_ij r_ij^T / r_ij^2) w_ij (seed Eqs. 8-9), with the
/// inversion safety of numerics 2.6: the identity when n_i < 0.5 n0, det(D A_i) < 0.05 (3D) or the smallest
/// eigenvalue of D A_i < 0.2.
Eigen::Matrix3d gradient_correction_matrix(const GradientMoment& moment, double reference_density);

/// Term of pair ij of the DS velocity correction (numerics 2.7, repulsive sign, simplest reading s = d - r), for a
/// neighbour closer than `stabilisation_distance`: -(partner_share (d - r) (w_ij / r_ij^2) r_ij) r_ij, to be summed
/// and divided by n0 dt. partner_share = rho_j / (rho_i + rho_j): 1/2 between fluid particles, 1 against a wall.
inline Vec3 stabilisation_term(double partner_share, double stabilisation_distance, double distance,
                               double weight_over_squared, const Vec3& offset) {
  return -((partner_share * (stabilisation_distance - distance) * weight_over_squared * distance) * offset);
}

}  // namespace riffle
