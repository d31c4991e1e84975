#include "systems/pressure_preconditioner.hpp"

#include <tbb/parallel_for.h>

#include <cmath>
#include <unordered_map>

namespace riffle {

bool TwoLevelPreconditioner::setup(const PressureMatrix& matrix, const std::vector<Vec3>& positions, const Vec3& origin,
                                   double cell_size) {
  matrix_ = matrix;
  const std::size_t rows = matrix.rows;
  inverse_diagonal_.resize(rows);
  tbb::parallel_for(std::size_t{0}, rows, [&](std::size_t row) { inverse_diagonal_[row] = 1.0 / matrix.diagonal[row]; });

  // Aggregates numbered in order of first appearance along the rows: deterministic for a given matrix.
  aggregate_of_.resize(rows);
  std::unordered_map<std::int64_t, std::uint32_t> index_of_cell;
  index_of_cell.reserve(rows / 16 + 16);
  for (std::size_t row = 0; row < rows; ++row) {
    const Vec3 cell = ((positions[row] - origin) / cell_size).array().floor();
    const std::int64_t key = (static_cast<std::int64_t>(cell[2]) + (1 << 20)) * (std::int64_t{1} << 42) +
                             (static_cast<std::int64_t>(cell[1]) + (1 << 20)) * (std::int64_t{1} << 21) +
                             (static_cast<std::int64_t>(cell[0]) + (1 << 20));
    const auto [entry, added] = index_of_cell.try_emplace(key, static_cast<std::uint32_t>(index_of_cell.size()));
    aggregate_of_[row] = entry->second;
  }
  aggregate_count_ = index_of_cell.size();
  member_start_.assign(aggregate_count_ + 1, 0);
  for (std::size_t row = 0; row < rows; ++row) ++member_start_[aggregate_of_[row] + 1];
  for (std::size_t a = 0; a < aggregate_count_; ++a) member_start_[a + 1] += member_start_[a];
  members_.resize(rows);
  std::vector<std::uint32_t> fill(member_start_.begin(), member_start_.end() - 1);
  for (std::size_t row = 0; row < rows; ++row) members_[fill[aggregate_of_[row]]++] = static_cast<std::uint32_t>(row);

  // A_c = P^T A P, one coarse row per task.
  coarse_matrix_.setZero(static_cast<Eigen::Index>(aggregate_count_), static_cast<Eigen::Index>(aggregate_count_));
  tbb::parallel_for(std::size_t{0}, aggregate_count_, [&](std::size_t a) {
    for (std::uint32_t k = member_start_[a]; k < member_start_[a + 1]; ++k) {
      const std::size_t row = members_[k];
      coarse_matrix_(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(a)) += matrix.diagonal[row];
      for (std::size_t e = matrix.row_start[row]; e < matrix.row_start[row + 1]; ++e)
        coarse_matrix_(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(aggregate_of_[matrix.columns[e]])) +=
            matrix.values[e];
    }
  });
  coarse_factor_.compute(coarse_matrix_);
  coarse_ready_ = coarse_factor_.info() == Eigen::Success;
  coarse_vector_.resize(static_cast<Eigen::Index>(aggregate_count_));
  return coarse_ready_;
}

void TwoLevelPreconditioner::apply(const std::vector<double>& residual, std::vector<double>& result) {
  const std::size_t rows = matrix_.rows;
  if (!coarse_ready_) {
    tbb::parallel_for(std::size_t{0}, rows, [&](std::size_t row) { result[row] = residual[row] * inverse_diagonal_[row]; });
    return;
  }
  tbb::parallel_for(std::size_t{0}, aggregate_count_, [&](std::size_t a) {
    double sum = 0.0;
    for (std::uint32_t k = member_start_[a]; k < member_start_[a + 1]; ++k) sum += residual[members_[k]];
    coarse_vector_[static_cast<Eigen::Index>(a)] = sum;
  });
  coarse_factor_.solveInPlace(coarse_vector_);
  tbb::parallel_for(std::size_t{0}, rows, [&](std::size_t row) {
    result[row] = residual[row] * inverse_diagonal_[row] + coarse_vector_[static_cast<Eigen::Index>(aggregate_of_[row])];
  });
}

}  // namespace riffle
