// MPS operators on a cubic lattice patch and on a perturbed one, against closed forms (numerics.md Sec. 2).
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "systems/physics/mps_operators.hpp"

using namespace riffle;

namespace {

constexpr double kSpacing = 0.005;        // [m] l0
constexpr double kRadius = 2.6 * kSpacing;  // r_e

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
        patch.positions.push_back(kSpacing * Vec3(i + offset(random), j + offset(random), k + offset(random)));
      }
  for (std::uint32_t index = 1; index < patch.positions.size(); ++index)
    if (patch.positions[index].norm() < kRadius) patch.centre_neighbours.push_back(index);
  return patch;
}

NeighbourSpan span(const Patch& patch) {
  return {patch.centre_neighbours.data(), patch.centre_neighbours.data() + patch.centre_neighbours.size()};
}

}  // namespace

TEST_CASE("number density of the lattice centre is n0") {
  const WendlandKernel kernel{kRadius};
  const Patch patch = lattice_patch(3, 0.0, 1);
  const LatticeConstants constants = lattice_constants(3, kSpacing, kRadius);
  CHECK(number_density(Vec3::Zero(), patch.positions, span(patch), kernel) ==
        doctest::Approx(constants.number_density).epsilon(1e-12));
  CHECK(static_cast<std::int64_t>(patch.centre_neighbours.size()) == constants.neighbour_count);
}

TEST_CASE("HS divergence and HL Laplacian carry the same lattice bias, so it cancels in the PPE") {
  const WendlandKernel kernel{kRadius};
  const Patch patch = lattice_patch(3, 0.0, 1);
  const LatticeConstants constants = lattice_constants(3, kSpacing, kRadius);
  // u = x: div u = 3; (1/n0) Dn/Dt = -bias * div u.
  std::vector<Vec3> velocities = patch.positions;
  const double rate = number_density_rate(Vec3::Zero(), Vec3::Zero(), patch.positions, velocities, span(patch), kernel);
  CHECK(rate / constants.number_density == doctest::Approx(-3.0 * constants.operator_bias).epsilon(1e-12));
  // p = |x|^2: lap p = 6, times the same bias.
  std::vector<double> values;
  for (const Vec3& x : patch.positions) values.push_back(x.squaredNorm());
  CHECK(laplacian(Vec3::Zero(), 0.0, patch.positions, values, span(patch), kernel, constants.number_density) ==
        doctest::Approx(6.0 * constants.operator_bias).epsilon(1e-12));
  // A constant field has zero Laplacian and zero gradient whatever the arrangement.
  std::vector<double> constant(patch.positions.size(), 7.0);
  CHECK(laplacian(Vec3::Zero(), 7.0, patch.positions, constant, span(patch), kernel, constants.number_density) == 0.0);
}

TEST_CASE("the corrected gradient is exact for linear fields, on the lattice and on a jittered arrangement") {
  const WendlandKernel kernel{kRadius};
  const double n0 = lattice_constants(3, kSpacing, kRadius).number_density;
  const Vec3 slope(1200.0, -300.0, 9810.0);  // [Pa/m]
  for (double jitter : {0.0, 0.15, 0.3}) {
    CAPTURE(jitter);
    const Patch patch = lattice_patch(4, jitter, 7);
    std::vector<double> pressure;
    for (const Vec3& x : patch.positions) pressure.push_back(101325.0 + slope.dot(x));
    const Eigen::Matrix3d correction = gradient_correction(Vec3::Zero(), patch.positions, span(patch), kernel, n0);
    if (jitter == 0.0) CHECK((correction - Eigen::Matrix3d::Identity()).norm() < 1e-12);
    const Vec3 gradient = corrected_gradient(Vec3::Zero(), pressure[0], correction, patch.positions, pressure,
                                             span(patch), kernel, n0);
    CHECK((gradient - slope).norm() < 1e-9 * slope.norm());
  }
}

TEST_CASE("the gradient correction falls back to the identity for a one-sided, flat neighbourhood") {
  const WendlandKernel kernel{kRadius};
  const double n0 = lattice_constants(3, kSpacing, kRadius).number_density;
  Patch patch;
  patch.positions.push_back(Vec3::Zero());
  for (int i = -2; i <= 2; ++i)
    for (int j = -2; j <= 2; ++j)
      if (i != 0 || j != 0) patch.positions.push_back(kSpacing * Vec3(i, j, 0.0));  // a plane: A is singular in z
  for (std::uint32_t k = 1; k < patch.positions.size(); ++k)
    if (patch.positions[k].norm() < kRadius) patch.centre_neighbours.push_back(k);
  CHECK(gradient_correction(Vec3::Zero(), patch.positions, span(patch), kernel, n0) == Eigen::Matrix3d::Identity());
}

TEST_CASE("dynamic stabilisation pushes particles that came too close apart, and leaves others alone") {
  const WendlandKernel kernel{kRadius};
  const double n0 = lattice_constants(3, kSpacing, kRadius).number_density;
  const double dt = 1e-3;
  const double closest = 0.9 * kSpacing;  // alpha_DS l0 with C_r = 0.1
  const std::vector<Vec3> positions = {Vec3::Zero(), Vec3(0.7 * kSpacing, 0.0, 0.0), Vec3(0.0, kSpacing, 0.0)};
  const std::vector<std::uint32_t> neighbours = {1, 2};
  const Vec3 push = stabilisation_velocity(Vec3::Zero(), positions, {neighbours.data(), neighbours.data() + 2}, kernel,
                                           n0, closest, 0.5, dt);
  // Away from the close partner along -x; the partner at exactly l0 > 0.9 l0 contributes nothing.
  CHECK(push.x() < 0.0);
  CHECK(push.y() == 0.0);
  CHECK(push.z() == 0.0);
  const double expected = 0.5 * (0.2 * kSpacing) / dt * kernel.weight(0.7 * kSpacing) / n0;
  CHECK(-push.x() == doctest::Approx(expected).epsilon(1e-12));
}
