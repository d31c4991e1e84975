// Budgets before allocation: scenes too big for the memory limit are refused with a file:line:column:
// key: message before any particle is generated; the limit can be raised by run.memory_limit and --memory-limit;
// the grain grid stays small whatever the empty space or the smallest grain; scene files must be regular files.
// A generated bed is counted and sized from its classes, as the run then generates it.
// Each case here ended in std::bad_alloc, a hang or a read until memory ran out before (main 25b9940).
#include <doctest/doctest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "engine/setup/bed_generation.hpp"
#include "engine/setup/budget.hpp"
#include "engine/setup/initial_state.hpp"
#include "engine/scene/scene.hpp"
#include "engine/run/simulation.hpp"
#include "systems/physics/geometry/domain.hpp"
#include "systems/dem/solid_neighbours.hpp"
#include "systems/physics/coupling/voidage_grid.hpp"
#include "systems/physics/dem/neighbour_range.hpp"
#include "systems/physics/time/solid_step.hpp"

namespace {

/// A dry DEM scene: `extra_run` is added to [run], `tank_extra` to [tank], `solids` is the [solids] body.
std::string dem_scene(const std::string& solids, const std::string& tank_extra = "",
                      const std::string& extra_run = "") {
  return "[run]\nend_time = 0.01\ndt = 1.0e-3\n" + extra_run +
         "\n[materials.sand]\ndensity = 2650.0\nyoung_modulus = 1.0e7\npoisson_ratio = 0.3\n"
         "\n[tank]\nsize = [0.3, 0.2, 0.2]\nwall_material = \"sand\"\n" +
         tank_extra +
         "\n[contact]\nrestitution = 0.5\nfriction = 0.3\n"
         "\n[solids]\n" +
         solids;
}

/// A water-only scene whose fluid box holds `side`^3 particles at spacing 1 mm, walls off.
std::string fluid_scene(int side, const std::string& extra_run = "") {
  const double edge = side * 1e-3;
  char text[1024];
  std::snprintf(text, sizeof text,
                "[run]\nend_time = 0.01\ndt = 1.0e-4\n%s\n[materials.water]\ndensity = 1000.0\n\n[tank]\n"
                "size = [%g, %g, %g]\nwall_material = \"water\"\n\n[fluid]\nspacing = 1.0e-3\ntank_walls = false\n\n"
                "[[fluid.boxes]]\nlow = [0.0, 0.0, 0.0]\nhigh = [%g, %g, %g]\n",
                extra_run.c_str(), edge, edge, edge, edge, edge, edge);
  return text;
}

std::string budget_problems(const std::string& text, const riffle::SceneLimits& limits = {}) {
  try {
    riffle::parse_scene(text, "budget.toml", limits);
  } catch (const riffle::SceneError& error) {
    return error.what();
  }
  return "";
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST_CASE("scene budget: grains over the scene's total are refused before they are generated") {
  // Two blocks of 3.1e7 grains each: under the per-block cap of 5e7, 6.2e7 in all (was generated: 5.5 GB of
  // SphereSpecs, then std::bad_alloc or minutes of work). The memory limit is out of the way: this is the count.
  const std::string block =
      "[[solids.blocks]]\nmin = [0.0005, 0.0005, 0.0005]\nmax = [0.2995, 0.1995, 0.0995]\nspacing = 0.00057\n"
      "radius = 0.00025\nmaterial = \"sand\"\n";
  const std::string second =
      "[[solids.blocks]]\nmin = [0.0005, 0.0005, 0.1005]\nmax = [0.2995, 0.1995, 0.1995]\nspacing = 0.00057\n"
      "radius = 0.00025\nmaterial = \"sand\"\n";
  const std::string problems = budget_problems(dem_scene(block + second, "", "memory_limit = 1.0e6\n"));
  INFO(problems);
  CHECK(contains(problems, "budget.toml:"));
  CHECK(contains(problems, "grains in all, more than the 5e7 a scene may have"));
}

TEST_CASE("scene budget: a fill whose classes exceed the memory limit is refused before random placement") {
  const std::string fill =
      "[[solids.fills]]\nmin = [0.0, 0.0, 0.0]\nmax = [0.3, 0.2, 0.2]\n"
      "[[solids.fills.classes]]\ndiameter = 0.0005\ncount = 4000000\nmaterial = \"sand\"\n";
  const std::string problems = budget_problems(dem_scene(fill, "", "memory_limit = 0.25\n"));
  INFO(problems);
  CHECK(contains(problems, "solids.fills[0].classes"));
  CHECK(contains(problems, "4e+06 grains would need at least an estimated"));
  CHECK(contains(problems, "(run.memory_limit)"));
}

TEST_CASE("scene budget: MPS particles over the memory limit are refused, naming fluid.spacing and the estimate") {
  // 200^3 = 8e6 fluid particles: several GiB with their neighbour lists.
  const std::string problems = budget_problems(fluid_scene(200, "memory_limit = 1.0\n"));
  INFO(problems);
  CHECK(contains(problems, "fluid.spacing: the scene needs an estimated"));
  CHECK(contains(problems, "8e+06 particles"));
  CHECK(contains(problems, "the memory limit is 1 GiB (run.memory_limit)"));
}

TEST_CASE("scene budget: the limit is raised by run.memory_limit and by --memory-limit (SceneLimits)") {
  const riffle::SceneBudget budget = riffle::estimate_budget(riffle::parse_scene(fluid_scene(40), "small.toml"));
  CHECK(budget.fluid_particles == 64000.0);
  const double need_gib = budget.bytes / (1024.0 * 1024.0 * 1024.0);
  const std::string below = "memory_limit = " + std::to_string(0.5 * need_gib) + "\n";
  const std::string above = "memory_limit = " + std::to_string(2.0 * need_gib) + "\n";
  CHECK(contains(budget_problems(fluid_scene(40, below)), "the memory limit is"));
  CHECK(budget_problems(fluid_scene(40, above)).empty());
  riffle::SceneLimits small, large;
  small.memory_limit = 0.5 * budget.bytes;
  large.memory_limit = 2.0 * budget.bytes;
  CHECK(contains(budget_problems(fluid_scene(40), small), "(--memory-limit)"));
  // The command line beats the scene key either way.
  CHECK(budget_problems(fluid_scene(40, below), large).empty());
  CHECK(contains(budget_problems(fluid_scene(40, above), small), "(--memory-limit)"));
}

TEST_CASE("scene budget: a contact skin far beyond the grains is refused") {
  const std::string spheres =
      "[[solids.spheres]]\nposition = [0.1, 0.1, 0.1]\nradius = 0.001\nmaterial = \"sand\"\n"
      "[[solids.spheres]]\nposition = [0.2, 0.1, 0.1]\nradius = 0.001\nmaterial = \"sand\"\n";
  std::string scene = dem_scene(spheres);
  scene.insert(scene.find("[solids]"), "skin = 1.0\n\n");
  const std::string problems = budget_problems(scene);
  INFO(problems);
  CHECK(contains(problems, "contact.skin: a skin of 1 m is more than twice the largest grain diameter"));
}

TEST_CASE("solid grid: its cell count stays bounded by the grains, not the empty space or the smallest grain") {
  riffle::DomainBox domain{riffle::Vec3(-10.0, -10.0, -10.0), riffle::Vec3(10.3, 10.2, 10.2)};
  SUBCASE("a huge domain around a few grains (domain_margin = 10 m, or an amplitude of 1e3 m)") {
    const std::vector<riffle::Vec3> grains = {{0.1, 0.1, 0.1}, {0.2, 0.1, 0.1}, {0.1, 0.15, 0.05}};
    const riffle::SolidGridShape shape = riffle::solid_grid_shape(grains, domain, 0.0025);
    CHECK(shape.cell_count() <= riffle::solid_grid_cell_limit(grains.size()));
    CHECK(shape.cell_size == 0.0025);  // the grains' box alone fits: the cells keep their size
  }
  SUBCASE("one 1 um grain among grains spread over the tank") {
    const std::vector<riffle::Vec3> grains = {{0.0, 0.0, 0.0}, {0.3, 0.2, 0.2}, {0.15, 0.1, 0.1}};
    const riffle::SolidGridShape shape = riffle::solid_grid_shape(grains, domain, 2.5e-6);
    CHECK(shape.cell_count() <= riffle::solid_grid_cell_limit(grains.size()));
    CHECK(shape.cell_count() > 1000.0);  // enlarged only as far as needed
  }
  SUBCASE("an amplitude of 4e9 m") {
    const riffle::DomainBox huge{riffle::Vec3::Constant(-4e9), riffle::Vec3::Constant(4e9)};
    const std::vector<riffle::Vec3> grains = {{-4e9, 0.0, 0.0}, {4e9, 0.0, 0.0}};
    const riffle::SolidGridShape shape = riffle::solid_grid_shape(grains, huge, 1e-5);
    CHECK(shape.cell_count() <= riffle::solid_grid_cell_limit(grains.size()));
  }
}

TEST_CASE("voidage grid: two particles far apart in a wide domain give a bounded grid") {
  // 4096^3 nodes (two 550 GB arrays) before: the per-axis cap of 4096 bounded nothing in total.
  riffle::VoidageGrid grid;
  const std::vector<riffle::Vec3> grains = {{0.0, 0.0, 0.0}, {1.0e3, 1.0e3, 1.0e3}};
  const std::vector<double> volumes = {1e-9, 1e-9};
  grid.build(grains, volumes, {}, 0, 1e-9, 0.01, riffle::Vec3::Constant(-1e4), riffle::Vec3::Constant(1e4));
  CHECK(static_cast<double>(grid.node_count()) <= riffle::voidage_node_limit(2));
  CHECK(grid.node_count() > 8);  // coarsened only as far as needed
}

TEST_CASE("solid grid: tiny grains, huge margins and amplitudes build a world and find the same contacts") {
  // Each of these asked the grain grid for 1e11 to 1e15 cells (std::bad_alloc in the first neighbour build).
  const std::string touching =
      "[[solids.spheres]]\nposition = [0.1, 0.1, 0.1]\nradius = 0.001\nmaterial = \"sand\"\n"
      "[[solids.spheres]]\nposition = [0.1019, 0.1, 0.1]\nradius = 0.001\nmaterial = \"sand\"\n";
  const std::string tiny = "[[solids.spheres]]\nposition = [0.25, 0.1, 0.1]\nradius = 1.0e-6\nmaterial = \"sand\"\n";
  std::string scene;
  SUBCASE("a 1 um grain") { scene = dem_scene(touching + tiny); }
  SUBCASE("domain_margin = 10 m") { scene = dem_scene(touching, "domain_margin = 10.0\n"); }
  SUBCASE("an amplitude of 1e3 m") {
    scene = dem_scene(touching, "[tank.motion]\nkind = \"sinusoidal\"\namplitude = 1.0e3\nfrequency = 1.0\n");
  }
  auto simulation = riffle::Simulation::from_model(riffle::parse_scene(scene, "grid.toml"));
  const riffle::Contacts& contacts = *simulation->world().contacts;
  REQUIRE(contacts.valid);
  // The two grains 1.9 mm apart (radii 1 mm) overlap: exactly one grain-grain pair lists them.
  CHECK(contacts.pair_second.size() == 1);
}

TEST_CASE("scene file input: only regular files, at most 16 MiB") {
  const std::filesystem::path directory =
      std::filesystem::temp_directory_path() / ("riffle_scene_budget_" + std::to_string(::getpid()));
  std::filesystem::create_directories(directory);
  struct RemoveOnExit {
    std::filesystem::path path;
    ~RemoveOnExit() { std::filesystem::remove_all(path); }
  } remove_on_exit{directory};
  auto refusal = [](const std::string& path) -> std::string {
    try {
      riffle::load_scene_file(path);
    } catch (const riffle::SceneError& error) {
      return error.what();
    }
    return "accepted";
  };
  SUBCASE("/dev/zero (read until memory ran out)") {
    CHECK(contains(refusal("/dev/zero"), "/dev/zero: is not a regular file"));
  }
  SUBCASE("a FIFO (blocked forever in open)") {
    const std::string fifo = (directory / "scene.fifo").string();
    REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    CHECK(contains(refusal(fifo), "is not a regular file"));
  }
  SUBCASE("a directory") { CHECK(contains(refusal(directory.string()), "is a directory")); }
  SUBCASE("a file over 16 MiB") {
    const std::string big = (directory / "big.toml").string();
    {
      std::ofstream out(big, std::ios::binary);
      const std::string line(1023, '#');
      for (int k = 0; k < 16 * 1024 + 1; ++k) out << line << '\n';
    }
    CHECK(contains(refusal(big), "more than the 16777216 (16 MiB) a scene may have"));
  }
}

TEST_CASE("scene budget: the seed bed is counted and sized from its classes, as the run generates it") {
  // scenes/dry_bed_settle.toml: the seed's three-layer bed, 135 + 537 + 7490 grains of 15, 10 and 5 mm.
  const riffle::Model model = riffle::load_scene_file(RIFFLE_SOURCE_DIR "/scenes/dry_bed_settle.toml");
  REQUIRE(model.solids.layered_beds.size() == 1);
  CHECK(model.solids.spheres.empty());  // the model keeps the bed's table, not its spheres
  const riffle::SceneBudget budget = riffle::estimate_budget(model);
  const riffle::World world = riffle::initial_world(model);  // generated here, once
  const double generated = static_cast<double>(world.solids->size());
  CHECK(generated == 8162.0);
  // Within a few per cent is what the budget needs; a bed that generates at all has exactly its classes' counts.
  CHECK(budget.grains == doctest::Approx(generated).epsilon(0.03));
  CHECK(budget.grains == generated);

  // The same scene with the generated spheres listed one by one: the same budget, the same DEM sub-step (set by the
  // smallest grains), the same sizes; and the neighbour skin the run takes from its grains is the classes' one.
  riffle::Model listed = model;
  listed.solids.layered_beds.clear();
  listed.solids.spheres = riffle::scene_spheres(model);
  const riffle::SceneBudget listed_budget = riffle::estimate_budget(listed);
  CHECK(listed_budget.grains == budget.grains);
  CHECK(listed_budget.grain_pairs == doctest::Approx(budget.grain_pairs).epsilon(1e-12));
  CHECK(listed_budget.bytes == doctest::Approx(budget.bytes).epsilon(1e-12));
  std::vector<riffle::DesignImpact> from_classes, from_spheres;
  const riffle::StableStep step = riffle::stable_solid_step(model, from_classes);
  CHECK(step.solid_dt == riffle::stable_solid_step(listed, from_spheres).solid_dt);
  CHECK(step.solid_dt == model.contact.stable_solid_dt);
  CHECK(step.reason == model.contact.stable_solid_dt_reason);
  CHECK(from_classes.size() == from_spheres.size());
  const riffle::GrainSizes sizes = riffle::scene_grain_sizes(model.solids);
  const auto [smallest, largest] = std::minmax_element(world.solids->radius.begin(), world.solids->radius.end());
  CHECK(sizes.smallest_radius == *smallest);
  CHECK(sizes.largest_radius == *largest);
  CHECK(riffle::default_skin(*world.solids) == 0.5 * sizes.smallest_radius);
}
