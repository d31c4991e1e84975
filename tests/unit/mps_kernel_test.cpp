// Wendland kernel and MPS lattice constants against the independent lattice sums of ../shared/docs/numerics.md
// (Sec. 1.1 table, 4 significant digits, so a tolerance of half a unit in the last printed digit), and the HS/HL
// operator bias of Sec. 2.5.
#include <doctest/doctest.h>

#include <cmath>

#include "systems/mps_kernel.hpp"

using namespace riffle;

TEST_CASE("the Wendland kernel: shape, support and derivative") {
  const WendlandKernel kernel{2.6};
  CHECK(kernel.weight(0.0) == 1.0);
  CHECK(kernel.weight(2.6) == 0.0);
  CHECK(kernel.weight(3.0) == 0.0);
  // w'(r) against a central difference: error h^2/6 |w'''| with |w'''| <= 60/r_e^3 on the support.
  const double h = 1e-5;
  for (double r = 0.1; r < 2.5; r += 0.1) {
    const double numeric = (kernel.weight(r + h) - kernel.weight(r - h)) / (2 * h);
    CHECK(std::abs(numeric - kernel.derivative(r)) < h * h / 6.0 * 60.0 / std::pow(2.6, 3) + 1e-10);
  }
  // w'/r is finite at 0: -20 / r_e^2.
  CHECK(kernel.derivative_over_distance(0.0) == doctest::Approx(-20.0 / (2.6 * 2.6)));
}

TEST_CASE("lattice constants match numerics.md Sec. 1.1") {
  struct Row {
    int dimension;
    double radius;
    std::int64_t neighbours;
    double number_density, lambda;
  };
  const Row rows[] = {{2, 2.1, 12, 1.0428, 1.1614}, {2, 2.4, 20, 1.6315, 1.2609}, {2, 3.1, 28, 3.3330, 1.7282},
                      {3, 2.1, 32, 1.8487, 1.3080}, {3, 2.6, 80, 4.3087, 1.6394}, {3, 3.1, 122, 7.9396, 2.1576}};
  for (const Row& row : rows) {
    CAPTURE(row.dimension);
    CAPTURE(row.radius);
    const LatticeConstants constants = lattice_constants(row.dimension, 1.0, row.radius);
    CHECK(constants.neighbour_count == row.neighbours);
    CHECK(std::abs(constants.number_density - row.number_density) <= 0.5e-4);
    CHECK(std::abs(constants.laplacian_lambda - row.lambda) <= 0.5e-4);
  }
}

TEST_CASE("lattice constants scale with the spacing: n0 is dimensionless, lambda0 goes as l0^2") {
  const LatticeConstants unit = lattice_constants(3, 1.0, 2.6);
  const LatticeConstants fine = lattice_constants(3, 0.005, 0.013);
  CHECK(fine.neighbour_count == unit.neighbour_count);
  CHECK(fine.number_density == doctest::Approx(unit.number_density).epsilon(1e-12));
  CHECK(fine.laplacian_lambda == doctest::Approx(unit.laplacian_lambda * 0.005 * 0.005).epsilon(1e-12));
}

TEST_CASE("the HS divergence and the HL Laplacian share the lattice bias of numerics.md Sec. 2.5") {
  // Printed to 3 decimals: tolerance half a unit in the last digit.
  CHECK(std::abs(lattice_constants(2, 1.0, 2.4).operator_bias - 1.527) <= 0.5e-3);
  CHECK(std::abs(lattice_constants(2, 1.0, 3.1).operator_bias - 1.290) <= 0.5e-3);
  CHECK(std::abs(lattice_constants(3, 1.0, 2.6).operator_bias - 1.195) <= 0.5e-3);
  CHECK(std::abs(lattice_constants(3, 1.0, 3.1).operator_bias - 1.124) <= 0.5e-3);
  CHECK_THROWS(lattice_constants(4, 1.0, 2.6));
  CHECK_THROWS(lattice_constants(3, 0.0, 2.6));
}
