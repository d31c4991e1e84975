// MPS operators on a cubic lattice patch and on a perturbed one, against closed forms (numerics.md Sec. 2). The
// per-pair terms and closures are the functions the fluid systems call (systems/physics/mps/mps_operators.hpp), summed
// here over the pair geometry of systems/physics/mps/fluid_pair_batch.hpp as the systems' pair loops sum them.
#include <doctest/doctest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>
#include <vector>

#include "systems/physics/mps/fluid_pair_batch.hpp"
#include "systems/physics/mps/mps_operators.hpp"

using namespace riffle;

namespace {

constexpr double kOperatorSpacing = 0.005;        // [m] l0
constexpr double kRadius = 2.6 * kOperatorSpacing;  // r_e

/// A cubic lattice of (2 n + 1)^3 points centred on the origin, optionally jittered, with the centre first.
struct Patch {
  std::vector<Vec3> positions;
  std::vector<std::uint32_t> centre_neighbours;
};

Patch lattice_patch(int n, double jitter, unsigned seed) {
  Patch patch;
  patch.positions.push_back(Vec3::Zero());
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> offset(-jitter, jitter);
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      for (int k = -n; k <= n; ++k) {
        if (i == 0 && j == 0 && k == 0) continue;
        patch.positions.push_back(kOperatorSpacing * Vec3(i + offset(random), j + offset(random), k + offset(random)));
      }
  for (std::uint32_t index = 1; index < patch.positions.size(); ++index)
    if (patch.positions[index].norm() < kRadius) patch.centre_neighbours.push_back(index);
  return patch;
}

/// Calls pair(batch, k) for each neighbour of the patch centre within r_e, as the fluid systems' pair loops do.
template <class Pair>
void for_each_centre_pair(const Patch& patch, const WendlandKernel& kernel, Pair&& pair) {
  FluidPairBatch batch;
  const NeighbourRange list{patch.centre_neighbours.data(),
                            patch.centre_neighbours.data() + patch.centre_neighbours.size()};
  for_each_pair_within(
      list, kernel.effective_radius * kernel.effective_radius, kernel, batch,
      [&](std::uint32_t j) -> Vec3 { return patch.positions[j] - patch.positions[0]; }, pair);
}

/// The GC gradient of `values` at the patch centre, as fluid_correct forms it.
Vec3 corrected_gradient(const Patch& patch, const std::vector<double>& values, const WendlandKernel& kernel,
                        double n0, Eigen::Matrix3d* correction = nullptr) {
  GradientMoment moment;
  Vec3 sum = Vec3::Zero();
  for_each_centre_pair(patch, kernel, [&](const FluidPairBatch& pair, std::size_t k) {
    const double weight_over_squared = pair.weight[k] * pair.inverse_squared[k];
    sum += gradient_term(values[pair.slot[k]] - values[0], weight_over_squared, pair.offset(k));
    moment.add(pair.weight[k], weight_over_squared, pair.offset(k));
  });
  const Eigen::Matrix3d matrix = gradient_correction_matrix(moment, n0);
  if (correction) *correction = matrix;
  return matrix * ((3.0 / n0) * sum);
}

}  // namespace

TEST_CASE("number density of the lattice centre is n0") {
  const WendlandKernel kernel{kRadius};
  const Patch patch = lattice_patch(3, 0.0, 1);
  const LatticeConstants constants = lattice_constants(3, kOperatorSpacing, kRadius);
  double density = 0.0;
  std::int64_t count = 0;
  for_each_centre_pair(patch, kernel, [&](const FluidPairBatch& pair, std::size_t k) {
    density += pair.weight[k];
    ++count;
  });
  CHECK(density == doctest::Approx(constants.number_density).epsilon(1e-12));
  CHECK(count == constants.neighbour_count);
}

TEST_CASE("HS divergence and HL Laplacian carry the same lattice bias, so it cancels in the PPE") {
  const WendlandKernel kernel{kRadius};
  const Patch patch = lattice_patch(3, 0.0, 1);
  const LatticeConstants constants = lattice_constants(3, kOperatorSpacing, kRadius);
  const double n0 = constants.number_density;
  // u = x: div u = 3; (1/n0) Dn/Dt = -bias * div u. p = |x|^2: lap p = 6, times the same bias.
  double rate = 0.0, laplacian = 0.0, linear_laplacian = 0.0;
  for_each_centre_pair(patch, kernel, [&](const FluidPairBatch& pair, std::size_t k) {
    const Vec3& x = patch.positions[pair.slot[k]];
    const double derivative_over_distance = kernel.derivative_over_distance(pair.distance[k]);
    rate += density_rate_term(true, derivative_over_distance, pair.offset(k), x);
    laplacian += laplacian_coefficient(derivative_over_distance) * x.squaredNorm();
    linear_laplacian += laplacian_coefficient(derivative_over_distance) * Vec3(1200.0, -300.0, 9810.0).dot(x);
  });
  CHECK(rate / n0 == doctest::Approx(-3.0 * constants.operator_bias).epsilon(1e-12));
  CHECK(laplacian / n0 == doctest::Approx(6.0 * constants.operator_bias).epsilon(1e-12));
  // A linear field has zero Laplacian on the lattice (its terms cancel in symmetric pairs): 1e-9 of one term's size.
  CHECK(std::abs(linear_laplacian / n0) < 1e-9 * 9810.0 / kOperatorSpacing);
  // A wall neighbour stands for itself and its mirror image: twice a fluid one's term.
  const Vec3 offset(0.3 * kOperatorSpacing, -0.2 * kOperatorSpacing, 0.9 * kOperatorSpacing), velocity(0.1, 0.2, -0.3);
  const double derivative_over_distance = kernel.derivative_over_distance(offset.norm());
  CHECK(density_rate_term(false, derivative_over_distance, offset, velocity) ==
        2.0 * density_rate_term(true, derivative_over_distance, offset, velocity));
}

TEST_CASE("the corrected gradient is exact for linear fields, on the lattice and on a jittered arrangement") {
  const WendlandKernel kernel{kRadius};
  const double n0 = lattice_constants(3, kOperatorSpacing, kRadius).number_density;
  const Vec3 slope(1200.0, -300.0, 9810.0);  // [Pa/m]
  for (double jitter : {0.0, 0.15, 0.3}) {
    CAPTURE(jitter);
    const Patch patch = lattice_patch(4, jitter, 7);
    std::vector<double> pressure;
    for (const Vec3& x : patch.positions) pressure.push_back(101325.0 + slope.dot(x));
    Eigen::Matrix3d correction;
    const Vec3 gradient = corrected_gradient(patch, pressure, kernel, n0, &correction);
    if (jitter == 0.0) CHECK((correction - Eigen::Matrix3d::Identity()).norm() < 1e-12);
    if (jitter > 0.0) CHECK(correction != Eigen::Matrix3d::Identity());  // the correction did act
    CHECK((gradient - slope).norm() < 1e-9 * slope.norm());
  }
}

TEST_CASE("the gradient correction falls back to the identity for a one-sided, flat neighbourhood") {
  const WendlandKernel kernel{kRadius};
  const double n0 = lattice_constants(3, kOperatorSpacing, kRadius).number_density;
  Patch patch;
  patch.positions.push_back(Vec3::Zero());
  for (int i = -2; i <= 2; ++i)
    for (int j = -2; j <= 2; ++j)
      if (i != 0 || j != 0) patch.positions.push_back(kOperatorSpacing * Vec3(i, j, 0.0));  // a plane: A is singular in z
  for (std::uint32_t k = 1; k < patch.positions.size(); ++k)
    if (patch.positions[k].norm() < kRadius) patch.centre_neighbours.push_back(k);
  Eigen::Matrix3d correction;
  corrected_gradient(patch, std::vector<double>(patch.positions.size(), 0.0), kernel, n0, &correction);
  CHECK(correction == Eigen::Matrix3d::Identity());
}

TEST_CASE("the Gershgorin shortcut of the gradient correction decides as the eigenvalue test would") {
  // Random symmetric moments around the lattice's (D A = I): the result is the inverse of D A exactly where
  // n >= 0.5 n0, det(D A) >= 0.05 and lambda_min(D A) >= 0.2, and the identity elsewhere.
  const double n0 = 100.0;
  std::mt19937 random(3);
  std::uniform_real_distribution<double> entry(-0.6, 0.6);
  int inverted = 0, identity = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    GradientMoment moment;
    const double scale = n0 / 3.0;  // D A = (3 / n0) moment
    moment.xx = scale * (1.0 + entry(random));
    moment.yy = scale * (1.0 + entry(random));
    moment.zz = scale * (1.0 + entry(random));
    moment.xy = scale * 0.5 * entry(random);
    moment.xz = scale * 0.5 * entry(random);
    moment.yz = scale * 0.5 * entry(random);
    moment.density = n0 * (trial % 10 == 0 ? 0.4 : 1.0);
    const Eigen::Matrix3d scaled = (3.0 / n0) * moment.matrix();
    const double smallest =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scaled, Eigen::EigenvaluesOnly).eigenvalues()[0];
    const bool invert = moment.density >= 0.5 * n0 && scaled.determinant() >= 0.05 && smallest >= 0.2;
    const Eigen::Matrix3d result = gradient_correction_matrix(moment, n0);
    if (invert) CHECK((result * scaled - Eigen::Matrix3d::Identity()).norm() < 1e-12);
    else CHECK(result == Eigen::Matrix3d::Identity());
    (invert ? inverted : identity) += 1;
  }
  CHECK(inverted > 100);  // both outcomes were exercised
  CHECK(identity > 100);
}

TEST_CASE("dynamic stabilisation pushes particles that came too close apart, and leaves others alone") {
  const WendlandKernel kernel{kRadius};
  const double n0 = lattice_constants(3, kOperatorSpacing, kRadius).number_density;
  const double dt = 1e-3;
  const double closest = 0.9 * kOperatorSpacing;  // alpha_DS l0 with C_r = 0.1
  Patch patch;
  patch.positions = {Vec3::Zero(), Vec3(0.7 * kOperatorSpacing, 0.0, 0.0), Vec3(0.0, kOperatorSpacing, 0.0)};
  patch.centre_neighbours = {1, 2};
  Vec3 stabilisation = Vec3::Zero();
  for_each_centre_pair(patch, kernel, [&](const FluidPairBatch& pair, std::size_t k) {
    if (pair.distance[k] < closest)
      stabilisation += stabilisation_term(0.5, closest, pair.distance[k], pair.weight[k] * pair.inverse_squared[k],
                                          pair.offset(k));
  });
  const Vec3 push = stabilisation / (n0 * dt);  // as fluid_correct adds it to the velocity
  // Away from the close partner along -x; the partner at exactly l0 > 0.9 l0 contributes nothing.
  CHECK(push.x() < 0.0);
  CHECK(push.y() == 0.0);
  CHECK(push.z() == 0.0);
  const double expected = 0.5 * (0.2 * kOperatorSpacing) / dt * kernel.weight(0.7 * kOperatorSpacing) / n0;
  CHECK(-push.x() == doctest::Approx(expected).epsilon(1e-12));
}
