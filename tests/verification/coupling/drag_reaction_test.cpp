// Where the drag reaction lands (`[coupling] drag_reaction`, docs/COUPLING.md "Where the drag reaction lands"). With
// "sampling_kernel" each grain's drag impulse J goes to the fluid particles within R = r + r_e with the normalised
// Wendland weights w_j / W it samples the water with. What the theory says, and what these tests check on the
// systems that run (FluidSampleCopy, SolidFluidSampling, SolidDrag, FluidDragReaction):
//  - an exchange: the water receives exactly minus the grains' impulse (times 1/eps in the mixture reading), in a
//    closed box and across a periodic seam, and each fluid particle receives -J share w_j / (W l0^3), the kernel's
//    own share (Eq. 26's form);
//  - dissipative grain by grain: the reaction's power on the water, sum_j u_j . f_j l0^3, is -share J . u_bar, where
//    u_bar = sum_j w_j u_j / W is what the grain sampled; for a held grain J = k u_bar dt (k > 0), so it is <= 0 for
//    any water velocity field; the grid's footprint differs from the sampled one and is not bound to that sign;
//  - the sums do not depend on the thread count (byte-identical on 1 and 2 threads).
// Each also with the ellipsoidal kernel of `[coupling] sampling_vertical_radius` (docs/COUPLING.md, "A thin bed's
// sampling"): the same statements hold for any normalised footprint the grain both samples and spreads with.
#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/output/checkpoint.hpp"
#include "engine/run/simulation.hpp"
#include "engine/scene/scene.hpp"
#include "engine/setup/fluid_layout.hpp"
#include "systems/coupling/fluid_drag_reaction.hpp"
#include "systems/coupling/fluid_sample_copy.hpp"
#include "systems/coupling/solid_drag.hpp"
#include "systems/coupling/solid_drag_law.hpp"
#include "systems/coupling/solid_fluid_sampling.hpp"
#include "systems/physics/mps/mps_kernel.hpp"
#include "tests/support/test_support.hpp"
#include "tests/support/scene_builder.hpp"

using riffle::test::SceneBuilder;

namespace riffle {
namespace {

constexpr double kReactionSpacing = 0.01;
constexpr double kVolume = kReactionSpacing * kReactionSpacing * kReactionSpacing;

/// The small test model with water at l0 = 1 cm and the reaction spread by the sampling kernel (or the grid);
/// periodic along x and y in a 0.1 m box if asked.
Model reaction_model(bool kernel, bool mixture, bool periodic = false, double vertical_radius = 0.0) {
  Model model = test::small_coupled_model(kReactionSpacing);
  model.coupling.sampling_vertical_radius = vertical_radius;
  model.coupling.fluid_velocity = mixture ? CouplingModel::FluidVelocity::kMixture : CouplingModel::FluidVelocity::kPore;
  model.coupling.sampling_kernel_reaction = kernel;
  if (periodic) {
    model.tank.origin = Vec3::Zero();
    model.tank.size = Vec3(0.1, 0.1, 0.1);
    model.tank.periodic = {true, true, false};
  }
  return model;
}

struct GrainSpec {
  Vec3 centre;
  double radius;
  Vec3 impulse;
  double voidage;
};

/// Water filling [0, 0.1]^3 on the l0 lattice, and the grains with their pending drag impulses.
World reaction_world(const std::vector<GrainSpec>& grains) {
  World world;
  test::fill_with_water(world, Vec3(0.1, 0.1, 0.1), kReactionSpacing);
  world.solids.emplace();
  for (const GrainSpec& grain : grains) {
    const std::size_t slot = world.solids->add(grain.centre, Vec3::Zero(), grain.radius, 2650.0, 0, 0);
    world.solids->drag_impulse[slot] = grain.impulse;
    world.solids->voidage[slot] = grain.voidage;
  }
  return world;
}

void run_reaction(const Model& model, World& world) {
  FluidDragReaction reaction(model);
  const Access access = reaction.access();
  SystemContext context(world, model, reaction, access, 0.0, 1.0e-3);
  reaction.run(context);
}

Vec3 received_momentum(const World& world) {
  Vec3 received = Vec3::Zero();
  for (const Vec3& per_volume : world.fluid->drag_reaction) received += per_volume * kVolume;
  return received;
}

/// The offset to the nearest image of the water, for checking the footprint independently of the system's grids.
Vec3 wrapped_offset(Vec3 offset, bool periodic) {
  if (periodic)
    for (int axis = 0; axis < 2; ++axis) offset[axis] -= 0.1 * std::round(offset[axis] / 0.1);
  return offset;
}

/// The sampling kernel's weight written out from its definition (docs/COUPLING.md): (1 - s)^4 (1 + 4 s) for s < 1,
/// s^2 = (dx^2 + dy^2) / R_h^2 + dz^2 / R_v^2, R_v = min(vertical, R_h), or R_h when vertical = 0 (the isotropic
/// Wendland kernel of mps_kernel.hpp).
double kernel_weight(const Vec3& offset, double horizontal, double vertical) {
  const double across = vertical > 0.0 ? std::min(vertical, horizontal) : horizontal;
  const double s = std::sqrt((offset.x() * offset.x() + offset.y() * offset.y()) / (horizontal * horizontal) +
                             offset.z() * offset.z() / (across * across));
  return s >= 1.0 ? 0.0 : std::pow(1.0 - s, 4) * (1.0 + 4.0 * s);
}

}  // namespace

TEST_CASE("sampling-kernel reaction: the water receives exactly minus the grains' impulse, closed and across a seam") {
  // Grains of three sizes, one by a wall (its sphere cut by the water's edge), one half out of the water's top, one
  // in a bed (eps 0.45); in the periodic box one on the x seam and one at the x-y corner.
  const std::vector<GrainSpec> closed{
      {Vec3(0.05, 0.05, 0.05), 0.0025, Vec3(1.0e-4, -2.0e-5, 3.0e-4), 0.9},
      {Vec3(0.013, 0.021, 0.009), 0.005, Vec3(-5.0e-5, 7.0e-5, 1.0e-5), 0.45},
      {Vec3(0.08, 0.02, 0.098), 0.0075, Vec3(2.0e-5, 0.0, -4.0e-5), 0.7}};
  const std::vector<GrainSpec> seam{
      {Vec3(0.002, 0.05, 0.05), 0.0025, Vec3(1.0e-4, -2.0e-5, 3.0e-4), 0.6},
      {Vec3(0.098, 0.003, 0.06), 0.005, Vec3(-5.0e-5, 7.0e-5, 1.0e-5), 0.45},
      {Vec3(0.05, 0.05, 0.04), 0.0025, Vec3(2.0e-5, 0.0, -4.0e-5), 1.0}};
  // R_v = 1.5 l0: a kernel 1.8-3.2 times narrower across than along (R_h = r + 2.4 l0).
  for (const double vertical : {0.0, 0.015})
  for (const bool periodic : {false, true}) {
    for (const bool mixture : {false, true}) {
      CAPTURE(vertical);
      CAPTURE(periodic);
      CAPTURE(mixture);
      const std::vector<GrainSpec>& grains = periodic ? seam : closed;
      const Model model = reaction_model(true, mixture, periodic, vertical);
      World world = reaction_world(grains);
      run_reaction(model, world);
      Vec3 expected = Vec3::Zero();
      double scale = 0.0;
      for (const GrainSpec& grain : grains) {
        expected -= mixture ? Vec3(grain.impulse / grain.voidage) : grain.impulse;
        scale += grain.impulse.norm() / (mixture ? grain.voidage : 1.0);
      }
      CHECK((received_momentum(world) - expected).norm() < 1e-12 * scale);
      for (const Vec3& impulse : world.solids->drag_impulse) CHECK(impulse.isZero(0.0));
      // Each grain alone: every fluid particle gets -J share w_j / (W l0^3), its weights those of the kernel on
      // R = r + r_e (r_e = 2.4 l0) around the grain, across the seams at the nearest image.
      for (const GrainSpec& grain : grains) {
        World alone = reaction_world({grain});
        run_reaction(model, alone);
        const double horizontal = grain.radius + 2.4 * kReactionSpacing;
        const FluidParticles& water = *alone.fluid;
        double weight_sum = 0.0;
        for (std::size_t j = 0; j < water.size(); ++j)
          weight_sum += kernel_weight(wrapped_offset(water.position[j] - grain.centre, periodic), horizontal, vertical);
        REQUIRE(weight_sum > 0.0);
        const double share = mixture ? 1.0 / grain.voidage : 1.0;
        double worst = 0.0, far_side = 0.0;
        for (std::size_t j = 0; j < water.size(); ++j) {
          const double weight =
              kernel_weight(wrapped_offset(water.position[j] - grain.centre, periodic), horizontal, vertical);
          const Vec3 expected_j = -grain.impulse * (share * weight / (weight_sum * kVolume));
          worst = std::max(worst, (water.drag_reaction[j] - expected_j).norm());
          if (std::abs(water.position[j].x() - grain.centre.x()) > 0.05) far_side += weight / weight_sum;
        }
        CHECK(worst < 1e-12 * grain.impulse.norm() * share / kVolume);
        // A grain on the seam gives a share of its impulse to the water on the far side of it (the kernel's weight
        // there, about half for a sphere centred 2 mm from the seam), on the real particles.
        if (periodic && grain.centre.x() < 0.01) CHECK(far_side > 0.3);
        if (periodic && grain.centre.x() > 0.09) CHECK(far_side > 0.3);
      }
    }
  }
}

TEST_CASE("sampling-kernel reaction: a held grain in sheared water pushes the water it samples, and dissipates") {
  // A held 2 mm grain at z = 3 mm over the floor, in a bed (eps = 0.45), the water filling z > 0 on the l0 = 2.5 mm
  // lattice (layers at 1.25, 3.75, ... mm), r_e = 2.4 l0: the sampling sphere R = 7 mm is cut by the floor, as
  // under seed 003's held bed (docs/RESULTS.md). The water is a shear flow u_x = s (z - z0) that
  // runs backwards below z0. One step of the systems that run: the water copied (FluidSampleCopy), sampled
  // (SolidFluidSampling), the drag integrated (SolidDrag), spread back (FluidDragReaction).
  // Theory: a footprint with weights p_j (sum 1) gives the reaction power P = -share J . sum_j p_j u_j per step,
  // J = k u_bar dt (k > 0, held grain), u_bar the sampled mean. In this linear field sum_j p_j u_j = s (c_p - z0),
  // c_p the footprint's height centroid, so P = -share k dt s^2 (c_w - z0)(c_p - z0) with c_w the sampling
  // centroid: <= 0 for every z0 when c_p = c_w (the kernel), and > 0 for z0 between c_w and c_p otherwise (the grid,
  // whose footprint's centroid is not the sampling one).
  const double l0 = 0.0025, shear = 40.0, radius = 0.001;
  const Vec3 grain_centre(0.02, 0.02, 0.003);
  struct Outcome {
    double power = 0.0, band_power = 0.0;  ///< [J] sum_j u_j . f_j l0^3, all and below the sampled centroid
    Vec3 impulse = Vec3::Zero(), sampled = Vec3::Zero(), pushed = Vec3::Zero();
    double centroid = 0.0;
  };
  const double share = 1.0 / 0.45;  // the mixture reading (the default): the water takes J / eps
  const auto run = [&](bool kernel, double z0, double vertical = 0.0) {
    Model model = test::small_coupled_model(l0);
    model.coupling.sampling_vertical_radius = vertical;
    model.coupling.sampling_kernel_reaction = kernel;
    model.tank.origin = Vec3::Zero();
    model.tank.size = Vec3(0.04, 0.04, 0.02);
    World world;
    test::fill_with_water(world, Vec3(0.04, 0.04, 0.02), l0);
    FluidParticles& water = *world.fluid;
    for (std::size_t j = 0; j < water.size(); ++j) water.velocity[j] = Vec3(shear * (water.position[j].z() - z0), 0, 0);
    world.fluid_sample.emplace();
    world.solids.emplace();
    const std::size_t grain = world.solids->add(grain_centre, Vec3::Zero(), radius, 2650.0, 0, 0);
    world.solids->voidage[grain] = 0.45;
    const double dt = 5.0e-4;
    FluidSampleCopy copy;
    SolidFluidSampling sampling(model);
    SolidDragLaw drag_law(model);
    SolidDrag drag(model);
    FluidDragReaction reaction(model);
    for (System* system : std::vector<System*>{&copy, &sampling, &drag_law, &drag, &reaction}) {
      const Access access = system->access();
      SystemContext context(world, model, *system, access, 0.0, dt);
      system->run(context);
    }
    Outcome out;
    out.impulse = world.solids->drag_force[grain] * dt;
    out.sampled = world.solids->fluid_velocity[grain];
    double weight_sum = 0.0, pushed_weight = 0.0;
    for (std::size_t j = 0; j < water.size(); ++j) {
      const double weight = kernel_weight(water.position[j] - grain_centre, radius + 2.4 * l0, vertical);
      weight_sum += weight;
      out.centroid += weight * water.position[j].z();
    }
    out.centroid /= weight_sum;
    const Vec3 direction = out.impulse.normalized();
    for (std::size_t j = 0; j < water.size(); ++j) {
      const Vec3 pushed = water.drag_reaction[j] * (l0 * l0 * l0);
      const double power = water.velocity[j].dot(pushed);
      out.power += power;
      if (water.position[j].z() < out.centroid) out.band_power += power;
      const double along = -pushed.dot(direction);  // how much of the push this particle takes
      out.pushed += along * water.velocity[j];
      pushed_weight += along;
    }
    out.pushed /= pushed_weight;
    return out;
  };
  // z0 at the grain's centre: the water around it runs back, the sampled mean forward (the floor cuts the sphere).
  const double first_z0 = 0.003;
  const Outcome kernel = run(true, first_z0);
  const Outcome grid = run(false, first_z0);
  REQUIRE(kernel.sampled.x() > 0.0);
  REQUIRE(kernel.impulse.x() > 0.0);
  // The kernel: the weighted mean of the water it pushes is the water it sampled, and the power is
  // -share J . u_bar < 0 (to rounding).
  CHECK((kernel.pushed - kernel.sampled).norm() < 1e-12 * kernel.sampled.norm());
  const double expected_power = -share * kernel.impulse.dot(kernel.sampled);
  CHECK(expected_power < 0.0);
  CHECK(std::abs(kernel.power - expected_power) < 1e-12 * std::abs(expected_power));
  CHECK((grid.impulse - kernel.impulse).norm() < 1e-15 * kernel.impulse.norm());  // the same sampling and drag
  MESSAGE("held grain at z = 3 mm, u_x = ", shear, " (z - ", first_z0, "): sampled u_x ", kernel.sampled.x(),
          " m/s (sampling centroid z = ", kernel.centroid, " m); grid-pushed mean u_x ", grid.pushed.x(),
          " m/s; power [J per step] kernel ", kernel.power, " (band below the centroid ", kernel.band_power,
          "), grid ", grid.power, " (band ", grid.band_power, ")");
  // The grid's footprint centroid, from the water it pushed; then a z0 between the two centroids.
  const double grid_centroid = first_z0 + grid.pushed.x() / shear;
  REQUIRE(std::abs(grid_centroid - kernel.centroid) > 0.01 * l0);
  const double second_z0 = 0.5 * (grid_centroid + kernel.centroid);
  const Outcome kernel_between = run(true, second_z0);
  const Outcome grid_between = run(false, second_z0);
  MESSAGE("z0 = ", second_z0, " m (between the sampling centroid ", kernel.centroid, " and the grid's ", grid_centroid,
          "): sampled u_x ", kernel_between.sampled.x(), " m/s, grid-pushed ", grid_between.pushed.x(),
          " m/s; power kernel ", kernel_between.power, ", grid ", grid_between.power, " J per step");
  CHECK(kernel_between.power < 0.0);
  CHECK(std::abs(kernel_between.power + share * kernel_between.impulse.dot(kernel_between.sampled)) <
        1e-12 * std::abs(kernel_between.power));
  CHECK(grid_between.power > 0.0);  // the held grain's reaction does work on the water
  // The ellipsoidal kernel (sampling_vertical_radius = r + l0 and l0, the held large bed's choices): the footprint
  // is still the sampled one, so the same power statement holds exactly, for a z0 below, at and above the grain.
  for (const double vertical : {radius + l0, l0}) {
    for (const double z0 : {0.0, 0.003, 0.006}) {
      CAPTURE(vertical);
      CAPTURE(z0);
      const Outcome squeezed = run(true, z0, vertical);
      REQUIRE(squeezed.impulse.norm() > 0.0);
      CHECK((squeezed.pushed - squeezed.sampled).norm() < 1e-12 * squeezed.sampled.norm());
      const double expected = -share * squeezed.impulse.dot(squeezed.sampled);
      CHECK(expected < 0.0);
      CHECK(std::abs(squeezed.power - expected) < 1e-12 * std::abs(expected));
      if (z0 == first_z0)
        MESSAGE("R_v = ", vertical, " m: sampled u_x ", squeezed.sampled.x(), " m/s (centroid z = ", squeezed.centroid,
                " m; isotropic ", kernel.centroid, " m), power ", squeezed.power, " J per step");
    }
  }
}

namespace {

/// The reaction of a bed of `count` grains (pseudo-random, fixed) on `threads` threads, as raw bytes.
std::string reaction_bytes(bool periodic, int threads, double vertical = 0.0) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  std::vector<GrainSpec> grains;
  std::uint64_t state = 12345;
  const auto next = [&state] {  // a fixed LCG: the same bed every call
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) / 9007199254740992.0;
  };
  for (int k = 0; k < 300; ++k)
    grains.push_back({Vec3(0.1 * next(), 0.1 * next(), 0.04 * next()), 0.002 + 0.004 * next(),
                      Vec3(next() - 0.5, next() - 0.5, next() - 0.5) * 1e-4, 0.4 + 0.6 * next()});
  const Model model = reaction_model(true, true, periodic, vertical);
  World world = reaction_world(grains);
  run_reaction(model, world);
  const std::vector<Vec3>& reaction = world.fluid->drag_reaction;
  return std::string(reinterpret_cast<const char*>(reaction.data()), reaction.size() * sizeof(Vec3));
}

}  // namespace

TEST_CASE("sampling-kernel reaction: byte-identical on one and two threads, and through a scene") {
  for (const bool periodic : {false, true}) {
    CAPTURE(periodic);
    CHECK(reaction_bytes(periodic, 1) == reaction_bytes(periodic, 2));
    CHECK(reaction_bytes(periodic, 1, 0.015) == reaction_bytes(periodic, 2, 0.015));
    CHECK(reaction_bytes(periodic, 1, 0.015) != reaction_bytes(periodic, 1));  // the key reaches the spreading
  }
  // The key through a scene: a 5 mm grain settling in a periodic box of water, 40 steps, 1 and 2 threads.
  const std::string scene = SceneBuilder().run({.end_time = 1.0, .dt = 1.0e-3})
      .material("grain", {.density = 2650.0, .young_modulus = 1.0e8, .poisson_ratio = 0.3})
      .tank({.size = {0.08, 0.08, 0.2}, .open_faces = {"z_max"}, .periodic = {"x", "y"}, .wall_material = "grain"})
      .contact({.restitution = 0.5, .friction = 0.5})
      .sphere({.position = {0.002, 0.078, 0.12}, .radius = 0.005, .material = "grain"}).fluid({.spacing = 0.01})
      .fluid_box({0.0, 0.0, 0.0}, {0.08, 0.08, 0.16}).coupling().set("drag_reaction", "sampling_kernel").toml();
  const auto bytes_after = [&](int threads, const std::string& extra) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    auto simulation = Simulation::from_model(parse_scene(scene + extra, "kernel.toml"));
    REQUIRE(simulation->model().coupling.sampling_kernel_reaction);
    for (int step = 0; step < 40; ++step) simulation->step();
    REQUIRE(simulation->world().step_status.ok());
    return encode_checkpoint(simulation->checkpoint_data());
  };
  CHECK(bytes_after(1, "") == bytes_after(2, ""));
  // With the ellipsoidal kernel (R_v = 1.2 l0): sampling and spreading alike on 1 and 2 threads.
  CHECK(bytes_after(1, "sampling_vertical_radius = 0.012\n") == bytes_after(2, "sampling_vertical_radius = 0.012\n"));
}

}  // namespace riffle
