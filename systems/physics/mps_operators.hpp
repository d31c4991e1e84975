#pragma once
// MPS particle operators (numerics.md Sec. 2; seed 000 Eqs. 4-12) in gather form: each evaluates one particle i
// from its neighbour list, so the fluid systems can run them in parallel loops that write only slot i.
// Second piece of the fluid issue after the kernel; verified on lattices in tests/unit/mps_operators_test.cpp.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "components/vec.hpp"
#include "systems/physics/mps_kernel.hpp"

namespace riffle {

/// Neighbour slots of one particle (excluding itself).
struct NeighbourSpan {
  const std::uint32_t* begin;
  const std::uint32_t* end;
};

/// n_i = sum_j w(r_ij)  (numerics 1.1)
double number_density(const Vec3& position, const std::vector<Vec3>& positions, NeighbourSpan neighbours,
                      const WendlandKernel& kernel);

/// HS source (Dn/Dt)_i = sum_j (w'_ij / r_ij) r_ij . u_ij  (seed Eq. 5); (1/n0) Dn/Dt = -div u in the continuum.
double number_density_rate(const Vec3& position, const Vec3& velocity, const std::vector<Vec3>& positions,
                           const std::vector<Vec3>& velocities, NeighbourSpan neighbours,
                           const WendlandKernel& kernel);

/// HL Laplacian with the HS-consistent closure a_ij = -2 w'_ij / r_ij (numerics 2.5):
/// <lap p>_i = (1/n0) sum_j a_ij (p_j - p_i).
double laplacian(const Vec3& position, double value, const std::vector<Vec3>& positions,
                 const std::vector<double>& values, NeighbourSpan neighbours, const WendlandKernel& kernel,
                 double reference_density);

/// GC matrix C_i = (1/D) A_i^{-1}, A_i = (1/n0) sum_j (r_ij r_ij^T / r_ij^2) w_ij (seed Eqs. 8-9), with the
/// inversion safety of numerics 2.6: the identity when n_i < 0.5 n0, det(D A_i) < 0.05 (3D) or the smallest
/// eigenvalue of D A_i < 0.2.
Eigen::Matrix3d gradient_correction(const Vec3& position, const std::vector<Vec3>& positions, NeighbourSpan neighbours,
                                    const WendlandKernel& kernel, double reference_density);

/// GC gradient <grad p>_i = (D/n0) sum_j (p_j - p_i)/r_ij^2 (C_i r_ij) w_ij (seed Eq. 8), 3D.
Vec3 corrected_gradient(const Vec3& position, double value, const Eigen::Matrix3d& correction,
                        const std::vector<Vec3>& positions, const std::vector<double>& values,
                        NeighbourSpan neighbours, const WendlandKernel& kernel, double reference_density);

/// DS velocity correction (numerics 2.7, repulsive sign, simplest reading s = d - r): for every neighbour closer
/// than `stabilisation_distance`, -(1/n0) (rho_j / (rho_i + rho_j)) (s / dt) w_ij r_hat_ij; equal densities give
/// the factor 1/2 (pass `wall` neighbours' factor 1 by listing them separately).
Vec3 stabilisation_velocity(const Vec3& position, const std::vector<Vec3>& positions, NeighbourSpan neighbours,
                            const WendlandKernel& kernel, double reference_density, double stabilisation_distance,
                            double partner_share, double dt);

}  // namespace riffle
