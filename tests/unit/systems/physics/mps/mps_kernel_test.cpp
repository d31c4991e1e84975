// Wendland kernel and MPS lattice constants against the independent lattice sums of ../shared/docs/numerics.md
// (Sec. 1.1 table, 4 significant digits, so a tolerance of half a unit in the last printed digit), and the HS/HL
// operator bias of Sec. 2.5; the batched pair geometry of the fluid's pair loops against the scalar kernel.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "systems/physics/mps/fluid_pair_batch.hpp"
#include "systems/physics/mps/mps_kernel.hpp"

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

TEST_CASE("the batched pair loops see the scalar kernel's values bit for bit, and only the pairs within r_e") {
  // The batched GC/DS, prediction and free-surface loops promise results identical to the scalar loops: the batch's
  // r, 1/r^2 and w must equal std::sqrt, 1/r^2 and WendlandKernel::weight exactly, for every batch position (the AVX2
  // copy works four at a time, the tail one at a time), and the cut must keep exactly the entries within r_e, in
  // list order, across batch boundaries.
  const WendlandKernel kernel(0.012);
  const double radius_squared = kernel.effective_radius * kernel.effective_radius;
  std::vector<Vec3> positions;
  std::uint64_t state = 12345;
  const auto uniform = [&] {  // a fixed LCG: the test must not depend on the library's random engines
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) / 9007199254740992.0;
  };
  const Vec3 centre(0.1, 0.2, 0.3);
  for (int k = 0; k < 1000; ++k)
    positions.push_back(centre + 0.016 * Vec3(2.0 * uniform() - 1.0, 2.0 * uniform() - 1.0, 2.0 * uniform() - 1.0));
  positions.push_back(centre + Vec3(kernel.effective_radius, 0.0, 0.0));  // exactly at r_e: cut
  positions.push_back(centre);                                           // r = 0: kept, 1/r^2 = inf
  std::vector<std::uint32_t> list(positions.size());
  for (std::uint32_t j = 0; j < list.size(); ++j) list[j] = j;

  std::vector<std::uint32_t> expected;
  for (const std::uint32_t j : list)
    if ((positions[j] - centre).squaredNorm() < radius_squared) expected.push_back(j);
  REQUIRE(expected.size() > 2 * kPairBatch);  // several full batches and a tail

  std::vector<std::uint32_t> seen;
  std::size_t mismatches = 0;
  FluidPairBatch batch;
  const auto offset_of = [&](std::uint32_t j) -> Vec3 { return positions[j] - centre; };
  const auto check = [&](const FluidPairBatch& pair, std::size_t k) {
    const std::uint32_t j = pair.slot[k];
    seen.push_back(j);
    const double distance_squared = (positions[j] - centre).squaredNorm();
    const double distance = std::sqrt(distance_squared);
    mismatches += pair.distance_squared[k] != distance_squared;
    mismatches += pair.distance[k] != distance;
    mismatches += pair.inverse_squared[k] != 1.0 / distance_squared;
    mismatches += pair.weight[k] != kernel.weight(distance);
    mismatches += pair.offset(k) != positions[j] - centre;
  };
  for_each_pair_within(NeighbourRange{list.data(), list.data() + list.size()}, radius_squared, kernel, batch, offset_of, check);
  CHECK(seen == expected);
  CHECK(mismatches == 0);

  // A near list (already cut) passes through whole.
  seen.clear();
  mismatches = 0;
  for_each_near_pair(NeighbourRange{expected.data(), expected.data() + expected.size()}, kernel, batch, offset_of, check);
  CHECK(seen == expected);
  CHECK(mismatches == 0);
}
