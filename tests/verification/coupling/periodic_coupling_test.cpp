// Grains and MPS water together in a periodic tank (docs/COUPLING.md, "Across a periodic seam"): a grain samples the
// water, and spreads its drag reaction back, through its images across the seams (the nearest image of each fluid
// particle), and the voidage and drag-reaction grids wrap along the periodic axes. What the theory says:
//  - a periodic box has no place: the same scene moved by half a period along x and y (grain and water lattice
//    alike) is the same problem, so a grain whose sampling sphere the seams cut (by x and y: the corner) has the
//    drag, voidage, sampled weight and velocity history of the grain half a period away, whose sphere is whole, to
//    rounding (the sums run in another order; nothing else differs);
//  - the drag reaction is an exchange: the water receives exactly minus the grains' impulse (to rounding), also from
//    grains on a seam and at the corner, on the real fluid particles on both sides of the seam; with the kernel
//    spreading (no grid) the footprint of a grain on the seam is that of the grain half a period away, moved;
//  - runs are byte-identical on one and two threads and after a resume in mid-run.
#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "engine/output/checkpoint.hpp"
#include "engine/run/simulation.hpp"
#include "engine/scene/scene.hpp"
#include "engine/setup/fluid_layout.hpp"
#include "systems/coupling/fluid_drag_reaction.hpp"
#include "tests/support/test_support.hpp"
#include "tests/support/scene_builder.hpp"

using riffle::test::SceneBuilder;

namespace riffle {
namespace {

/// A 5 mm grain (2650 kg/m^3) settling from (x, y, 0.12) in still water 0.16 m deep, l0 = 1 cm, in a tank of
/// 0.08 x 0.08 m periodic along x and y (sampling radius r + r_e = 0.029 m < half the period).
std::string periodic_settling_scene(double x, double y, const std::string& extra = "") {
  return SceneBuilder().run({.end_time = 1.0, .dt = 1.0e-3})
             .material("grain", {.density = 2650.0, .young_modulus = 1.0e8, .poisson_ratio = 0.3})
             .material("glass", {.density = 2500.0, .young_modulus = 1.0e8, .poisson_ratio = 0.3})
             .tank({.size = {0.08, 0.08, 0.2}, .open_faces = {"z_max"}, .periodic = {"x", "y"},
                    .wall_material = "glass"})
             .contact({.restitution = 0.5, .friction = 0.5})
             .sphere({.position = {x, y, 0.12}, .radius = 0.005, .material = "grain"})
             .fluid({.spacing = 0.01}).fluid_box({0.0, 0.0, 0.0}, {0.08, 0.08, 0.16}).toml() +
         extra;
}

struct GrainRecord {
  Vec3 velocity, drag, fluid_velocity, position;
  double voidage = 0.0, weight = 0.0;
};

std::vector<GrainRecord> settle(const std::string& text, int steps) {
  auto simulation = Simulation::from_model(parse_scene(text, "settling.toml"));
  std::vector<GrainRecord> history;
  for (int step = 0; step < steps; ++step) {
    simulation->step();
    REQUIRE(simulation->world().step_status.ok());
    const Solids& grains = *simulation->world().solids;
    REQUIRE(grains.size() == 1);
    history.push_back({grains.velocity[0], grains.drag_force[0], grains.fluid_velocity[0], grains.position[0],
                       grains.voidage[0], grains.fluid_weight[0]});
  }
  return history;
}

}  // namespace

// The seam grain starts at (2 mm, 78 mm): its sampling sphere (29 mm) is cut by the x seam and the y seam. The other
// starts half a period away, (42 mm, 38 mm), in the middle. The fluid lattice (l0/2 + k l0) maps onto itself under
// the shift, and both grids (voidage, drag reaction) hold whole, even numbers of cells per period here (0.08 m over
// 0.668 x 29 mm cells: 4; over the voidage cells: even too), so the two problems are the same to rounding. Rounding:
// the sums over fluid particles run in other orders (slot orders differ), a relative 1e-16 per operation, which
// the pressure solve and 150 steps amplify by a few orders (measured: 4e-15 at most): 1e-12 of each quantity's
// scale is far below any seam error (a sphere cut in half samples half the weight: a 50 % error, and a drag reaction
// lost at the seam moves the water differently by the drag's order) and far above rounding.
TEST_CASE("a grain settling across the seam and corner matches the grain half a period away, to rounding") {
  // Both voidage estimates: the self-corrected one reads 1 for a lone grain anywhere; main's trilinear one includes
  // the grain's own volume and reads 0.63-0.99 depending on the grain's place among the nodes, which the wrapping
  // grid must give the seam grain as to the grain in the middle.
  for (const std::string estimate : {"self_corrected", "cloud_in_cell"}) {
    CAPTURE(estimate);
    const std::string extra = "\n[coupling]\nvoidage_estimate = \"" + estimate + "\"\n";
    const int steps = 150;
    const std::vector<GrainRecord> seam = settle(periodic_settling_scene(0.002, 0.078, extra), steps);
    const std::vector<GrainRecord> middle = settle(periodic_settling_scene(0.042, 0.038, extra), steps);
    const double speed = std::max(1e-3, middle.back().velocity.norm());
    double drag_scale = 0.0, weight_scale = 0.0;
    for (const GrainRecord& record : middle) {
      drag_scale = std::max(drag_scale, record.drag.norm());
      weight_scale = std::max(weight_scale, record.weight);
    }
    REQUIRE(drag_scale > 0.0);
    REQUIRE(weight_scale > 0.0);
    double worst_velocity = 0.0, worst_drag = 0.0, worst_voidage = 0.0, worst_weight = 0.0;
    for (int step = 0; step < steps; ++step) {
      const GrainRecord& a = seam[static_cast<std::size_t>(step)];
      const GrainRecord& b = middle[static_cast<std::size_t>(step)];
      worst_velocity = std::max(worst_velocity, (a.velocity - b.velocity).norm() / speed);
      worst_drag = std::max(worst_drag, (a.drag - b.drag).norm() / drag_scale);
      worst_voidage = std::max(worst_voidage, std::abs(a.voidage - b.voidage));
      worst_weight = std::max(worst_weight, std::abs(a.weight - b.weight) / weight_scale);
    }
    CAPTURE(worst_velocity);
    CAPTURE(worst_drag);
    CAPTURE(worst_voidage);
    CAPTURE(worst_weight);
    CAPTURE(middle.back().voidage);
    CHECK(middle.back().velocity.z() < -0.05);  // it settles (terminal slip ~0.3 m/s for this grain)
    if (estimate == "cloud_in_cell") CHECK(middle.back().voidage < 0.999);  // its own volume counts
    CHECK(worst_velocity < 1e-12);
    CHECK(worst_drag < 1e-12);
    CHECK(worst_voidage < 1e-12);
    CHECK(worst_weight < 1e-12);
  }
}

// FluidDragReaction on a periodic 0.1 m box of water (l0 = 1 cm), grains on the x seam, at the x-y corner and inside:
// the water receives minus the grains' impulse (each grain's weights are normalised over all the fluid particles
// they reach, across the seam included), to a few ulps of the largest impulse, with the grid (cells wrapping the
// period) and with the kernel spreading. The kernel spreading has no grid: a grain on the seam gives each fluid
// particle what the grain half a period away gives the particle half a period away, to rounding.
TEST_CASE("the water receives exactly minus the drag impulse of grains on the seam and corner, on both sides") {
  const auto make_world = [](const std::vector<Vec3>& centres, const std::vector<double>& voidages) {
    World world;
    test::fill_with_water(world, Vec3(0.1, 0.1, 0.1), 0.01);
    world.solids.emplace();
    for (std::size_t k = 0; k < centres.size(); ++k) {
      const std::size_t slot = world.solids->add(centres[k], Vec3::Zero(), 0.0025, 1318.0, 0, 0);
      world.solids->drag_impulse[slot] = Vec3(1.0e-4, -2.0e-5 * static_cast<double>(k + 1), 3.0e-4);
      world.solids->voidage[slot] = voidages[k];
    }
    return world;
  };
  const auto make_model = [](bool kernel) {
    Model model = test::small_coupled_model(0.01);
    model.coupling.self_induced_velocity = kernel;
    model.tank.origin = Vec3::Zero();
    model.tank.size = Vec3(0.1, 0.1, 0.1);
    model.tank.periodic = {true, true, false};
    return model;
  };
  const auto run = [](const Model& model, World& world) {
    FluidDragReaction reaction(model);
    const Access access = reaction.access();
    SystemContext context(world, model, reaction, access, 0.0, 1.0e-3);
    reaction.run(context);
  };
  const std::vector<Vec3> centres{Vec3(0.002, 0.05, 0.05), Vec3(0.098, 0.003, 0.06), Vec3(0.05, 0.05, 0.04)};
  for (const bool kernel : {false, true}) {
    CAPTURE(kernel);
    const Model model = make_model(kernel);
    World world = make_world(centres, {1.0, 1.0, 1.0});
    Vec3 given = Vec3::Zero();
    for (const Vec3& impulse : world.solids->drag_impulse) given += impulse;
    run(model, world);
    Vec3 received = Vec3::Zero();
    for (const Vec3& per_volume : world.fluid->drag_reaction) received += per_volume * 1.0e-6;  // times l0^3
    CHECK((received + given).norm() < 1e-15);
    for (const Vec3& impulse : world.solids->drag_impulse) CHECK(impulse.isZero(0.0));
  }
  // One grain on the seam and corner, one half a period away (the lattice maps onto itself), kernel spreading.
  const Model model = make_model(true);
  World seam = make_world({Vec3(0.002, 0.097, 0.05)}, {1.0});
  World middle = make_world({Vec3(0.052, 0.047, 0.05)}, {1.0});
  run(model, seam);
  run(model, middle);
  const FluidParticles& a = *seam.fluid;
  const FluidParticles& b = *middle.fluid;
  double largest = 0.0, worst = 0.0;
  std::size_t far_side = 0;
  for (std::size_t j = 0; j < a.size(); ++j) {
    // The particle half a period away (indices of the l0 lattice, wrapped).
    const Vec3 moved = a.position[j] + Vec3(0.05, -0.05, 0.0);
    std::size_t match = a.size();
    for (std::size_t k = 0; k < b.size() && match == a.size(); ++k) {
      Vec3 d = b.position[k] - moved;
      for (int axis = 0; axis < 2; ++axis) d[axis] -= 0.1 * std::round(d[axis] / 0.1);
      if (d.norm() < 1e-6) match = k;
    }
    REQUIRE(match < b.size());
    largest = std::max(largest, b.drag_reaction[match].norm());
    worst = std::max(worst, (a.drag_reaction[j] - b.drag_reaction[match]).norm());
    if (!a.drag_reaction[j].isZero(0.0) && a.position[j].x() > 0.05 && a.position[j].y() < 0.05) ++far_side;
  }
  REQUIRE(largest > 0.0);
  CHECK(far_side > 10);  // the corner image's share landed on the real particles across both seams
  CHECK(worst < 1e-12 * largest);
}

namespace {

std::string coupled_bytes_after(const std::string& text, int threads, int steps) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  auto simulation = Simulation::from_model(parse_scene(text, "coupled.toml"));
  for (int step = 0; step < steps; ++step) simulation->step();
  REQUIRE(simulation->world().step_status.ok());
  return encode_checkpoint(simulation->checkpoint_data());
}

}  // namespace

TEST_CASE("grains and water periodic: one and two threads, and a resumed run, give byte-identical checkpoints") {
  // The grain is thrown across the x and y seams (centre from (2, 78) mm at (-0.3, +0.2) m/s: it wraps within about
  // 0.01 s, before the checkpoint at step 27), so the resume carries wrapped positions and the halo of a grain that
  // changed sides. Once as the scene is, once with [coupling] viscous_stress (the grains sample the last step's
  // nu <lap u>, which the checkpoint must carry: format 7).
  Vec3 centre_without = Vec3::Zero();
  for (const bool viscous : {false, true}) {
  CAPTURE(viscous);
  std::string text = periodic_settling_scene(0.002, 0.078);
  const std::string sphere_material = "material = \"grain\"\n";
  REQUIRE(text.find(sphere_material) != std::string::npos);
  text.replace(text.find(sphere_material), sphere_material.size(),
               sphere_material + "velocity = [-0.3, 0.2, 0.0]\n");
  if (viscous) {
    REQUIRE(text.find("[coupling]") == std::string::npos);
    text += "\n[coupling]\nviscous_stress = true\n";
  }
  const std::string one = coupled_bytes_after(text, 1, 60);
  const std::string two = coupled_bytes_after(text, 2, 60);
  CHECK(one == two);
  const auto directory = test::scratch_dir("periodic_coupling_resume");
  auto first_part = Simulation::from_model(parse_scene(text, "coupled.toml"));
  for (int step = 0; step < 27; ++step) first_part->step();
  REQUIRE(first_part->world().step_status.ok());
  const std::string path = (directory / "part.ckpt").string();
  write_checkpoint(path, first_part->checkpoint_data());
  first_part.reset();
  auto resumed = Simulation::from_checkpoint(path);
  for (int step = 27; step < 60; ++step) resumed->step();
  REQUIRE(resumed->world().step_status.ok());
  // It crossed both seams: its centre now lies on the far side of each (x near 0.08 m, y near 0).
  const Vec3 centre = resumed->world().solids->position[0];
  CHECK(centre.x() > 0.06);
  CHECK(centre.x() < 0.08);
  CHECK(centre.y() >= 0.0);
  CHECK(centre.y() < 0.02);
  CHECK(encode_checkpoint(resumed->checkpoint_data()) == two);
  if (viscous) {
    // The force was on, sampled something (the water around a moving grain shears) and moved the grain.
    double largest = 0.0;
    for (const Vec3& force : resumed->world().solids->viscous_force) largest = std::max(largest, force.norm());
    CHECK(largest > 0.0);
    CHECK((centre - centre_without).norm() > 1e-9);
  } else {
    centre_without = centre;
  }
  }
}

}  // namespace riffle
