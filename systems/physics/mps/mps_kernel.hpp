#pragma once
// MPS kernel and reference constants (numerics.md Secs. 1.1-1.2 and 2.5; seed 000 Sec. 3.1 names the kernel).
// The fifth-order Wendland (C2) kernel w(r) = (1 - r/r_e)^4 (1 + 4 r/r_e) for r < r_e; MPS operators divide by the
// reference number density n0 of the initial perfect lattice, so the kernel's normalisation does not matter.
// First piece of the fluid issue: the kernel, its derivatives and the lattice constants, verified against the
// independent lattice sums of numerics.md; the fluid systems build on it.
#include <cstdint>

namespace riffle {

struct WendlandKernel {
  double effective_radius = 0.0;  ///< [m] r_e
  double inverse_radius = 0.0;    ///< [1/m] 1 / r_e: the pair loops multiply instead of dividing

  WendlandKernel() = default;
  explicit WendlandKernel(double radius) : effective_radius(radius), inverse_radius(radius > 0.0 ? 1.0 / radius : 0.0) {}

  /// w(r) [1]
  double weight(double distance) const {
    if (distance >= effective_radius) return 0.0;
    return weight_inside(distance);
  }
  /// (1 - q)^4 (1 + 4 q), q = r / r_e: w(r) for r < r_e, unclipped (branch-free, for the batched pair loops).
  double weight_inside(double distance) const {
    const double q = distance * inverse_radius;
    const double one_minus = 1.0 - q;
    const double squared = one_minus * one_minus;
    return squared * squared * (1.0 + 4.0 * q);
  }
  /// w'(r) / r = -20 / r_e^2 (1 - q)^3 [1/m^2], finite at r = 0 (used by the HS source and the HL Laplacian).
  double derivative_over_distance(double distance) const {
    if (distance >= effective_radius) return 0.0;
    const double one_minus = 1.0 - distance * inverse_radius;
    return -20.0 * inverse_radius * inverse_radius * one_minus * one_minus * one_minus;
  }
  /// w'(r) [1/m]
  double derivative(double distance) const { return distance * derivative_over_distance(distance); }
};

/// Reference constants of an interior particle of the perfect square (2D) or cubic (3D) lattice (numerics.md 1.1).
struct LatticeConstants {
  double number_density = 0.0;     ///< n0 = sum_j w(r_ij) [1]
  std::int64_t neighbour_count = 0;  ///< N0: neighbours with w > 0
  double laplacian_lambda = 0.0;   ///< lambda0 = sum r^2 w / sum w [m^2]
  /// Bias of the HS divergence (and, equally, of the HL Laplacian with a = -2 w'/r) on the lattice:
  /// -(1/n0) sum_j w'(r_ij) r_ij / D, the factor by which both overestimate the continuum operator (numerics 2.5).
  double operator_bias = 0.0;
};

/// Lattice sums for dimension 2 or 3, particle spacing `spacing` and kernel radius `effective_radius`.
LatticeConstants lattice_constants(int dimension, double spacing, double effective_radius);

}  // namespace riffle
