#include "systems/physics/mps/pressure_preconditioner.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>
#include <utility>

namespace riffle {

void TwoLevelPreconditioner::take_rows(const PressureMatrix& matrix, const std::vector<Vec3>& positions,
                                       const Vec3& origin, double cell_size) {
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
}

namespace {

using CoarseRow = std::vector<std::pair<std::uint32_t, double>>;

/// The coarse rows of aggregates [0, aggregates) (members in member_start/members), row a of A_c = P^T A P summed in
/// member and entry order into a scratch row, then sorted by column: the same for any thread count. `coarse_column`
/// maps a row or ghost column of the matrix to its coarse column; `own_column(a)` is aggregate a's own.
template <typename CoarseColumn, typename OwnColumn>
std::vector<CoarseRow> coarse_rows_of(const PressureMatrix& matrix, const std::vector<std::uint32_t>& member_start,
                                      const std::vector<std::uint32_t>& members, std::size_t aggregates,
                                      std::size_t coarse_columns, CoarseColumn coarse_column, OwnColumn own_column) {
  std::vector<CoarseRow> coarse_rows(aggregates);
  // Per thread: where column c sits in the coarse row being summed (-1: not yet).
  tbb::enumerable_thread_specific<std::vector<std::int32_t>> scratch_rows(std::vector<std::int32_t>(coarse_columns, -1));
  tbb::parallel_for(std::size_t{0}, aggregates, [&](std::size_t a) {
    std::vector<std::int32_t>& position_of_column = scratch_rows.local();
    CoarseRow& coarse_row = coarse_rows[a];
    const auto add = [&](std::uint32_t column, double value) {
      std::int32_t& position = position_of_column[column];
      if (position < 0) {
        position = static_cast<std::int32_t>(coarse_row.size());
        coarse_row.emplace_back(column, 0.0);
      }
      coarse_row[static_cast<std::size_t>(position)].second += value;
    };
    for (std::uint32_t k = member_start[a]; k < member_start[a + 1]; ++k) {
      const std::size_t row = members[k];
      add(own_column(a), matrix.diagonal[row]);
      for (std::size_t e = matrix.row_start[row]; e < matrix.row_start[row + 1]; ++e)
        add(coarse_column(matrix.columns[e]), matrix.values[e]);
    }
    for (const auto& entry : coarse_row) position_of_column[entry.first] = -1;
    std::sort(coarse_row.begin(), coarse_row.end());
  });
  return coarse_rows;
}

}  // namespace

bool TwoLevelPreconditioner::setup(const PressureMatrix& matrix, const std::vector<Vec3>& positions, const Vec3& origin,
                                   double cell_size) {
  first_aggregate_ = 0;
  gather_ = nullptr;
  take_rows(matrix, positions, origin, cell_size);
  return factorise(coarse_rows_of(
      matrix, member_start_, members_, aggregate_count_, aggregate_count_,
      [&](std::uint32_t column) { return aggregate_of_[column]; },
      [](std::size_t a) { return static_cast<std::uint32_t>(a); }));
}

bool TwoLevelPreconditioner::setup_over_ranks(const PressureMatrix& matrix, std::size_t ghost_columns,
                                              const std::vector<Vec3>& positions, const Vec3& origin, double cell_size,
                                              const RankLinks& links) {
  gather_ = links.gather;
  take_rows(matrix, positions, origin, cell_size);
  const std::size_t rows = matrix.rows;

  // The aggregates numbered over all the ranks in rank order.
  const std::vector<double> counts = gather_({static_cast<double>(aggregate_count_)}, {});
  aggregate_counts_.resize(counts.size());
  std::size_t total = 0;
  for (std::size_t r = 0; r < counts.size(); ++r) {
    if (r == links.rank) first_aggregate_ = total;
    aggregate_counts_[r] = static_cast<std::size_t>(counts[r]);
    total += aggregate_counts_[r];
  }
  // Each ghost column's aggregate, as its owner numbered it (exact in a double below 2^53).
  std::vector<double> global_aggregate(rows + ghost_columns, 0.0);
  for (std::size_t row = 0; row < rows; ++row)
    global_aggregate[row] = static_cast<double>(first_aggregate_ + aggregate_of_[row]);
  links.refresh_ghosts(global_aggregate);
  std::vector<std::uint32_t> aggregate_of_column(global_aggregate.size());
  for (std::size_t column = 0; column < global_aggregate.size(); ++column)
    aggregate_of_column[column] = static_cast<std::uint32_t>(global_aggregate[column]);
  const std::vector<CoarseRow> own_rows = coarse_rows_of(
      matrix, member_start_, members_, aggregate_count_, total,
      [&](std::uint32_t column) { return aggregate_of_column[column]; },
      [&](std::size_t a) { return static_cast<std::uint32_t>(first_aggregate_ + a); });

  // Every rank's coarse rows, flattened as (entries, column, value, column, value, ...) per row, gathered in rank
  // order: every rank assembles and factorises the same A_c.
  std::vector<double> flat;
  for (const CoarseRow& row : own_rows) {
    flat.push_back(static_cast<double>(row.size()));
    for (const auto& [column, value] : row) {
      flat.push_back(static_cast<double>(column));
      flat.push_back(value);
    }
  }
  const std::vector<double> all = gather_(flat, {});
  std::vector<CoarseRow> coarse_rows(total);
  std::size_t at = 0;
  for (CoarseRow& row : coarse_rows) {
    const auto entries = static_cast<std::size_t>(all.at(at++));
    row.reserve(entries);
    for (std::size_t e = 0; e < entries; ++e, at += 2)
      row.emplace_back(static_cast<std::uint32_t>(all.at(at)), all.at(at + 1));
  }
  // The same A_c on every rank factorises alike; the flags are still gathered, so that a rank can never skip the
  // coarse level's gathers that the others make.
  const bool factorised = factorise(coarse_rows);
  const std::vector<double> flags = gather_({factorised ? 1.0 : 0.0}, {});
  coarse_ready_ = std::all_of(flags.begin(), flags.end(), [](double flag) { return flag == 1.0; });
  return coarse_ready_;
}

bool TwoLevelPreconditioner::factorise(const std::vector<CoarseRow>& coarse_rows) {
  const std::size_t size_total = coarse_rows.size();
  // No unknowns (every fluid particle on the free surface): nothing to coarsen, and Eigen cannot compress an empty
  // matrix (makeCompressed reads one entry past its empty arrays).
  if (size_total == 0) {
    coarse_ready_ = false;
    return false;
  }
  const auto size = static_cast<Eigen::Index>(size_total);
  coarse_matrix_.resize(size, size);
  Eigen::VectorXi entries_per_column(size);
  for (std::size_t a = 0; a < size_total; ++a)
    entries_per_column[static_cast<Eigen::Index>(a)] = static_cast<int>(coarse_rows[a].size());
  coarse_matrix_.reserve(entries_per_column);
  // A_c is symmetric, so coarse row a is also column a.
  for (std::size_t a = 0; a < size_total; ++a)
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
  const auto restrict_into = [&](double* restricted) {
    tbb::parallel_for(std::size_t{0}, aggregate_count_, [&](std::size_t a) {
      double sum = 0.0;
      for (std::uint32_t k = member_start_[a]; k < member_start_[a + 1]; ++k) sum += residual[members_[k]];
      restricted[a] = sum;
    });
  };
  if (gather_) {  // over ranks every rank solves for the whole coarse vector from all the ranks' restrictions
    own_restricted_.resize(aggregate_count_);
    restrict_into(own_restricted_.data());
    const std::vector<double> all = gather_(own_restricted_, aggregate_counts_);
    restricted_ = Eigen::Map<const Eigen::VectorXd>(all.data(), static_cast<Eigen::Index>(all.size()));
  } else {
    restricted_.resize(static_cast<Eigen::Index>(aggregate_count_));
    restrict_into(restricted_.data());
  }
  coarse_vector_ = coarse_factor_.solve(restricted_);
  double dot = 0.0;  // serial: a few hundred terms in a fixed order; over ranks this rank's aggregates' share
  for (std::size_t a = 0; a < aggregate_count_; ++a) {
    const auto k = static_cast<Eigen::Index>(first_aggregate_ + a);
    dot += restricted_[k] * coarse_vector_[k];
  }
  return dot;
}

void TwoLevelPreconditioner::apply(const std::vector<double>& residual, std::vector<double>& result) {
  solve_coarse(residual);
  tbb::parallel_for(std::size_t{0}, matrix_.rows,
                    [&](std::size_t row) { result[row] = residual[row] * inverse_diagonal_[row] + coarse_correction(row); });
}

}  // namespace riffle
