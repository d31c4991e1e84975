// The two-level preconditioner of the pressure solve: symmetric positive definite (so CG stays CG), exact on the
// coarse space, and falling back to Jacobi when the coarse matrix cannot be factorised.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "systems/physics/mps/pressure_preconditioner.hpp"

using namespace riffle;

namespace {
/// A 3D 7-point Laplacian with a Dirichlet boundary on an n^3 lattice of spacing 1 (M = 6 I - neighbours), points at
/// the lattice sites: an SPD M-matrix like the PPE's.
struct Lattice {
  std::size_t n;
  std::vector<double> diagonal, values;
  std::vector<std::size_t> row_start{0};
  std::vector<std::uint32_t> columns;
  std::vector<Vec3> positions;

  explicit Lattice(std::size_t size) : n(size) {
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
  const Lattice lattice(8);
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
  const Lattice lattice(8);
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
