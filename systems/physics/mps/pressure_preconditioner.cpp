#include "systems/physics/mps/pressure_preconditioner.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>
#include <utility>

namespace riffle {

bool TwoLevelPreconditioner::setup(const PressureMatrix& matrix, const std::vector<Vec3>& positions, const Vec3& origin,
                                   double cell_size) {
  matrix_ = matrix;
  const std::size_t rows = matrix.rows;
  inverse_diagonal_.resize(rows);
  tbb::parallel_for(std::size_t{0}, rows, [&](std::size_t row) { inverse_diagonal_[row] = 1.0 / matrix.diagonal[row]; });

  // Aggregates numbered in order of first appearance along the rows: deterministic for a given matrix. The cells
  // are looked up in a dense array over the rows' bounding box (anchored on the grid of `origin`).
  aggregate_of_.resize(rows);
  std::array<std::int64_t, 3> low{0, 0, 0}, count{1, 1, 1};
  std::vector<std::array<std::int64_t, 3>> cell_of_row(rows);
  if (rows > 0) {
    std::array<std::int64_t, 3> high{};
    for (std::size_t row = 0; row < rows; ++row) {
      for (int axis = 0; axis < 3; ++axis) {
        const double scaled = std::floor((positions[row][axis] - origin[axis]) / cell_size);
        cell_of_row[row][axis] = static_cast<std::int64_t>(std::clamp(scaled, -1.0e9, 1.0e9));
      }
      for (int axis = 0; axis < 3; ++axis) {
        low[axis] = row == 0 ? cell_of_row[row][axis] : std::min(low[axis], cell_of_row[row][axis]);
        high[axis] = row == 0 ? cell_of_row[row][axis] : std::max(high[axis], cell_of_row[row][axis]);
      }
    }
    for (int axis = 0; axis < 3; ++axis) count[axis] = high[axis] - low[axis] + 1;
  }
  const double cell_total = static_cast<double>(count[0]) * static_cast<double>(count[1]) * static_cast<double>(count[2]);
  // A stray particle far away would make the dense lookup huge; with more cells than 8 per row, hash instead.
  const bool dense_lookup = cell_total <= 8.0 * static_cast<double>(rows) + 64.0;
  std::unordered_map<std::int64_t, std::uint32_t> index_of_cell;
  if (dense_lookup) aggregate_of_cell_.assign(static_cast<std::size_t>(cell_total), -1);
  aggregate_count_ = 0;
  for (std::size_t row = 0; row < rows; ++row) {
    const std::int64_t x = cell_of_row[row][0] - low[0], y = cell_of_row[row][1] - low[1], z = cell_of_row[row][2] - low[2];
    const std::int64_t key = (z * count[1] + y) * count[0] + x;
    if (dense_lookup) {
      std::int64_t& aggregate = aggregate_of_cell_[static_cast<std::size_t>(key)];
      if (aggregate < 0) aggregate = static_cast<std::int64_t>(aggregate_count_++);
      aggregate_of_[row] = static_cast<std::uint32_t>(aggregate);
    } else {
      const auto [entry, added] = index_of_cell.try_emplace(key, static_cast<std::uint32_t>(aggregate_count_));
      if (added) ++aggregate_count_;
      aggregate_of_[row] = entry->second;
    }
  }
  member_start_.assign(aggregate_count_ + 1, 0);
  for (std::size_t row = 0; row < rows; ++row) ++member_start_[aggregate_of_[row] + 1];
  for (std::size_t a = 0; a < aggregate_count_; ++a) member_start_[a + 1] += member_start_[a];
  members_.resize(rows);
  std::vector<std::uint32_t> fill(member_start_.begin(), member_start_.end() - 1);
  for (std::size_t row = 0; row < rows; ++row) members_[fill[aggregate_of_[row]]++] = static_cast<std::uint32_t>(row);

  // A_c = P^T A P, one coarse row per task, summed in member and entry order into a scratch row, then kept sorted
  // by column: the same matrix for any thread count.
  std::vector<std::vector<std::pair<std::uint32_t, double>>> coarse_rows(aggregate_count_);
  // Per thread: where column c sits in the coarse row being summed (-1: not yet).
  tbb::enumerable_thread_specific<std::vector<std::int32_t>> scratch_rows(std::vector<std::int32_t>(aggregate_count_, -1));
  tbb::parallel_for(std::size_t{0}, aggregate_count_, [&](std::size_t a) {
    std::vector<std::int32_t>& position_of_column = scratch_rows.local();
    std::vector<std::pair<std::uint32_t, double>>& coarse_row = coarse_rows[a];
    const auto add = [&](std::uint32_t column, double value) {
      std::int32_t& position = position_of_column[column];
      if (position < 0) {
        position = static_cast<std::int32_t>(coarse_row.size());
        coarse_row.emplace_back(column, 0.0);
      }
      coarse_row[static_cast<std::size_t>(position)].second += value;
    };
    for (std::uint32_t k = member_start_[a]; k < member_start_[a + 1]; ++k) {
      const std::size_t row = members_[k];
      add(static_cast<std::uint32_t>(a), matrix.diagonal[row]);
      for (std::size_t e = matrix.row_start[row]; e < matrix.row_start[row + 1]; ++e)
        add(aggregate_of_[matrix.columns[e]], matrix.values[e]);
    }
    for (const auto& entry : coarse_row) position_of_column[entry.first] = -1;
    std::sort(coarse_row.begin(), coarse_row.end());
  });
  // No unknowns (every fluid particle on the free surface): nothing to coarsen, and Eigen cannot compress an empty
  // matrix (makeCompressed reads one entry past its empty arrays).
  if (aggregate_count_ == 0) {
    coarse_ready_ = false;
    return false;
  }
  const auto size = static_cast<Eigen::Index>(aggregate_count_);
  coarse_matrix_.resize(size, size);
  Eigen::VectorXi entries_per_column(size);
  for (std::size_t a = 0; a < aggregate_count_; ++a) entries_per_column[static_cast<Eigen::Index>(a)] = static_cast<int>(coarse_rows[a].size());
  coarse_matrix_.reserve(entries_per_column);
  // A_c is symmetric, so coarse row a is also column a.
  for (std::size_t a = 0; a < aggregate_count_; ++a)
    for (const auto& [column, value] : coarse_rows[a])
      coarse_matrix_.insert(static_cast<Eigen::Index>(column), static_cast<Eigen::Index>(a)) = value;
  coarse_matrix_.makeCompressed();
  coarse_factor_.compute(coarse_matrix_);
  coarse_ready_ = coarse_factor_.info() == Eigen::Success;
  coarse_vector_.resize(size);
  return coarse_ready_;
}

double TwoLevelPreconditioner::solve_coarse(const std::vector<double>& residual) {
  if (!coarse_ready_) return 0.0;
  restricted_.resize(static_cast<Eigen::Index>(aggregate_count_));
  tbb::parallel_for(std::size_t{0}, aggregate_count_, [&](std::size_t a) {
    double sum = 0.0;
    for (std::uint32_t k = member_start_[a]; k < member_start_[a + 1]; ++k) sum += residual[members_[k]];
    restricted_[static_cast<Eigen::Index>(a)] = sum;
  });
  coarse_vector_ = coarse_factor_.solve(restricted_);
  double dot = 0.0;  // serial: a few hundred terms in a fixed order
  for (Eigen::Index a = 0; a < restricted_.size(); ++a) dot += restricted_[a] * coarse_vector_[a];
  return dot;
}

void TwoLevelPreconditioner::apply(const std::vector<double>& residual, std::vector<double>& result) {
  solve_coarse(residual);
  tbb::parallel_for(std::size_t{0}, matrix_.rows,
                    [&](std::size_t row) { result[row] = residual[row] * inverse_diagonal_[row] + coarse_correction(row); });
}

}  // namespace riffle
