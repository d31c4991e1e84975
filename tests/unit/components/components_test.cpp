// Structure-of-arrays invariants and the cell reorder.
#include <doctest/doctest.h>

#include <algorithm>
#include <map>
#include <numeric>
#include <tuple>

#include "engine/setup/initial_state.hpp"
#include "systems/physics/geometry/cell_order.hpp"
#include "systems/dem/solid_cell_sort.hpp"
#include "tests/support/test_support.hpp"

using namespace riffle;

TEST_CASE("adding grains keeps every field the same length and ids unique") {
  Solids solids;
  for (int k = 0; k < 10; ++k) solids.add(Vec3(k, 0, 0), Vec3::Zero(), 0.001 * (k + 1), 1000.0, 0, k % 3);
  CHECK(entity_count(solids) == 10);
  CHECK_NOTHROW(check_field_sizes(solids, "solids"));
  for (std::size_t k = 0; k < 10; ++k) CHECK(solids.id[k] == k);
  // m = rho 4/3 pi r^3, I = 2/5 m r^2 for a solid sphere.
  CHECK(solids.mass[0] == doctest::Approx(1000.0 * 4.0 / 3.0 * 3.14159265358979 * 1e-9).epsilon(1e-12));
  CHECK(solids.moment_of_inertia[0] == doctest::Approx(0.4 * solids.mass[0] * 1e-6).epsilon(1e-12));
  solids.radius.pop_back();
  CHECK_THROWS_WITH(check_field_sizes(solids, "solids"), "solids.radius holds 9 values, expected 10");
}

TEST_CASE("permute_fields moves every field together with its id") {
  Solids solids;
  for (int k = 0; k < 6; ++k) solids.add(Vec3(k, 2 * k, 3 * k), Vec3(-k, 0, 0), 0.01 + k, 1000.0, k, k);
  const std::vector<std::size_t> order = {5, 3, 1, 0, 2, 4};
  REQUIRE(is_permutation_of_indices(order));
  CHECK_FALSE(is_permutation_of_indices({0, 0, 1}));
  CHECK_FALSE(is_permutation_of_indices({0, 3, 1}));
  permute_fields(solids, order);
  for (std::size_t slot = 0; slot < order.size(); ++slot) {
    const auto id = static_cast<double>(solids.id[slot]);
    CHECK(solids.id[slot] == order[slot]);
    CHECK(solids.position[slot] == Vec3(id, 2 * id, 3 * id));
    CHECK(solids.velocity[slot] == Vec3(-id, 0, 0));
    CHECK(solids.radius[slot] == 0.01 + id);
    CHECK(solids.material[slot] == static_cast<std::int32_t>(id));
  }
}

TEST_CASE("cell_order sorts grains by (z, y, x) cell and is a permutation") {
  const Model model = test::small_model();
  World world = initial_world(model);
  Solids& solids = *world.solids;
  // Shuffle deterministically so the order is not already sorted.
  std::vector<std::size_t> shuffle(solids.size());
  for (std::size_t k = 0; k < shuffle.size(); ++k) shuffle[k] = (k * 7919) % shuffle.size();
  REQUIRE(is_permutation_of_indices(shuffle));
  permute_fields(solids, shuffle);
  std::map<EntityId, Vec3> before;
  for (std::size_t k = 0; k < solids.size(); ++k) before[solids.id[k]] = solids.position[k];

  const double cell = 0.03;
  const std::vector<std::size_t> order = cell_order(solids, Vec3::Zero(), cell);
  REQUIRE(is_permutation_of_indices(order));
  permute_fields(solids, order);
  auto key = [&](std::size_t k) {
    const Eigen::Array3d c = (solids.position[k] / cell).array().floor();
    return std::make_tuple(c[2], c[1], c[0]);
  };
  for (std::size_t k = 1; k < solids.size(); ++k) CHECK(key(k - 1) <= key(k));
  for (std::size_t k = 0; k < solids.size(); ++k) CHECK(before.at(solids.id[k]) == solids.position[k]);
}

TEST_CASE("cell_order orders by (z, y, x) cell, then slot, whether it counts cells or falls back to sorting") {
  // Points on a jittered lattice with many per cell (ties), in scrambled slots.
  std::vector<Vec3> positions;
  for (int k = 0; k < 3000; ++k) {
    const int scrambled = (k * 7919) % 3000;
    positions.emplace_back(0.001 * (scrambled % 17) + 1.0e-5 * (k % 3), 0.0013 * ((scrambled / 17) % 13),
                           0.0011 * (scrambled / 221));
  }
  const double cell = 0.004;
  // The expected order, by brute force: (z, y, x) cell, ties by slot.
  const auto expected_order = [&](const std::vector<Vec3>& points) {
    std::vector<std::tuple<double, double, double, std::size_t>> keys;
    for (std::size_t k = 0; k < points.size(); ++k) {
      const Eigen::Array3d c = (points[k] / cell).array().floor().max(0.0);
      keys.emplace_back(c[2], c[1], c[0], k);
    }
    std::sort(keys.begin(), keys.end());
    std::vector<std::size_t> order;
    for (const auto& key : keys) order.push_back(std::get<3>(key));
    return order;
  };
  CHECK(cell_order(positions, positions.size(), Vec3::Zero(), cell) == expected_order(positions));
  // One stray point 10 km away: the box of cells would be huge, so the comparison sort takes over; same answer.
  std::vector<Vec3> with_stray = positions;
  with_stray.emplace_back(1.0e4, 0.0, 0.0);
  CHECK(cell_order(with_stray, with_stray.size(), Vec3::Zero(), cell) == expected_order(with_stray));
  // Points already in order keep their slots; only the first `count` take part.
  std::vector<Vec3> in_order;
  for (const std::size_t k : expected_order(positions)) in_order.push_back(positions[k]);
  std::vector<std::size_t> identity(in_order.size());
  std::iota(identity.begin(), identity.end(), std::size_t{0});
  CHECK(cell_order(in_order, in_order.size(), Vec3::Zero(), cell) == identity);
  CHECK(cell_order(positions, 100, Vec3::Zero(), cell).size() == 100);
}

TEST_CASE("tank_walls builds one inward-facing plane per closed face") {
  TankModel tank;
  tank.size = Vec3(0.24, 0.16, 0.2);
  tank.origin = Vec3(1.0, 0.0, 0.0);
  tank.open_faces = {"z_max"};
  const Walls walls = tank_walls(tank);
  REQUIRE(walls.size() == 5);
  const Vec3 centre = tank.origin + 0.5 * tank.size;
  for (std::size_t wall = 0; wall < walls.size(); ++wall) {
    CHECK(walls.name[wall] != "z_max");
    // The inward normal points from the face towards the tank centre.
    CHECK(walls.normal[wall].dot(centre - walls.point[wall]) > 0.0);
    CHECK(walls.normal[wall].norm() == doctest::Approx(1.0));
    CHECK(walls.half_extent_u[wall].dot(walls.normal[wall]) == 0.0);
    CHECK(walls.half_extent_v[wall].dot(walls.normal[wall]) == 0.0);
  }
}

TEST_CASE("hold_until on a step boundary releases the grains at that step, whatever the summed time's rounding") {
  SolidsModel solids;
  solids.hold_until = 2.0;
  double time = 0.0;  // the stepper's time: a sum of steps, as a run reaches the seed 003 scenes' 2 s hold
  for (int step = 0; step < 4000; ++step) time += 5.0e-4;
  CHECK(time != 2.0);  // the rounding this guards against (1.99999999999984 on IEEE doubles)
  CHECK_FALSE(solids.held(time));
  CHECK(solids.held(time - 1.25e-5));  // the step's last sub-step before 2 s (40 sub-steps of 12.5 us) is held
  CHECK(solids.held(0.0));
  CHECK_FALSE(solids.held(2.0));
  solids.hold_until = -std::numeric_limits<double>::infinity();  // the default: never held
  CHECK_FALSE(solids.held(0.0));
  solids.fixed_to_tank = true;
  CHECK(solids.held(1.0e9));
}
