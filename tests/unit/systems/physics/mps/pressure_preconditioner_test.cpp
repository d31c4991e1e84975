// The two-level preconditioner of the pressure solve: symmetric positive definite (so CG stays CG), exact on the
// coarse space, and falling back to Jacobi when the coarse matrix cannot be factorised; over ranks, the one-rank
// preconditioner over the whole domain.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <barrier>
#include <cmath>
#include <cstdint>
#include <thread>
#include <vector>

#include "systems/physics/mps/pressure_preconditioner.hpp"

using namespace riffle;

namespace {
/// A 3D 7-point Laplacian with a Dirichlet boundary on an n^3 lattice of spacing 1 (M = 6 I - neighbours), points at
/// the lattice sites: an SPD M-matrix like the PPE's.
struct PressureLattice {
  std::size_t n;
  std::vector<double> diagonal, values;
  std::vector<std::size_t> row_start{0};
  std::vector<std::uint32_t> columns;
  std::vector<Vec3> positions;

  explicit PressureLattice(std::size_t size) : n(size) {
    for (std::size_t z = 0; z < n; ++z)
      for (std::size_t y = 0; y < n; ++y)
        for (std::size_t x = 0; x < n; ++x) {
          positions.emplace_back(x + 0.5, y + 0.5, z + 0.5);
          diagonal.push_back(6.0);
          const long coords[3] = {long(x), long(y), long(z)};
          for (int axis = 0; axis < 3; ++axis)
            for (int side = -1; side <= 1; side += 2) {
              long c[3] = {coords[0], coords[1], coords[2]};
              c[axis] += side;
              if (c[axis] < 0 || c[axis] >= long(n)) continue;
              columns.push_back(static_cast<std::uint32_t>((c[2] * long(n) + c[1]) * long(n) + c[0]));
              values.push_back(-1.0);
            }
          row_start.push_back(columns.size());
        }
  }
  PressureMatrix matrix() const {
    return {diagonal.size(), diagonal.data(), row_start.data(), columns.data(), values.data()};
  }
};

double dot(const std::vector<double>& a, const std::vector<double>& b) {
  double sum = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) sum += a[k] * b[k];
  return sum;
}
}  // namespace

TEST_CASE("the two-level preconditioner is symmetric and positive definite") {
  const PressureLattice lattice(8);
  TwoLevelPreconditioner preconditioner;
  REQUIRE(preconditioner.setup(lattice.matrix(), lattice.positions, Vec3::Zero(), 4.0));
  CHECK(preconditioner.coarse_size() == 8);  // 8^3 sites in cells of 4: 2 x 2 x 2 aggregates
  std::vector<double> x(lattice.diagonal.size()), y(x.size()), mx(x.size()), my(x.size());
  for (std::size_t k = 0; k < x.size(); ++k) {
    x[k] = std::sin(0.37 * k) + 0.1;
    y[k] = std::cos(1.3 * k) - 0.2;
  }
  preconditioner.apply(x, mx);
  preconditioner.apply(y, my);
  // (M^-1 x, y) = (x, M^-1 y) to rounding; (M^-1 x, x) > 0.
  CHECK(dot(mx, y) == doctest::Approx(dot(x, my)).epsilon(1e-12));
  CHECK(dot(mx, x) > 0.0);
}

TEST_CASE("the coarse correction is exact for residuals in the coarse space's range") {
  // r = A P e for a coarse vector e: the coarse part returns P e exactly, so M^-1 r - D^-1 r = P e.
  const PressureLattice lattice(8);
  TwoLevelPreconditioner preconditioner;
  REQUIRE(preconditioner.setup(lattice.matrix(), lattice.positions, Vec3::Zero(), 4.0));
  std::vector<double> prolonged(lattice.diagonal.size()), residual(prolonged.size()), result(prolonged.size());
  for (std::size_t k = 0; k < prolonged.size(); ++k) {
    const Vec3& p = lattice.positions[k];
    prolonged[k] = 1.0 + (p[0] > 4.0 ? 2.0 : 0.0) + (p[2] > 4.0 ? -0.5 : 0.0);  // piecewise constant per aggregate
  }
  for (std::size_t row = 0; row < prolonged.size(); ++row) {
    double sum = lattice.diagonal[row] * prolonged[row];
    for (std::size_t e = lattice.row_start[row]; e < lattice.row_start[row + 1]; ++e) sum += lattice.values[e] * prolonged[lattice.columns[e]];
    residual[row] = sum;
  }
  preconditioner.apply(residual, result);
  for (std::size_t k = 0; k < prolonged.size(); ++k)
    CHECK(result[k] - residual[k] / lattice.diagonal[k] == doctest::Approx(prolonged[k]).epsilon(1e-10));
}

TEST_CASE("a pressure solve without unknowns has no coarse level (every fluid particle on the free surface)") {
  // Found by the checkpoint fuzzer: Eigen read past the arrays of the empty coarse matrix when compressing it.
  const std::size_t row_start[1] = {0};
  const PressureMatrix empty{0, nullptr, row_start, nullptr, nullptr};
  TwoLevelPreconditioner preconditioner;
  CHECK_FALSE(preconditioner.setup(empty, {}, Vec3::Zero(), 4.0));
  CHECK(preconditioner.coarse_size() == 0);
  std::vector<double> residual, result;
  CHECK(preconditioner.solve_coarse(residual) == 0.0);
  preconditioner.apply(residual, result);
}

namespace {
/// The lattice's rows over two ranks simulated by two threads in one process: rank 0 holds the sites below z = split,
/// rank 1 the rest; each rank's matrix has its own rows as columns 0 .. rows - 1 and, past them, one ghost column per
/// row of the other rank it couples to. The links' gather and ghost refresh go through shared slots and a barrier,
/// as MPI's collectives would.
struct TwoRanks {
  std::array<std::vector<std::size_t>, 2> own, ghost;  ///< global rows: this rank's, its ghost columns'
  std::array<std::vector<double>, 2> diagonal, values;
  std::array<std::vector<std::size_t>, 2> row_start;
  std::array<std::vector<std::uint32_t>, 2> columns;
  std::array<std::vector<Vec3>, 2> positions;
  std::array<std::vector<double>, 2> slots;
  std::vector<double> shared;  ///< every row's entry, for the ghost refresh
  std::barrier<> barrier{2};

  TwoRanks(const PressureLattice& lattice, double split) : shared(lattice.diagonal.size()) {
    const auto rank_of = [&](std::size_t row) { return lattice.positions[row][2] < split ? 0 : 1; };
    for (std::size_t row = 0; row < lattice.diagonal.size(); ++row) own[rank_of(row)].push_back(row);
    for (int r = 0; r < 2; ++r) {
      std::vector<std::int64_t> local(lattice.diagonal.size(), -1);
      for (std::size_t k = 0; k < own[r].size(); ++k) local[own[r][k]] = static_cast<std::int64_t>(k);
      std::vector<std::size_t> ghost_rows;
      for (const std::size_t row : own[r])
        for (std::size_t e = lattice.row_start[row]; e < lattice.row_start[row + 1]; ++e)
          if (rank_of(lattice.columns[e]) != r) ghost_rows.push_back(lattice.columns[e]);
      std::sort(ghost_rows.begin(), ghost_rows.end());
      ghost_rows.erase(std::unique(ghost_rows.begin(), ghost_rows.end()), ghost_rows.end());
      ghost[r] = ghost_rows;
      for (std::size_t g = 0; g < ghost_rows.size(); ++g)
        local[ghost_rows[g]] = static_cast<std::int64_t>(own[r].size() + g);
      row_start[r] = {0};
      for (const std::size_t row : own[r]) {
        diagonal[r].push_back(lattice.diagonal[row]);
        positions[r].push_back(lattice.positions[row]);
        for (std::size_t e = lattice.row_start[row]; e < lattice.row_start[row + 1]; ++e) {
          columns[r].push_back(static_cast<std::uint32_t>(local[lattice.columns[e]]));
          values[r].push_back(lattice.values[e]);
        }
        row_start[r].push_back(columns[r].size());
      }
    }
  }
  PressureMatrix matrix(int r) const {
    return {own[r].size(), diagonal[r].data(), row_start[r].data(), columns[r].data(), values[r].data()};
  }
  TwoLevelPreconditioner::RankLinks links(int r) {
    return {[this, r](const std::vector<double>& values, const std::vector<std::size_t>&) {
              slots[r] = values;
              barrier.arrive_and_wait();
              std::vector<double> all = slots[0];
              all.insert(all.end(), slots[1].begin(), slots[1].end());
              barrier.arrive_and_wait();
              return all;
            },
            [this, r](std::vector<double>& x) {
              for (std::size_t k = 0; k < own[r].size(); ++k) shared[own[r][k]] = x[k];
              barrier.arrive_and_wait();
              for (std::size_t g = 0; g < ghost[r].size(); ++g) x[own[r].size() + g] = shared[ghost[r][g]];
              barrier.arrive_and_wait();
            },
            static_cast<std::size_t>(r)};
  }
  /// M^-1 of each of `inputs` (global vectors) over the two ranks, and the ranks' coarse dot shares summed.
  std::vector<std::vector<double>> apply(const std::vector<std::vector<double>>& inputs, std::size_t& coarse_size,
                                         std::vector<double>& coarse_dots) {
    std::vector<std::vector<double>> outputs(inputs.size(), std::vector<double>(shared.size()));
    std::array<std::vector<double>, 2> dots{std::vector<double>(inputs.size()), std::vector<double>(inputs.size())};
    std::array<std::size_t, 2> sizes{};
    const auto rank_work = [&](int r) {
      TwoLevelPreconditioner preconditioner;
      preconditioner.setup_over_ranks(matrix(r), ghost[r].size(), positions[r], Vec3::Zero(), 4.0, links(r));
      sizes[r] = preconditioner.coarse_size();
      for (std::size_t v = 0; v < inputs.size(); ++v) {
        std::vector<double> residual(own[r].size());
        for (std::size_t k = 0; k < own[r].size(); ++k) residual[k] = inputs[v][own[r][k]];
        dots[r][v] = preconditioner.solve_coarse(residual);
        for (std::size_t k = 0; k < own[r].size(); ++k)
          outputs[v][own[r][k]] = residual[k] / diagonal[r][k] + preconditioner.coarse_correction(k);
      }
    };
    std::thread other(rank_work, 1);
    rank_work(0);
    other.join();
    CHECK(sizes[0] == sizes[1]);
    coarse_size = sizes[0];
    coarse_dots.resize(inputs.size());
    for (std::size_t v = 0; v < inputs.size(); ++v) coarse_dots[v] = dots[0][v] + dots[1][v];
    return outputs;
  }
};

std::vector<double> varied(std::size_t size, double a, double b) {
  std::vector<double> v(size);
  for (std::size_t k = 0; k < size; ++k) v[k] = std::sin(a * static_cast<double>(k)) + b;
  return v;
}
}  // namespace

TEST_CASE("over two ranks whose boundary follows the coarse cells, the preconditioner is the one-rank one") {
  // Sites below z = 4 on rank 0: every aggregate (cells of 4) lies on one rank, so the coarse space, A_c and M^-1 are
  // one rank's, numbered in another order: equal to rounding. The ranks' coarse dot shares add up to the whole.
  const PressureLattice lattice(8);
  TwoLevelPreconditioner alone;
  REQUIRE(alone.setup(lattice.matrix(), lattice.positions, Vec3::Zero(), 4.0));
  const std::vector<double> x = varied(lattice.diagonal.size(), 0.37, 0.1);
  std::vector<double> expected(x.size());
  alone.apply(x, expected);
  const double expected_dot = alone.solve_coarse(x);
  TwoRanks ranks(lattice, 4.0);
  REQUIRE(!ranks.ghost[0].empty());
  std::size_t coarse_size = 0;
  std::vector<double> coarse_dots;
  const std::vector<std::vector<double>> result = ranks.apply({x}, coarse_size, coarse_dots);
  CHECK(coarse_size == alone.coarse_size());
  for (std::size_t k = 0; k < x.size(); ++k) CHECK(result[0][k] == doctest::Approx(expected[k]).epsilon(1e-12));
  CHECK(coarse_dots[0] == doctest::Approx(expected_dot).epsilon(1e-12));
}

TEST_CASE("over two ranks that cut the coarse cells, the preconditioner stays symmetric and positive definite") {
  // Sites below z = 3 on rank 0: the cells of 4 that straddle z = 3 become one aggregate on each rank (2 x 2 x 2
  // cells, the lower 4 split: 12 aggregates). M^-1 over the whole domain is still D^-1 + P A_c^-1 P^T.
  const PressureLattice lattice(8);
  TwoRanks ranks(lattice, 3.0);
  const std::vector<double> x = varied(lattice.diagonal.size(), 0.37, 0.1);
  const std::vector<double> y = varied(lattice.diagonal.size(), 1.3, -0.2);
  std::size_t coarse_size = 0;
  std::vector<double> coarse_dots;
  const std::vector<std::vector<double>> result = ranks.apply({x, y}, coarse_size, coarse_dots);
  CHECK(coarse_size == 12);
  CHECK(dot(result[0], y) == doctest::Approx(dot(x, result[1])).epsilon(1e-12));
  CHECK(dot(result[0], x) > 0.0);
  // r . M^-1 r = sum r^2 / diag + the coarse dot, as the CG forms it from the ranks' shares.
  double jacobi = 0.0;
  for (std::size_t k = 0; k < x.size(); ++k) jacobi += x[k] * x[k] / lattice.diagonal[k];
  CHECK(jacobi + coarse_dots[0] == doctest::Approx(dot(result[0], x)).epsilon(1e-12));
}
