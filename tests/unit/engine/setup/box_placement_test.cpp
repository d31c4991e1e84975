// Boxes placed where the scene says ([[fluid.boxes]] / [[fluid.wall_boxes]] placement = "extent"): the grid rule of
// fluid_layout.hpp box_grid and its bounds, the exact grid-to-grid distance behind the overlap checks, and the
// scene's checks, wall-box merging and budget for off-lattice boxes.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "engine/setup/budget.hpp"
#include "engine/scene/scene.hpp"
#include "engine/setup/fluid_layout.hpp"
#include "engine/setup/initial_state.hpp"
#include "tests/support/test_support.hpp"
#include "tests/support/scene_builder.hpp"

using namespace riffle;
using riffle::test::SceneBuilder;

namespace {

/// The low and high faces of the particles' cells along `axis` (centres +- l0/2).
std::pair<double, double> cell_faces(const BoxGrid& grid, int axis) {
  const double first = grid.first[axis] - 0.5 * grid.spacing;
  return {first, first + static_cast<double>(grid.count[static_cast<std::size_t>(axis)]) * grid.spacing};
}

/// A 2-D-like dam break tank of 1.6 x 0.096 x 0.64 m at l0 = 32 mm (50 x 3 x 20 cells) with an obstacle whose low x
/// is 15 mm off the lattice.
std::string obstacle_scene(const std::string& obstacle, const std::string& water = "") {
  return SceneBuilder(SceneBuilder::kSpaced).run({.end_time = 0.1, .dt = 1.0e-3})
      .material("glass", {.density = 2500.0}).tank({.size = {1.6, 0.096, 0.64}, .wall_material = "glass"})
      .fluid({.spacing = 0.032}).fluid_box({0.0, 0.0, 0.0}, {0.64, 0.096, 0.32})
      .toml() + water + "\n[[fluid.wall_boxes]]\n" + obstacle;
}

using test::problems_of;

}  // namespace

TEST_CASE("extent placement: n = round(size / l0) particles at l0, anchored on lattice faces, else centred") {
  const Vec3 origin(0.1, -0.2, 0.0);
  const double l0 = 0.032;
  std::mt19937_64 random(22);
  std::uniform_real_distribution<double> corner(0.0, 1.0), size(0.001, 0.4);
  for (int trial = 0; trial < 2000; ++trial) {
    Vec3 low, high;
    for (int a = 0; a < 3; ++a) {
      low[a] = origin[a] + corner(random);
      high[a] = low[a] + size(random);
    }
    if (trial % 3 == 0) low[2] = origin[2];                   // standing on the floor
    if (trial % 5 == 0) high[0] = origin[0] + l0 * std::ceil((high[0] - origin[0]) / l0);  // high face on the lattice
    const BoxGrid grid = box_grid(origin, low, high, l0, true);
    for (int a = 0; a < 3; ++a) {
      const auto k = static_cast<std::size_t>(a);
      CHECK(grid.count[k] == std::max<std::int64_t>(1, std::llround((high[a] - low[a]) / l0)));
      const auto [from, to] = cell_faces(grid, a);
      // Each face within l0/2 of the given one (the documented bound); a box thinner than l0/2 is one layer of l0.
      const double bound = high[a] - low[a] >= 0.5 * l0 ? 0.5 * l0 : l0 - (high[a] - low[a]);
      CHECK(std::abs(from - low[a]) <= bound + 1e-12);
      CHECK(std::abs(to - high[a]) <= bound + 1e-12);
      const double low_cells = (low[a] - origin[a]) / l0, high_cells = (high[a] - origin[a]) / l0;
      if (std::abs(low_cells - std::round(low_cells)) < 1e-9) {
        CHECK(from == doctest::Approx(low[a]).epsilon(1e-12));  // anchored at the low face
      } else if (std::abs(high_cells - std::round(high_cells)) < 1e-9) {
        CHECK(to == doctest::Approx(high[a]).epsilon(1e-12));
      } else if (high[a] - low[a] >= 0.5 * l0) {  // centred: each face within l0/4 (one particle at least)
        CHECK(std::abs(from - low[a]) <= 0.25 * l0 + 1e-12);
        CHECK(std::abs(to - high[a]) <= 0.25 * l0 + 1e-12);
        CHECK(from - low[a] == doctest::Approx(high[a] - to).epsilon(1e-9).scale(l0));
      }
    }
  }
  // A box on the tank lattice gets the snapped box's particles whichever the placement.
  const Vec3 low = origin + l0 * Vec3(3, 1, 0), high = origin + l0 * Vec3(9, 4, 5);
  const FluidLayout snapped = fluid_box_layout(origin, low, high, l0);
  const FluidLayout fitted = grid_layout(box_grid(origin, low, high, l0, true), origin, FluidKind::kFluid);
  REQUIRE(snapped.particles.size() == fitted.particles.size());
  for (std::size_t i = 0; i < snapped.particles.size(); ++i) {
    CHECK((snapped.particles[i].position - fitted.particles[i].position).norm() < 1e-14);
    CHECK(snapped.particles[i].cell == fitted.particles[i].cell);
  }
}

TEST_CASE("grid_distance is the exact smallest particle distance (against all pairs)") {
  const Vec3 origin = Vec3::Zero();
  const double l0 = 0.01;
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> corner(0.0, 0.08), size(0.001, 0.05);
  for (int trial = 0; trial < 300; ++trial) {
    BoxGrid grids[2];
    for (BoxGrid& grid : grids) {
      Vec3 low, high;
      for (int a = 0; a < 3; ++a) {
        low[a] = corner(random);
        high[a] = low[a] + size(random);
      }
      grid = box_grid(origin, low, high, l0, trial % 2 == 0);
    }
    if (grids[0].empty() || grids[1].empty()) continue;
    const FluidLayout a = grid_layout(grids[0], origin, FluidKind::kWall);
    const FluidLayout b = grid_layout(grids[1], origin, FluidKind::kWall);
    double brute = 1e300;
    for (const LatticeParticle& p : a.particles)
      for (const LatticeParticle& q : b.particles) brute = std::min(brute, (p.position - q.position).norm());
    CHECK(grid_distance(grids[0], grids[1]) == doctest::Approx(brute).epsilon(1e-9).scale(l0));
  }
}

TEST_CASE("an obstacle 15 mm off the lattice at l0 = 32 mm fills its extent within l0/2") {
  // The obstacle [0.655, 0.815] x [0, 0.096] x [0, 0.16]: snapped it would start at the lattice's 0.656 - 0.016;
  // fitted: 5 x 3 x 5 particles, x centred (0.16 = 5 l0: the faces exactly where given), z anchored on the floor.
  const Model model = parse_scene(
      obstacle_scene("low = [0.655, 0.0, 0.0]\nhigh = [0.815, 0.096, 0.16]\nplacement = \"extent\"\n"), "ok.toml");
  const World world = initial_world(model);
  const FluidParticles& particles = *world.fluid;
  const double l0 = 0.032;
  Vec3 low = Vec3::Constant(1e300), high = Vec3::Constant(-1e300);
  std::size_t box_particles = 0;
  const std::size_t tank_shell = tank_wall_layout(model.tank.origin, model.tank.size, model.tank.open_faces, l0,
                                                  model.fluid.effective_radius())
                                     .particles.size();
  const std::size_t fluid = fluid_box_layout(Vec3::Zero(), Vec3::Zero(), Vec3(0.64, 0.096, 0.32), l0).particles.size();
  for (std::size_t i = fluid + tank_shell; i < particles.size(); ++i) {
    ++box_particles;
    low = low.cwiseMin(particles.position[i]);
    high = high.cwiseMax(particles.position[i]);
  }
  CHECK(box_particles == 5 * 3 * 5);
  CHECK(low[0] - 0.5 * l0 == doctest::Approx(0.655).epsilon(1e-12));
  CHECK(high[0] + 0.5 * l0 == doctest::Approx(0.815).epsilon(1e-12));
  CHECK(low[2] == doctest::Approx(0.5 * l0).epsilon(1e-12));  // on the floor: l0 from the floor's wall layer
  // Budget counts what is placed.
  const SceneBudget budget = estimate_budget(model);
  CHECK(budget.fluid_particles == static_cast<double>(fluid));
  CHECK(budget.wall_particles + budget.dummy_particles == static_cast<double>(tank_shell + box_particles));
  // An odd size: 0.1 m = 3.125 l0 -> 3 particles, centred: faces 2 mm inside each given face (<= l0/4).
  const Model odd = parse_scene(
      obstacle_scene("low = [0.705, 0.0, 0.0]\nhigh = [0.805, 0.096, 0.1]\nplacement = \"extent\"\n"), "odd.toml");
  const World odd_world = initial_world(odd);
  double first = 1e300, last = -1e300;
  for (std::size_t i = fluid + tank_shell; i < odd_world.fluid->size(); ++i) {
    first = std::min(first, odd_world.fluid->position[i][0]);
    last = std::max(last, odd_world.fluid->position[i][0]);
  }
  CHECK(first - 0.5 * l0 == doctest::Approx(0.705 + 0.002).epsilon(1e-12));
  CHECK(last + 0.5 * l0 == doctest::Approx(0.805 - 0.002).epsilon(1e-12));
}

TEST_CASE("off-lattice boxes: closer than l0/2 to the water is an error, overlapping wall boxes merge") {
  // The obstacle [0.62, 0.78] (5 particles, centred) starts at x = 0.636, 12 mm from the water's last column at 0.624.
  const std::vector<std::string> problems = problems_of(
      obstacle_scene("low = [0.62, 0.0, 0.0]\nhigh = [0.78, 0.096, 0.16]\nplacement = \"extent\"\n"));
  REQUIRE(problems.size() == 1);
  CHECK(problems[0].find("bad.toml:21:7: fluid.wall_boxes[0].low: the wall box overlaps fluid.boxes[0] (their "
                         "particles come within ") == 0);
  CHECK(problems[0].find("closer than spacing / 2") != std::string::npos);
  // Touching faces (the water ends at 0.64, the obstacle starts there, off-lattice elsewhere) are fine.
  CHECK_NOTHROW(parse_scene(
      obstacle_scene("low = [0.64, 0.0, 0.0]\nhigh = [0.79, 0.096, 0.17]\nplacement = \"extent\"\n"), "ok.toml"));
  // A fluid box fitted to its extent against a snapped one.
  const std::vector<std::string> water = problems_of(obstacle_scene(
      "low = [1.2, 0.0, 0.0]\nhigh = [1.3, 0.096, 0.1]\n",
      "\n[[fluid.boxes]]\nlow = [0.6, 0.0, 0.0]\nhigh = [0.8, 0.096, 0.1]\nplacement = \"extent\"\n"));
  REQUIRE(water.size() == 1);
  CHECK(water[0].find("fluid.boxes[1].low: the box overlaps fluid.boxes[0] (their particles come within") !=
        std::string::npos);
  const std::vector<std::string> bad_choice =
      problems_of(obstacle_scene("low = [1.2, 0.0, 0.0]\nhigh = [1.3, 0.096, 0.1]\nplacement = \"exact\"\n"));
  REQUIRE(bad_choice.size() == 1);
  CHECK(bad_choice[0].find("fluid.wall_boxes[0].placement: expected one of \"lattice\", \"extent\", got \"exact\"") !=
        std::string::npos);

  // Two overlapping wall boxes, one off the lattice: no two wall particles closer than l0/2.
  const Model model = parse_scene(
      obstacle_scene("low = [0.9, 0.0, 0.0]\nhigh = [1.1, 0.096, 0.2]\nplacement = \"extent\"\n\n"
                     "[[fluid.wall_boxes]]\nlow = [1.0, 0.0, 0.0]\nhigh = [1.2, 0.096, 0.25]\n"),
      "merge.toml");
  const World world = initial_world(model);
  const FluidParticles& particles = *world.fluid;
  std::size_t walls = 0, close_pairs = 0;
  const double l0 = 0.032;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.kind[i] == static_cast<std::int32_t>(FluidKind::kFluid)) continue;
    ++walls;
    for (std::size_t j = i + 1; j < particles.size(); ++j)
      if (particles.kind[j] != static_cast<std::int32_t>(FluidKind::kFluid) &&
          (particles.position[i] - particles.position[j]).norm() < 0.5 * l0)
        ++close_pairs;
  }
  CHECK(close_pairs == 0);
  const std::size_t shell = tank_wall_layout(model.tank.origin, model.tank.size, model.tank.open_faces, l0,
                                             model.fluid.effective_radius())
                                .particles.size();
  const std::size_t first_box = 6 * 3 * 6;  // round(0.2 / 0.032) = 6 (x), 3, 6
  // The snapped box has 7 x 3 x 8 points; 3 x 3 x 6 of them lie within 8 mm of the first box's and are dropped.
  CHECK(walls == shell + first_box + 7 * 3 * 8 - 3 * 3 * 6);
}
