// MPS neighbour lists (systems/mps/fluid_neighbours.hpp) against a brute-force O(N^2) search, and independent of the
// thread count.
#include <doctest/doctest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "components/halo.hpp"
#include "engine/setup/fluid_layout.hpp"
#include "systems/mps/fluid_neighbours.hpp"
#include "systems/physics/mps/mps_kernel.hpp"
#include "systems/physics/geometry/periodic_box.hpp"
#include "systems/system.hpp"
#include "tests/support/test_support.hpp"

using namespace riffle;

namespace {

constexpr double kNeighbourSpacing = 0.005;  // [m] l0

/// A jittered 9 x 8 x 7 lattice block plus a far stray particle, a particle on top of another and a NaN.
std::vector<Vec3> jittered_block() {
  std::vector<Vec3> positions;
  std::mt19937 random(7);
  std::uniform_real_distribution<double> offset(-0.4 * kNeighbourSpacing, 0.4 * kNeighbourSpacing);
  for (int k = 0; k < 7; ++k)
    for (int j = 0; j < 8; ++j)
      for (int i = 0; i < 9; ++i)
        positions.push_back(kNeighbourSpacing * Vec3(i, j, k) + Vec3(offset(random), offset(random), offset(random)));
  // Shuffle so slot order is not spatial order.
  std::shuffle(positions.begin(), positions.end(), random);
  positions.push_back(Vec3(1.0e4, -3.0e3, 2.0e4));  // stray: the grid must not explode, it has no neighbours
  positions.push_back(positions[5]);                 // coincident with slot 5: neighbours at distance 0
  positions.push_back(Vec3(std::nan(""), 0.0, 0.0)); // non-finite: no neighbours, nobody's neighbour
  return positions;
}

std::vector<std::vector<std::uint32_t>> brute_force(const std::vector<Vec3>& positions, double radius) {
  std::vector<std::vector<std::uint32_t>> lists(positions.size());
  for (std::size_t i = 0; i < positions.size(); ++i)
    for (std::size_t j = 0; j < positions.size(); ++j)
      if (j != i && (positions[j] - positions[i]).squaredNorm() < radius * radius)
        lists[i].push_back(static_cast<std::uint32_t>(j));  // ascending
  return lists;
}

}  // namespace

TEST_CASE("fluid neighbour lists equal a brute-force search, in ascending slot order") {
  const std::vector<Vec3> positions = jittered_block();
  for (const double ratio : {2.6, 3.1}) {
    CAPTURE(ratio);
    const double radius = ratio * kNeighbourSpacing;
    FluidNeighbours neighbours;
    build_fluid_neighbours(positions, radius, neighbours);
    const auto expected = brute_force(positions, radius);
    REQUIRE(neighbours.offsets.size() == positions.size() + 1);
    CHECK(neighbours.offsets.front() == 0);
    CHECK(neighbours.offsets.back() == neighbours.slots.size());
    CHECK(neighbours.radius == radius);
    std::size_t total = 0;
    for (std::size_t i = 0; i < positions.size(); ++i) {
      const std::vector<std::uint32_t> found(neighbours.slots.begin() + neighbours.offsets[i],
                                             neighbours.slots.begin() + neighbours.offsets[i + 1]);
      CHECK(found == expected[i]);
      total += expected[i].size();
    }
    CHECK(neighbours.slots.size() == total);
    CHECK(total > 20 * 504);  // the block is dense enough to mean something
    const std::size_t stray = positions.size() - 3, nan_slot = positions.size() - 1;
    CHECK(neighbours.offsets[stray + 1] == neighbours.offsets[stray]);
    CHECK(neighbours.offsets[nan_slot + 1] == neighbours.offsets[nan_slot]);
  }
}

TEST_CASE("fluid neighbour lists do not depend on the grid's cells: a narrow search on the wide skin's cells") {
  // The adaptive skin (FluidNeighbourSearch) searches r_e + 0.1 l0 on the cells of r_e + 0.3 l0.
  const std::vector<Vec3> positions = jittered_block();
  const double radius = 2.5 * kNeighbourSpacing;
  const auto expected = brute_force(positions, radius);
  for (const double cell_ratio : {0.0, 2.7, 6.0}) {
    CAPTURE(cell_ratio);
    FluidNeighbours neighbours;
    build_fluid_neighbours(positions, radius, neighbours, static_cast<std::size_t>(-1), Vec3(0.001, -0.002, 0.0),
                           cell_ratio * kNeighbourSpacing);
    CHECK(neighbours.radius == radius);
    for (std::size_t i = 0; i < positions.size(); ++i)
      CHECK(std::vector<std::uint32_t>(neighbours.slots.begin() + neighbours.offsets[i],
                                       neighbours.slots.begin() + neighbours.offsets[i + 1]) == expected[i]);
  }
}

TEST_CASE("fluid neighbour lists do not depend on the thread count and rebuild in place") {
  const std::vector<Vec3> positions = jittered_block();
  FluidNeighbours serial, parallel;
  tbb::task_arena one(1);
  one.execute([&] { build_fluid_neighbours(positions, 2.6 * kNeighbourSpacing, serial); });
  build_fluid_neighbours(positions, 2.6 * kNeighbourSpacing, parallel);
  CHECK(serial.offsets == parallel.offsets);
  CHECK(serial.slots == parallel.slots);
  // A second build over different data replaces the lists.
  const std::vector<Vec3> few = {Vec3::Zero(), Vec3(kNeighbourSpacing, 0, 0), Vec3(10 * kNeighbourSpacing, 0, 0)};
  build_fluid_neighbours(few, 2.6 * kNeighbourSpacing, parallel);
  CHECK(parallel.builds == 2);
  CHECK(parallel.offsets == std::vector<std::uint32_t>{0, 1, 2, 2});
  CHECK(parallel.slots == std::vector<std::uint32_t>{1, 0});
  build_fluid_neighbours({}, 2.6 * kNeighbourSpacing, parallel);
  CHECK(parallel.offsets == std::vector<std::uint32_t>{0});
  CHECK(parallel.slots.empty());
  CHECK_THROWS_AS(build_fluid_neighbours(few, 0.0, parallel), std::invalid_argument);
}

TEST_CASE("the search's 4- and 8-wide candidate tests keep exactly the pairs of the portable one") {
  // Where the CPU has AVX2 or AVX-512 the search tests 4 or 8 candidates at a time (masked tails, compressed
  // stores); a CPU without them takes the portable test throughout and the comparison is trivially equal.
  // Candidates within a rounding error of the radius (on a sphere of radius (1 +- 1e-15) R around some queries, and
  // at R) check that all sum the squared distance in the same order.
  std::vector<Vec3> positions = jittered_block();
  const double radius = 2.6 * kNeighbourSpacing;
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), scale(-1.0e-15, 1.0e-15);
  for (std::size_t centre = 0; centre < 40; ++centre)
    for (int k = 0; k < 12; ++k) {
      Vec3 direction(unit(random), unit(random), unit(random));
      direction.normalize();
      const double distance = k == 0 ? radius : radius * (1.0 + scale(random));
      positions.push_back(positions[centre] + distance * direction);
    }
  const std::size_t query_count = positions.size() - 100;  // the last 100 are found but not queried
  const auto expected = brute_force(positions, radius);
  FluidNeighbours portable;
  set_fluid_search_simd_cap(FluidSearchSimd::kPortable);
  CHECK(fluid_search_simd() == FluidSearchSimd::kPortable);
  build_fluid_neighbours(positions, radius, portable, query_count);
  REQUIRE(portable.offsets.size() == query_count + 1);
  for (std::size_t i = 0; i < query_count; ++i) {
    CAPTURE(i);
    // Queries first, then the others, each ascending (build_fluid_neighbours' order).
    std::vector<std::uint32_t> want;
    for (const std::uint32_t j : expected[i]) if (j < query_count) want.push_back(j);
    for (const std::uint32_t j : expected[i]) if (j >= query_count) want.push_back(j);
    CHECK(std::vector<std::uint32_t>(portable.slots.begin() + portable.offsets[i],
                                     portable.slots.begin() + portable.offsets[i + 1]) == want);
  }
  for (const FluidSearchSimd cap : {FluidSearchSimd::kAvx2, FluidSearchSimd::kAvx512}) {
    set_fluid_search_simd_cap(cap);
    MESSAGE("cap " << static_cast<int>(cap) << ": this CPU takes " << static_cast<int>(fluid_search_simd())
                   << " (0 portable, 1 AVX2, 2 AVX-512)");
    FluidNeighbours wide;
    build_fluid_neighbours(positions, radius, wide, query_count);
    CHECK(wide.offsets == portable.offsets);
    CHECK(wide.slots == portable.slots);
  }
}

TEST_CASE("a box of water periodic along x: no walls on the x faces, and the halo joins the lattice across the seam") {
  // Theory: the lattice filling the period, with the shell of the other faces, is one period of a lattice infinite
  // along x, so every particle's number density depends on its (y, z) layer only (no dip at the seam), and equals
  // the sum over the infinite lattice (here three periods, searched by brute force).
  const std::array<std::int64_t, 3> cells{8, 5, 6};  // period 8 l0 > 2 r_e
  const double radius = 3.1 * kNeighbourSpacing;
  const Vec3 origin(0.02, -0.01, 0.0);
  const Vec3 size = kNeighbourSpacing * Vec3(8.0, 5.0, 6.0);
  const std::array<bool, 3> periodic{true, false, false};
  const FluidLayout water = fluid_box_layout(origin, origin, origin + size, kNeighbourSpacing);
  const FluidLayout shell = tank_wall_layout(origin, size, {}, kNeighbourSpacing, radius, periodic);
  const std::int64_t layers = 1 + dummy_layer_count(kNeighbourSpacing, radius);
  REQUIRE(water.fluid == 8 * 5 * 6);
  CHECK(shell.particles.size() ==
        static_cast<std::size_t>(cells[0] * (cells[1] + 2 * layers) * (cells[2] + 2 * layers) - 8 * 5 * 6));
  std::vector<Vec3> positions;
  for (const LatticeParticle& particle : water.particles) positions.push_back(particle.position);
  for (const LatticeParticle& particle : shell.particles) {
    CHECK(particle.cell[0] >= 0);  // no layer beyond a periodic face
    CHECK(particle.cell[0] < cells[0]);
    CHECK(particle.face >= 2);  // owned by a y or z face
    positions.push_back(particle.position);
  }
  const std::size_t fluid = water.fluid, real = positions.size();
  std::vector<EntityId> ids(real);
  for (std::size_t i = 0; i < real; ++i) ids[i] = static_cast<EntityId>(i);

  PeriodicBox box;
  box.low = origin;
  box.length = size;
  box.periodic = periodic;
  REQUIRE(periodic_cutoff_fits(box, radius));
  Halo halo;
  build_halo(positions, ids, box, radius, halo);
  REQUIRE(halo.size() > 0);
  std::vector<Vec3> ghosts;
  halo_copy_positions(halo, positions, ghosts);
  std::vector<Vec3> all = positions;
  all.insert(all.end(), ghosts.begin(), ghosts.end());
  FluidNeighbours lists;
  build_fluid_neighbours(all, radius, lists, fluid);
  REQUIRE(lists.particle_count() == fluid);

  // The infinite lattice's answer: the reals and their images one period either side.
  std::vector<Vec3> extended;
  for (const double shift : {-1.0, 0.0, 1.0})
    for (const Vec3& position : positions) extended.push_back(position + Vec3(shift * size[0], 0.0, 0.0));
  const WendlandKernel kernel(radius);
  std::vector<double> density(fluid, 0.0);
  bool any_ghost = false;
  for (std::size_t i = 0; i < fluid; ++i) {
    double nearest = 1e300;
    for (std::uint32_t k = lists.offsets[i]; k < lists.offsets[i + 1]; ++k) {
      const std::uint32_t j = lists.slots[k];
      REQUIRE(j < all.size());
      CHECK(halo.owner_of(j) != i);  // never its own image: the period exceeds 2 r_e
      any_ghost = any_ghost || j >= real;
      const double distance = (all[j] - all[i]).norm();
      nearest = std::min(nearest, distance);
      density[i] += kernel.weight(distance);
    }
    CHECK(nearest == doctest::Approx(kNeighbourSpacing).epsilon(1e-12));  // no gap nor overlap across the seam
    double expected = 0.0;
    for (std::size_t j = 0; j < extended.size(); ++j)
      if (j != real + i) expected += kernel.weight((extended[j] - positions[i]).norm());
    CHECK(density[i] == doctest::Approx(expected).epsilon(1e-12));
  }
  CHECK(any_ghost);
  // No dip at the seam: along x, each (y, z) row of the water has one number density.
  for (std::size_t i = 0; i < fluid; ++i) {
    const std::size_t row_start = i - i % static_cast<std::size_t>(cells[0]);  // fluid_box_layout: x fastest
    CHECK(density[i] == doctest::Approx(density[row_start]).epsilon(1e-12));
  }
}

TEST_CASE("the search at r* past a periodic face reaches the images of particles up to a step's travel further") {
  // r* is wrapped only at the correction, so at the predicted positions a particle may lie a step's travel δ past
  // the high face; it then meets the image of a particle up to r_e + skin + δ from the low face, which the halo must
  // hold. Theory: the brute-force pairs of the reals and their images one period either side.
  const double spacing = 0.01, effective_radius = 0.021, skin = 0.001;  // the narrow skin: a rebuild every step
  Model model = test::small_coupled_model(spacing);
  model.tank.motion = TankMotionModel{};
  model.tank.origin = Vec3::Zero();
  model.tank.size = Vec3(0.1, 0.1, 0.1);
  model.tank.periodic = {true, false, false};
  const PeriodicBox box = periodic_box(model);
  World world;
  test::fill_with_water(world, Vec3(0.1, 0.1, 0.1), spacing);
  world.fluid_neighbours.emplace();
  FluidParticles& water = *world.fluid;
  water.predicted_position = water.position;
  // The particle nearest the high face at mid-height steps 0.4 l0 past it; one particle of its row is put 0.3 l0
  // beyond the unwidened halo's reach (r_e + skin) from the low face, where the first one's image meets it 0.1 l0
  // inside r_e.
  const auto slot_at = [&](const Vec3& where) {
    std::size_t found = water.size();
    for (std::size_t i = 0; i < water.size(); ++i)
      if ((water.position[i] - where).norm() < 1e-9) found = i;
    REQUIRE(found < water.size());
    return found;
  };
  const std::size_t past = slot_at(Vec3(0.095, 0.055, 0.055)), beyond = slot_at(Vec3(0.025, 0.055, 0.055));
  const double travel = 0.4 * spacing;
  water.predicted_position[past].x() = 0.1 + travel;
  water.predicted_position[beyond].x() = effective_radius + skin + 0.3 * spacing;
  const Vec3 image = water.predicted_position[beyond] + Vec3(0.1, 0.0, 0.0);
  const double image_gap = (image - water.predicted_position[past]).norm();
  REQUIRE(image_gap < effective_radius);
  CHECK(periodic_overshoot(water.predicted_position, box) == doctest::Approx(travel).epsilon(1e-12));

  FluidNeighbourSearch search(effective_radius, skin, skin, FluidNeighbourSearch::Positions::kPredicted, box);
  const Access access = search.access();
  SystemContext context(world, model, search, access, 0.0, 1.0e-3);
  search.run(context);
  const FluidNeighbours& lists = *world.fluid_neighbours;
  // Every pair within r_e of the reals and their images, by brute force, is in the lists (cut at r_e).
  const std::size_t reals = water.size();
  std::vector<Vec3> all = water.predicted_position;
  all.insert(all.end(), lists.ghosts.predicted_position.begin(), lists.ghosts.predicted_position.end());
  std::size_t missed = 0, checked = 0;
  for (std::size_t i = 0; i < reals; ++i) {
    std::vector<std::uint32_t> owners_found;
    for (std::uint32_t k = lists.offsets[i]; k < lists.offsets[i + 1]; ++k) {
      const std::uint32_t j = lists.slots[k];
      if ((all[j] - all[i]).norm() < effective_radius) owners_found.push_back(lists.halo.owner_of(j));
    }
    for (std::size_t j = 0; j < reals; ++j)
      for (const double shift : {-0.1, 0.0, 0.1}) {
        if (j == i && shift == 0.0) continue;
        const Vec3 image = water.predicted_position[j] + Vec3(shift, 0.0, 0.0);
        if ((image - water.predicted_position[i]).norm() >= effective_radius) continue;
        ++checked;
        if (std::count(owners_found.begin(), owners_found.end(), static_cast<std::uint32_t>(j)) == 0) ++missed;
      }
  }
  MESSAGE(checked, " pairs within r_e checked, ", missed, " missed");
  CHECK(checked > 10000);
  CHECK(missed == 0);
}
