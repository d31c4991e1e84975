// The periodic box and its halo (systems/physics/geometry/periodic_box.hpp, components/halo.hpp): wrapping, the images near
// the seam, the halo's ghosts; the scene keys of [tank] periodic and their refusals; beds generated in a periodic
// box do not overlap across the seam.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "engine/scene/scene.hpp"
#include "engine/setup/bed_generation.hpp"
#include "systems/mps/fluid_pressure.hpp"
#include "systems/physics/geometry/periodic_box.hpp"
#include "tests/support/test_support.hpp"
#include "tests/support/scene_builder.hpp"

using namespace riffle;
using riffle::test::SceneBuilder;

namespace {

PeriodicBox box_xy() {
  PeriodicBox box;
  box.low = Vec3(-0.01, 0.0, 0.0);
  box.length = Vec3(0.04, 0.03, 0.02);
  box.periodic = {true, true, false};
  return box;
}

/// A grain scene in a box periodic along `periodic` (a TOML array body), with `extra` appended.
std::string periodic_scene(const std::string& tank_extra, const std::string& extra = "") {
  return SceneBuilder().run({.end_time = 0.01, .dt = 1.0e-4, .gravity = {0.0, 0.0, -9.81}})
             .material("grain", {.density = 2650.0, .young_modulus = 1.0e8, .poisson_ratio = 0.3})
             .tank({.size = {0.04, 0.03, 0.02}, .wall_material = "grain"}).verbatim(tank_extra + "\n")
             .contact({.restitution = 0.5, .friction = 0.5})
             .sphere({.position = {0.02, 0.015, 0.005}, .radius = 0.0025, .material = "grain"}).toml() +
         extra;
}

bool mentions(const std::vector<std::string>& problems, const std::string& text) {
  return std::any_of(problems.begin(), problems.end(),
                     [&](const std::string& line) { return line.find(text) != std::string::npos; });
}

}  // namespace

TEST_CASE("wrap moves a point by whole periods into the box (low to low + L) along the periodic axes only") {
  const PeriodicBox box = box_xy();
  CHECK(box.wrap(Vec3(0.031, 0.0305, 0.5)).isApprox(Vec3(-0.009, 0.0005, 0.5), 1e-15));
  CHECK(box.wrap(Vec3(-0.0101, -0.001, -1.0)).isApprox(Vec3(0.0299, 0.029, -1.0), 1e-15));
  CHECK(box.wrap(Vec3(0.0, 0.01, 0.0)) == Vec3(0.0, 0.01, 0.0));  // inside: unchanged, bit for bit
  // Several periods (never in a run: a grain moves far less than a period per sub-step) still land inside.
  const Vec3 far = box.wrap(Vec3(0.5, -0.7, 0.0));
  CHECK(box.inside(far));
  CHECK(std::abs(far.x() - (0.5 - 12 * 0.04)) < 1e-15);
  // -1e-18 past the low face rounds to low + L, which the box excludes: it is the low face itself.
  const Vec3 tiny = box.wrap(Vec3(-0.01 - 1e-18, 0.0, 0.0));
  CHECK(box.inside(tiny));
  CHECK(box.inside(box.wrap(Vec3(0.03, 0.03, 0.0))));  // exactly on the high faces: the low ones
  CHECK_FALSE(box.inside(Vec3(0.03, 0.0, 0.0)));
  // NaN stays NaN: the domain check diagnoses it.
  CHECK(std::isnan(box.wrap(Vec3(std::nan(""), 0.0, 0.0)).x()));
}

TEST_CASE("image_shifts lists the images a search within the cutoff can meet: faces and the corner") {
  const PeriodicBox box = box_xy();
  std::array<Vec3, 3> shifts;
  CHECK(box.image_shifts(Vec3(0.01, 0.015, 0.0), 0.005, shifts) == 0);  // far from every seam
  REQUIRE(box.image_shifts(Vec3(-0.008, 0.015, 0.0), 0.005, shifts) == 1);  // near x low: the image past x high
  CHECK(shifts[0] == Vec3(0.04, 0.0, 0.0));
  REQUIRE(box.image_shifts(Vec3(0.027, 0.029, 0.0), 0.005, shifts) == 3);  // near the corner (x high, y high)
  CHECK(shifts[0] == Vec3(-0.04, 0.0, 0.0));
  CHECK(shifts[1] == Vec3(0.0, -0.03, 0.0));
  CHECK(shifts[2] == Vec3(-0.04, -0.03, 0.0));
  // z is not periodic: a point at z = 0 has no image.
  PeriodicBox x_only = box;
  x_only.periodic = {true, false, false};
  CHECK(x_only.image_shifts(Vec3(0.0, 0.0, 0.0), 0.005, shifts) == 0);
  CHECK(periodic_cutoff_fits(box, 0.0149));
  CHECK_FALSE(periodic_cutoff_fits(box, 0.015));  // the y period 0.03 is not longer than 2 x 0.015
}

TEST_CASE("build_halo: one ghost per image of each real within the cutoff of a seam, ordered by owner") {
  const PeriodicBox box = box_xy();
  const std::vector<Vec3> positions = {Vec3(0.01, 0.015, 0.0), Vec3(0.028, 0.001, 0.0), Vec3(-0.009, 0.015, 0.0)};
  const std::vector<EntityId> ids = {7, 3, 11};
  Halo halo;
  build_halo(positions, ids, box, 0.004, halo);
  CHECK(halo.valid);
  CHECK(halo.real_count == 3);
  REQUIRE(halo.size() == 4);  // grain 1: x high and y low and their corner; grain 2: x low
  CHECK(halo.owner == std::vector<std::uint32_t>{1, 1, 1, 2});
  CHECK(halo.owner_id == std::vector<EntityId>{3, 3, 3, 11});
  CHECK(halo.shift[0] == Vec3(-0.04, 0.0, 0.0));
  CHECK(halo.shift[1] == Vec3(0.0, 0.03, 0.0));
  CHECK(halo.shift[2] == Vec3(-0.04, 0.03, 0.0));
  CHECK(halo.shift[3] == Vec3(0.04, 0.0, 0.0));
  CHECK(halo.owner_of(2) == 2);  // a real is its own owner
  CHECK(halo.owner_of(5) == 1);  // ghost 2
  std::vector<Vec3> ghost_position;
  halo_copy_positions(halo, positions, ghost_position);
  const Ghosted<Vec3> all = ghosted(positions, ghost_position, halo);
  CHECK(all[0] == positions[0]);
  CHECK(all[6] == Vec3(-0.009 + 0.04, 0.015, 0.0));
  // Every ghost lies within the cutoff outside the box: the images a search from inside can meet.
  for (std::size_t g = 0; g < halo.size(); ++g) CHECK_FALSE(box.inside(ghost_position[g]));
}

TEST_CASE("tank.periodic: walls only on the other faces, and the scene's mistakes named") {
  const Model model = parse_scene(periodic_scene("periodic = [\"x\"]\n"), "periodic.toml");
  CHECK(model.tank.periodic == std::array<bool, 3>{true, false, false});
  CHECK(model.tank.any_periodic());
  const Model plain = parse_scene(periodic_scene(""), "plain.toml");
  CHECK_FALSE(plain.tank.any_periodic());

  // A sphere may reach across the seam (its centre inside the period), not past a wall.
  CHECK_NOTHROW(parse_scene(periodic_scene("periodic = [\"x\", \"y\"]\n", SceneBuilder().within("solids")
      .sphere({.position = {0.001, 0.029, 0.005}, .radius = 0.0025, .material = "grain"}).toml()),
                            "seam.toml"));
  CHECK(mentions(test::problems_of(periodic_scene("periodic = [\"y\"]\n", SceneBuilder().within("solids")
      .sphere({.position = {0.001, 0.029, 0.005}, .radius = 0.0025, .material = "grain"}).toml())),
                 "does not fit inside the tank"));

  SUBCASE("z cannot be periodic") {
    const auto problems = test::problems_of(periodic_scene("periodic = [\"z\"]\n"), "z.toml");
    CHECK(mentions(problems, "z.toml:"));
    CHECK(mentions(problems, "tank.periodic"));
  }
  SUBCASE("a periodic axis has no faces to open") {
    const auto problems =
        test::problems_of(periodic_scene("periodic = [\"x\"]\nopen_faces = [\"x_max\", \"z_max\"]\n"));
    CHECK(mentions(problems, "tank.periodic"));
    CHECK(mentions(problems, "x_max cannot also be listed in open_faces"));
  }
  SUBCASE("a tank shaken along a periodic axis is refused; along another axis it is fine") {
    const std::string shaken = SceneBuilder()
        .tank_motion({.amplitude = 0.001, .frequency = 2.0, .direction = {1.0, 0.0, 0.0}}).toml();
    const auto problems = test::problems_of(periodic_scene("periodic = [\"x\"]\n" + shaken));
    CHECK(mentions(problems, "the tank moves along x ([tank.motion]), which is periodic"));
    std::string along_y = shaken;
    along_y.replace(along_y.find("[1.0, 0.0, 0.0]"), 15, "[0.0, 1.0, 0.0]");
    CHECK_NOTHROW(parse_scene(periodic_scene("periodic = [\"x\"]\n" + along_y), "y.toml"));
  }
  SUBCASE("a period no longer than twice the list's reach is refused") {
    // 2 x (5 mm + 1.25 mm skin) = 12.5 mm > a 12 mm period.
    std::string text = periodic_scene("periodic = [\"x\"]\n");
    text.replace(text.find("size = [0.04"), 12, "size = [0.012");
    text.replace(text.find("position = [0.02"), 16, "position = [0.006");
    CHECK(mentions(test::problems_of(text), "a periodic period must exceed twice the contact list's reach"));
  }
  SUBCASE("periodic grains need contacts; periodic water and coupled grains need periods long enough") {
    std::string no_contact = periodic_scene("periodic = [\"x\"]\n");
    no_contact.erase(no_contact.find("[contact]"), no_contact.find("[solids]") - no_contact.find("[contact]"));
    CHECK(mentions(test::problems_of(no_contact), "periodic grains need [contact]"));
    // 2 x (2.4 + 0.3) x 5 mm = 27 mm > the 20 mm period along y.
    std::string fluid = test::fluid_scene_text();
    fluid.replace(fluid.find("open_faces"), 0, "periodic = [\"y\"]\n");
    const auto short_period = test::problems_of(fluid, "short.toml");
    CHECK(mentions(short_period, "short.toml:"));
    CHECK(mentions(short_period, "a periodic period must exceed twice the fluid neighbour lists' reach"));
    const std::string water = "[fluid]\nspacing = 0.005\n\n[[fluid.boxes]]\nlow = [0.0, 0.0, 0.0]\n"
                              "high = [0.04, 0.03, 0.01]\n";
    // Grains and water together (coupled across the seam through the grains' images): accepted while the period
    // exceeds twice the sampling radius r + r_e = 2.5 + 12 mm; a 4 mm grain in a 30 mm period (2 x 16 mm) is not.
    std::string both = periodic_scene("periodic = [\"x\"]\n", water);
    const Model coupled = parse_scene(both, "both.toml");
    CHECK(coupled.fluid.enabled);
    CHECK(coupled.solids.enabled);
    std::string wide = both;
    wide.replace(wide.find("size = [0.04"), 12, "size = [0.03");
    wide.replace(wide.find("position = [0.02"), 16, "position = [0.015");
    wide.replace(wide.find("radius = 0.0025"), 15, "radius = 0.004");
    wide.replace(wide.find("high = [0.04"), 12, "high = [0.03");
    CHECK(mentions(test::problems_of(wide), "exceed twice the grains' sampling radius of the water"));
    // Water alone, periodic along x and y (periods 8 and 6 l0 > 2 x 2.7 l0): accepted.
    std::string water_only = periodic_scene("periodic = [\"x\", \"y\"]\n", water);
    water_only.erase(water_only.find("[contact]"), water_only.find("[fluid]") - water_only.find("[contact]"));
    const Model model = parse_scene(water_only, "water.toml");
    CHECK(model.fluid.enabled);
    CHECK(model.tank.periodic == std::array<bool, 3>{true, true, false});
  }
}

TEST_CASE("periodic water: the period fits the lattice, a moving lid spans the period, no surge front across a seam") {
  // Water alone in a box periodic along x (size 0.04 x 0.03 x 0.02 m, l0 = 5 mm, tank_walls = false: with tank walls
  // every axis is checked against the lattice already).
  const auto water_scene = [](const std::string& tank_extra, const std::string& fluid_extra) {
    const std::string water = "[fluid]\nspacing = 0.005\ntank_walls = false\n\n[[fluid.boxes]]\n"
                              "low = [0.0, 0.0, 0.0]\nhigh = [0.04, 0.03, 0.01]\n";
    std::string text = periodic_scene(tank_extra, water + fluid_extra);
    text.erase(text.find("[contact]"), text.find("[fluid]") - text.find("[contact]"));
    return text;
  };
  CHECK_NOTHROW(parse_scene(water_scene("periodic = [\"x\"]\n", ""), "water.toml"));
  SUBCASE("a period that is no whole number of cells is refused (the water would meet its image off l0)") {
    std::string text = water_scene("periodic = [\"x\"]\n", "");
    text.replace(text.find("size = [0.04"), 12, "size = [0.042");
    const auto problems = test::problems_of(text, "period.toml");
    CHECK(mentions(problems, "period.toml:"));
    CHECK(mentions(problems, "fluid.spacing"));
    CHECK(mentions(problems, "with x periodic the tank size along x (0.042 m) must be an integer multiple of spacing"));
    // The same size along a walled axis without tank walls is the water's own business: accepted.
    std::string walled = water_scene("periodic = [\"y\"]\n", "");
    walled.replace(walled.find("size = [0.04, 0.03"), 18, "size = [0.042, 0.03");
    CHECK_NOTHROW(parse_scene(walled, "walled.toml"));
  }
  SUBCASE("a moving lid along a periodic x must span the whole period") {
    const std::string lid = "\n[[fluid.wall_boxes]]\nlow = [0.0, 0.0, 0.015]\nhigh = [0.04, 0.03, 0.02]\n"
                            "lid = \"no_slip\"\nvelocity = 0.01\n";
    CHECK_NOTHROW(parse_scene(water_scene("periodic = [\"x\"]\n", lid), "lid.toml"));
    std::string short_lid = water_scene("periodic = [\"x\"]\n", lid);
    short_lid.replace(short_lid.find("high = [0.04, 0.03, 0.02]"), 25, "high = [0.03, 0.03, 0.02]");
    const auto problems = test::problems_of(short_lid, "lid.toml");
    CHECK(mentions(problems, "lid.toml:"));
    CHECK(mentions(problems, "fluid.wall_boxes[0].low"));
    CHECK(mentions(problems, "with x periodic a moving lid must span the whole period along x"));
    // Periodic along y only: the lid wraps within its own box along x, as before.
    std::string y_only = short_lid;
    y_only.replace(y_only.find("periodic = [\"x\"]"), 16, "periodic = [\"y\"]");
    CHECK_NOTHROW(parse_scene(y_only, "y.toml"));
  }
  SUBCASE("a surge front along a periodic axis is refused; along a walled one it is fine") {
    const std::string probe = "\n[output]\n[[output.probes]]\nkind = \"surge_front\"\nname = \"front\"\n"
                              "direction = [DIRECTION]\n";
    std::string along_x = water_scene("periodic = [\"x\"]\n", probe);
    along_x.replace(along_x.find("DIRECTION"), 9, "1.0, 0.0, 0.0");
    const auto problems = test::problems_of(along_x, "front.toml");
    CHECK(mentions(problems, "front.toml:"));
    CHECK(mentions(problems, "direction"));
    CHECK(mentions(problems, "a surge front along a periodic axis (x) has no meaning"));
    std::string along_y = water_scene("periodic = [\"x\"]\n", probe);
    along_y.replace(along_y.find("DIRECTION"), 9, "0.0, 1.0, 0.0");
    CHECK_NOTHROW(parse_scene(along_y, "y.toml"));
  }
}

TEST_CASE("the pressure solve exchanges the ghosts' pressures exactly when the model is periodic") {
  // One source for "is periodic" (the model, as the searches' periodic_box): a periodic model's solve writes
  // FluidNeighbours (the ghost pressures fluid_correct reads), a closed one's only reads it.
  const std::string water = "[fluid]\nspacing = 0.005\ntank_walls = false\n\n[[fluid.boxes]]\n"
                            "low = [0.0, 0.0, 0.0]\nhigh = [0.04, 0.03, 0.01]\n";
  std::string periodic = periodic_scene("periodic = [\"x\"]\n", water);
  periodic.erase(periodic.find("[contact]"), periodic.find("[fluid]") - periodic.find("[contact]"));
  std::string closed = periodic;
  closed.erase(closed.find("periodic = [\"x\"]"), 16);
  const FluidPressureSolve periodic_solve(parse_scene(periodic, "periodic.toml"));
  const FluidPressureSolve closed_solve(parse_scene(closed, "closed.toml"));
  CHECK(periodic_solve.access().writes_component(component_id<FluidNeighbours>));
  CHECK_FALSE(closed_solve.access().writes_component(component_id<FluidNeighbours>));
  CHECK(closed_solve.access().reads_component(component_id<FluidNeighbours>));
}

TEST_CASE("a layered bed generated in a periodic box overlaps nowhere, across the seam included") {
  const Model model = parse_scene(periodic_scene("periodic = [\"x\", \"y\"]\n", SceneBuilder(SceneBuilder::kSpaced)
      .within("solids")
      .array_table("solids.layered_beds").set("layers", 2).set("layer_thickness", 0.005).set("loose_factor", 1.7)
      .set("seed", 3)
      .array_table("solids.layered_beds.classes").set("diameter", 0.004).set("count", 30).set("material", "grain")
      .set("arrangement", "regular")
      .array_table("solids.layered_beds.classes").set("diameter", 0.002).set("count", 200).set("material", "grain")
      .toml()),
                                  "bed.toml");
  const std::vector<SphereSpec> spheres = scene_spheres(model);
  REQUIRE(spheres.size() == 231);
  const Vec3 period = model.tank.size;
  double closest = 1e300;  // smallest gap over all pairs, by the nearest image
  for (std::size_t a = 1; a < spheres.size(); ++a)  // sphere 0 is the scene's explicit one, placed by hand
    for (std::size_t b = a + 1; b < spheres.size(); ++b) {
      Vec3 d = spheres[b].position - spheres[a].position;
      for (int axis = 0; axis < 2; ++axis) d[axis] -= period[axis] * std::round(d[axis] / period[axis]);
      closest = std::min(closest, d.norm() - spheres[a].radius - spheres[b].radius);
    }
  CHECK(closest >= 0.0);
}
