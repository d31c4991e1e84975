#pragma once
// A pressure-equation-like system for the solver tests: the 3D 7-point Laplacian on an n^3 lattice with a Dirichlet
// face at the top (z = n: the free surface's p = 0) and Neumann walls elsewhere, plus a small compressible diagonal.
// Symmetric positive definite, as the PPE; its exact solution by a sparse Cholesky factorisation (Eigen),
// independent of the solvers under test.
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <cmath>
#include <cstdint>
#include <vector>

#include "systems/physics/mps/pressure_preconditioner.hpp"

namespace riffle::test {

struct TankLattice {
  std::vector<double> diagonal, values;
  std::vector<std::size_t> row_start{0};
  std::vector<std::uint32_t> columns;

  explicit TankLattice(long n) {
    for (long z = 0; z < n; ++z)
      for (long y = 0; y < n; ++y)
        for (long x = 0; x < n; ++x) {
          double diag = 1.0e-3 + (z == n - 1 ? 1.0 : 0.0);
          const long coords[3] = {x, y, z};
          for (int axis = 0; axis < 3; ++axis)
            for (int side = -1; side <= 1; side += 2) {
              long c[3] = {coords[0], coords[1], coords[2]};
              c[axis] += side;
              if (c[axis] < 0 || c[axis] >= n) continue;
              columns.push_back(static_cast<std::uint32_t>((c[2] * n + c[1]) * n + c[0]));
              values.push_back(-1.0);
              diag += 1.0;
            }
          diagonal.push_back(diag);
          row_start.push_back(columns.size());
        }
  }
  std::size_t rows() const { return diagonal.size(); }
  PressureMatrix matrix() const { return {rows(), diagonal.data(), row_start.data(), columns.data(), values.data()}; }
  /// Rows [first, first + count) as a matrix of their own (columns stay global), pointing into this lattice.
  PressureMatrix block(std::size_t first, std::size_t count, std::vector<std::size_t>& block_row_start) const {
    block_row_start.assign(count + 1, 0);
    for (std::size_t r = 0; r <= count; ++r) block_row_start[r] = row_start[first + r] - row_start[first];
    return {count, diagonal.data() + first, block_row_start.data(), columns.data() + row_start[first],
            values.data() + row_start[first]};
  }
  std::vector<double> product(const std::vector<double>& x) const {
    std::vector<double> y(x.size());
    for (std::size_t row = 0; row < x.size(); ++row) {
      double sum = diagonal[row] * x[row];
      for (std::size_t k = row_start[row]; k < row_start[row + 1]; ++k) sum += values[k] * x[columns[k]];
      y[row] = sum;
    }
    return y;
  }
  std::vector<double> direct_solve(const std::vector<double>& rhs) const {
    std::vector<Eigen::Triplet<double>> entries;
    for (std::size_t row = 0; row < rows(); ++row) {
      entries.emplace_back(row, row, diagonal[row]);
      for (std::size_t k = row_start[row]; k < row_start[row + 1]; ++k) entries.emplace_back(row, columns[k], values[k]);
    }
    Eigen::SparseMatrix<double> m(rows(), rows());
    m.setFromTriplets(entries.begin(), entries.end());
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> factor(m);
    const Eigen::VectorXd x = factor.solve(Eigen::Map<const Eigen::VectorXd>(rhs.data(), rhs.size()));
    return {x.data(), x.data() + x.size()};
  }
  /// A smooth right-hand side with some variation.
  static std::vector<double> varied_rhs(std::size_t size) {
    std::vector<double> rhs(size);
    for (std::size_t k = 0; k < size; ++k) rhs[k] = 1.0 + 0.3 * std::sin(0.7 * static_cast<double>(k));
    return rhs;
  }
};

inline double norm(const std::vector<double>& v) {
  double sum = 0.0;
  for (const double value : v) sum += value * value;
  return std::sqrt(sum);
}

}  // namespace riffle::test
