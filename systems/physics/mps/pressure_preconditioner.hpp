#pragma once
// Two-level additive preconditioner for the pressure equation (numerics.md 3.5 and amendment 5 ask for more than
// Jacobi in 3D): M^-1 r = D^-1 r + P A_c^-1 P^T r, where P aggregates the unknowns by coarse cells of a few l0 and
// A_c = P^T A P is the Galerkin coarse matrix, factorised by a sparse Cholesky (each aggregate couples only to its
// neighbours, so the factor stays small: the dense factor of a few hundred aggregates cost more than the whole
// serial remainder of the solve). Jacobi alone damps
// only the short waves of the error, so CG needs iterations in proportion to the domain size in particles; the
// coarse solve removes the long waves. Symmetric positive definite whenever A is, so CG stays CG.
// Every sum runs in a fixed order, so results do not depend on the thread count.
#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <cstdint>
#include <vector>

#include "components/vec.hpp"

namespace riffle {

/// The pressure matrix M = diag + off-diagonal CSR, over `rows` unknowns (off-diagonal columns are row indices).
struct PressureMatrix {
  std::size_t rows = 0;
  const double* diagonal = nullptr;
  const std::size_t* row_start = nullptr;  ///< rows + 1
  const std::uint32_t* columns = nullptr;
  const double* values = nullptr;
};

class TwoLevelPreconditioner {
 public:
  /// Aggregates unknown `row` (at `positions[row]`) into cubic cells of edge `cell_size` anchored at `origin`, builds
  /// and factorises A_c. Returns false (and apply() is then plain Jacobi) if A_c is not positive definite.
  bool setup(const PressureMatrix& matrix, const std::vector<Vec3>& positions, const Vec3& origin, double cell_size);

  /// z = D^-1 r + P A_c^-1 P^T r.
  void apply(const std::vector<double>& residual, std::vector<double>& result);

  /// The coarse half on its own, for a CG that never stores z: solves c = A_c^-1 P^T r and returns
  /// (P^T r) . c = r . (P c), so that r . z = sum of r^2 / diag + that (0 without a coarse level).
  double solve_coarse(const std::vector<double>& residual);
  /// (P c)[row] after solve_coarse (0 without a coarse level).
  double coarse_correction(std::size_t row) const {
    return coarse_ready_ ? coarse_vector_[static_cast<Eigen::Index>(aggregate_of_[row])] : 0.0;
  }

  std::size_t coarse_size() const { return coarse_ready_ ? aggregate_count_ : 0; }

 private:
  PressureMatrix matrix_;
  std::vector<double> inverse_diagonal_;
  std::vector<std::uint32_t> aggregate_of_;      ///< row -> aggregate
  std::vector<std::uint32_t> member_start_;      ///< aggregate -> first index into members_
  std::vector<std::uint32_t> members_;           ///< rows grouped by aggregate, ascending
  std::size_t aggregate_count_ = 0;
  std::vector<std::int64_t> aggregate_of_cell_;  ///< scratch: cell of the aggregation grid -> aggregate, -1 if none
  Eigen::SparseMatrix<double> coarse_matrix_;
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>> coarse_factor_;
  Eigen::VectorXd coarse_vector_;
  Eigen::VectorXd restricted_;  ///< P^T r of the last solve_coarse
  bool coarse_ready_ = false;
};

}  // namespace riffle
