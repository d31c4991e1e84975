// The grains' sampling kernel with `[coupling] sampling_vertical_radius` (docs/COUPLING.md, "A thin bed's sampling"):
// the ellipsoidal Wendland kernel w(s R_h), s^2 = (dx^2 + dy^2) / R_h^2 + dz^2 / R_v^2, normalised by its own weight
// sum. What the theory says, checked on the system that runs (SolidFluidSampling, after FluidSampleCopy):
//  - its weights are the formula's: the grain's weight sum W equals the sum of the written-out weights, over the
//    nearest images across a periodic seam too;
//  - a normalised kernel symmetric under reflection through the grain's centre reads a linear field u = a + B x
//    exactly at the centre, sum_j w_j (x_j - c) = 0, when the water's lattice is symmetric about the centre too
//    (the centre on a lattice node or between layers): the velocity, the pressure force -V grad p and the water's
//    acceleration g - grad p / rho, to rounding (relative 1e-12 of the field's range over the kernel);
//  - with R_v = 0 (the default) the weights are the isotropic kernel's, bit for bit.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "engine/setup/fluid_layout.hpp"
#include "systems/coupling/fluid_sample_copy.hpp"
#include "systems/coupling/solid_fluid_sampling.hpp"
#include "systems/physics/mps/mps_kernel.hpp"
#include "systems/physics/coupling/sampling_kernel.hpp"
#include "tests/support/test_support.hpp"

namespace riffle {
namespace {

constexpr double kKernelSpacing = 0.01;
constexpr double kBox = 0.1;

/// (1 - s)^4 (1 + 4 s) for s < 1, written out from the definition (R_v = R_h when vertical = 0).
double formula_weight(const Vec3& offset, double horizontal, double vertical) {
  const double across = vertical > 0.0 ? std::min(vertical, horizontal) : horizontal;
  const double s = std::sqrt((offset.x() * offset.x() + offset.y() * offset.y()) / (horizontal * horizontal) +
                             offset.z() * offset.z() / (across * across));
  return s >= 1.0 ? 0.0 : std::pow(1.0 - s, 4) * (1.0 + 4.0 * s);
}

struct Sampled {
  double weight_sum = 0.0;
  Vec3 velocity = Vec3::Zero(), pressure_force = Vec3::Zero(), acceleration = Vec3::Zero();
};

/// A grain other than sample()'s default: its radius, its voidage, and whether the self-induced correction is on.
struct SampledGrain {
  double radius = 0.0025;
  double voidage = 1.0;
  bool self_induced = false;
};

/// Water filling [0, 0.1]^3 on the l0 = 1 cm lattice (layers at 5, 15, ... mm), velocity a + B x and pressure
/// gradient g0 + G x; one grain (radius 2.5 mm unless `grain` says otherwise) at `centre` sampled once (added mass
/// on: the acceleration too).
Sampled sample(const Vec3& centre, double vertical, bool periodic, const Vec3& a, const Eigen::Matrix3d& b,
               const Vec3& g0, const Eigen::Matrix3d& g, const SampledGrain& grain_setting = {}) {
  Model model = test::small_coupled_model(kKernelSpacing);
  model.coupling.added_mass = true;
  model.coupling.self_induced_velocity = grain_setting.self_induced;
  model.coupling.sampling_vertical_radius = vertical;
  model.tank.origin = Vec3::Zero();
  model.tank.size = Vec3(kBox, kBox, kBox);
  if (periodic) model.tank.periodic = {true, true, false};
  World world;
  test::fill_with_water(world, Vec3(kBox, kBox, kBox), kKernelSpacing);
  FluidParticles& water = *world.fluid;
  for (std::size_t j = 0; j < water.size(); ++j) {
    water.velocity[j] = a + b * water.position[j];
    water.pressure_gradient[j] = g0 + g * water.position[j];
  }
  world.fluid_sample.emplace();
  world.solids.emplace();
  const std::size_t grain = world.solids->add(centre, Vec3::Zero(), grain_setting.radius, 2650.0, 0, 0);
  world.solids->voidage[grain] = grain_setting.voidage;
  FluidSampleCopy copy;
  SolidFluidSampling sampling(model);
  for (System* system : std::vector<System*>{&copy, &sampling}) {
    const Access access = system->access();
    SystemContext context(world, model, *system, access, 0.0, 1.0e-3);
    system->run(context);
  }
  Sampled out;
  out.weight_sum = world.solids->fluid_weight[grain];
  out.velocity = world.solids->fluid_velocity[grain];
  out.pressure_force = world.solids->pressure_force[grain];
  out.acceleration = world.solids->fluid_acceleration[grain];
  return out;
}

}  // namespace

TEST_CASE("ellipsoidal sampling kernel: the metric's weights are the formula's, and R_v = 0 is the isotropic kernel") {
  const double horizontal = 0.007;
  for (const double vertical : {0.0, 0.0035, 0.0025, 0.01}) {
    const double stretch = sampling_vertical_stretch(horizontal, vertical);
    const WendlandKernel kernel(horizontal);
    for (const Vec3& offset : {Vec3(0.0, 0.0, 0.0), Vec3(0.003, -0.002, 0.001), Vec3(0.0, 0.0, 0.002),
                               Vec3(0.0, 0.0, -0.0034), Vec3(0.0068, 0.0, 0.0), Vec3(0.001, 0.001, 0.0024),
                               Vec3(0.005, 0.004, 0.0)}) {
      CAPTURE(vertical);
      CAPTURE(offset.transpose());
      const double weight = kernel.weight(std::sqrt(sampling_distance_squared(offset, stretch)));
      CHECK(weight == doctest::Approx(formula_weight(offset, horizontal, vertical)).epsilon(1e-13).scale(1e-13));
      if (vertical == 0.0) CHECK(sampling_distance_squared(offset, stretch) == offset.squaredNorm());
    }
  }
  // R_v at or above R_h: the sphere (stretch exactly 1).
  CHECK(sampling_vertical_stretch(horizontal, 0.01) == 1.0);
  CHECK(sampling_vertical_stretch(horizontal, 0.0035) == 2.0);
}

TEST_CASE("ellipsoidal sampling kernel: a grain reads a linear field at its centre, its weight sum is the formula's") {
  const Vec3 a(0.1, -0.05, 0.02), g0(30.0, -20.0, 9810.0);
  Eigen::Matrix3d b, g;
  b << 0.3, -1.1, 4.0, 0.7, 0.2, -2.5, -0.4, 1.3, 0.9;  // [1/s], every component
  g << 200.0, -50.0, 800.0, 10.0, -300.0, 120.0, -60.0, 40.0, 500.0;  // [Pa/m^2]
  const double horizontal = 0.0025 + 2.4 * kKernelSpacing;
  const double volume = 4.0 / 3.0 * std::numbers::pi * 0.0025 * 0.0025 * 0.0025;
  // Centres on a lattice node (x, y) and between layers (z = 50 mm), or between layers (55 mm) and on the x seam of
  // a periodic box: the lattice mirrors through the centre in each case.
  struct Case {
    Vec3 centre;
    bool periodic;
  };
  for (const Case& c : {Case{Vec3(0.05, 0.05, 0.05), false}, Case{Vec3(0.045, 0.055, 0.055), false},
                        Case{Vec3(0.0, 0.05, 0.055), true}}) {
    for (const double vertical : {0.0, 0.015, 0.012, 0.02}) {
      CAPTURE(c.centre.transpose());
      CAPTURE(c.periodic);
      CAPTURE(vertical);
      // In the periodic box the field is evaluated at the real particles: a + B x is linear through the seam only
      // along y and z, so there the x column of B and G is left out.
      Eigen::Matrix3d bb = b, gg = g;
      if (c.periodic) {
        bb.col(0).setZero();
        gg.col(0).setZero();
      }
      const Sampled linear = sample(c.centre, vertical, c.periodic, a, bb, g0, gg);
      // The weight sum against the formula over the water (nearest images across the seam).
      double expected_sum = 0.0;
      for (int i = 0; i < 10; ++i)
        for (int j = 0; j < 10; ++j)
          for (int k = 0; k < 10; ++k) {
            Vec3 offset = Vec3((i + 0.5) * kKernelSpacing, (j + 0.5) * kKernelSpacing, (k + 0.5) * kKernelSpacing) - c.centre;
            if (c.periodic) offset.x() -= kBox * std::round(offset.x() / kBox);
            expected_sum += formula_weight(offset, horizontal, vertical);
          }
      REQUIRE(expected_sum > 0.0);
      CHECK(linear.weight_sum == doctest::Approx(expected_sum).epsilon(1e-12));
      const Vec3 velocity = a + bb * c.centre, gradient = g0 + gg * c.centre;
      const double velocity_scale = a.norm() + bb.norm() * horizontal;
      const double gradient_scale = g0.norm() + gg.norm() * horizontal;
      CHECK((linear.velocity - velocity).norm() < 1e-12 * velocity_scale);
      CHECK((linear.pressure_force + volume * gradient).norm() < 1e-12 * volume * gradient_scale);
      const Vec3 acceleration = test::small_model().gravity - gradient / 1000.0;  // the water's default density
      CHECK((linear.acceleration - acceleration).norm() < 1e-12 * gradient_scale / 1000.0);
    }
  }
}


TEST_CASE("a dilute grain larger than l0 samples with the kernel it has at l0 = r, a bed grain with r + r_e") {
  // coupling_kernel_radius: r + r_e for r <= l0 (bit for bit) and for a grain the self-induced correction does not
  // act on; r + (r_e / l0) r for a dilute grain with r > l0, which no longer narrows as l0 shrinks.
  const double r_e = 2.4 * kKernelSpacing;
  CHECK(coupling_kernel_radius(0.004, r_e, kKernelSpacing, true) == 0.004 + r_e);
  CHECK(coupling_kernel_radius(kKernelSpacing, r_e, kKernelSpacing, true) == kKernelSpacing + r_e);
  CHECK(coupling_kernel_radius(0.012, r_e, kKernelSpacing, false) == 0.012 + r_e);
  CHECK(coupling_kernel_radius(0.012, r_e, kKernelSpacing, true) == doctest::Approx(0.012 * 3.4).epsilon(1e-15));
  for (const double spacing : {0.012, 0.008, 0.004, 0.002})  // 1.7 d whatever the finer water (r_e = 2.4 l0)
    CHECK(coupling_kernel_radius(0.012, 2.4 * spacing, spacing, true) == doctest::Approx(0.0408).epsilon(1e-14));

  // On the system that runs: a 24 mm grain (d/l0 = 2.4) in the 1 cm water, dilute (eps = 1) and in a bed (0.5).
  const Vec3 centre(0.05, 0.05, 0.05);
  for (const double voidage : {1.0, 0.5}) {
    CAPTURE(voidage);
    const Sampled read = sample(centre, 0.0, false, Vec3::Zero(), Eigen::Matrix3d::Zero(), Vec3::Zero(),
                                Eigen::Matrix3d::Zero(), SampledGrain{0.012, voidage, true});
    const double radius = voidage > 0.8 ? 0.012 * 3.4 : 0.012 + r_e;
    double expected_sum = 0.0;
    for (int i = 0; i < 10; ++i)
      for (int j = 0; j < 10; ++j)
        for (int k = 0; k < 10; ++k)
          expected_sum += formula_weight(
              Vec3((i + 0.5) * kKernelSpacing, (j + 0.5) * kKernelSpacing, (k + 0.5) * kKernelSpacing) - centre,
              radius, 0.0);
    CHECK(read.weight_sum == doctest::Approx(expected_sum).epsilon(1e-12));
  }
}

}  // namespace riffle
