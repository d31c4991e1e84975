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
#include <functional>
#include <utility>
#include <vector>

#include "components/vec.hpp"

namespace riffle {

/// The pressure matrix M = diag + off-diagonal CSR, over `rows` unknowns (off-diagonal columns are row indices; over
/// MPI ranks, columns from `rows` on are the ghosts' entries).
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

  /// How the coarse level reaches the other MPI ranks. gather: every rank's vector concatenated in rank order, on every
  /// rank, given every rank's length or none (ranks::gather_all). refresh_ghosts: x[rows + g] set to the entry x[row]
  /// its owner holds for ghost column g.
  using Gather = std::function<std::vector<double>(const std::vector<double>&, const std::vector<std::size_t>&)>;
  struct RankLinks {
    Gather gather;
    std::function<void(std::vector<double>&)> refresh_ghosts;
    std::size_t rank = 0;  ///< this rank's place in gather's order
  };
  /// Over MPI ranks: `matrix` is this rank's rows, its columns past `rows` the ghosts' (one per ghost entry). Each
  /// rank aggregates its own rows as setup() does; the coarse matrix spans every rank's aggregates (numbered in rank
  /// order), gathered and factorised on every rank alike, so the coarse correction reaches across the ranks'
  /// boundaries and the preconditioner is the one-rank one's over the whole domain (a block-Jacobi coarse level per
  /// rank lets the iterations grow with the rank count). `ghost_columns` is the number of ghost entries. Returns
  /// false on every rank alike if A_c is not positive definite.
  bool setup_over_ranks(const PressureMatrix& matrix, std::size_t ghost_columns, const std::vector<Vec3>& positions,
                        const Vec3& origin, double cell_size, const RankLinks& links);

  /// z = D^-1 r + P A_c^-1 P^T r.
  void apply(const std::vector<double>& residual, std::vector<double>& result);

  /// The coarse half on its own, for a CG that never stores z: solves c = A_c^-1 P^T r and returns
  /// (P^T r) . c = r . (P c), so that r . z = sum of r^2 / diag + that (0 without a coarse level). Over ranks, this
  /// rank's aggregates' share of it: the ranks' shares add up to the whole.
  double solve_coarse(const std::vector<double>& residual);
  /// (P c)[row] after solve_coarse (0 without a coarse level).
  double coarse_correction(std::size_t row) const {
    return coarse_ready_ ? coarse_vector_[static_cast<Eigen::Index>(first_aggregate_ + aggregate_of_[row])] : 0.0;
  }

  /// The coarse level's unknowns (over ranks, all the ranks' aggregates).
  std::size_t coarse_size() const { return coarse_ready_ ? static_cast<std::size_t>(coarse_vector_.size()) : 0; }

 private:
  /// Keeps `matrix` and its inverse diagonal, and groups its rows into the cells of edge `cell_size` anchored at
  /// `origin` (aggregate_of_, members_).
  void take_rows(const PressureMatrix& matrix, const std::vector<Vec3>& positions, const Vec3& origin, double cell_size);
  /// Builds A_c from the coarse rows of every aggregate (columns sorted) and factorises it.
  bool factorise(const std::vector<std::vector<std::pair<std::uint32_t, double>>>& coarse_rows);

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
  std::size_t first_aggregate_ = 0;  ///< over ranks: the global number of this rank's first aggregate
  Gather gather_;                              ///< over ranks (else empty)
  std::vector<std::size_t> aggregate_counts_;  ///< over ranks: each rank's aggregates
  std::vector<double> own_restricted_;         ///< over ranks: P^T r over this rank's aggregates, to be gathered
};

}  // namespace riffle
