// Initial MPS lattices: fluid boxes and tank wall/dummy shells against closed-form counts (engine/setup/fluid_layout.hpp,
// numerics.md Sec. 3.1).
#include <doctest/doctest.h>

#include <algorithm>
#include <set>

#include "engine/setup/fluid_layout.hpp"

using namespace riffle;

namespace {

constexpr double kLayoutSpacing = 0.005;  // [m] l0
const Vec3 kOrigin(0.1, -0.2, 0.03);

/// Closed form of tank_wall_layout: prod (n_a + L_a^- + L_a^+) - prod n_a.
std::size_t layout_shell_count(const std::array<std::int64_t, 3>& cells, const std::array<bool, 6>& closed, std::int64_t layers) {
  std::int64_t outer = 1, inner = 1;
  for (std::size_t a = 0; a < 3; ++a) {
    outer *= cells[a] + (closed[2 * a] ? layers : 0) + (closed[2 * a + 1] ? layers : 0);
    inner *= cells[a];
  }
  return static_cast<std::size_t>(outer - inner);
}

Vec3 cells_to_size(const std::array<std::int64_t, 3>& cells) {
  return kLayoutSpacing * Vec3(static_cast<double>(cells[0]), static_cast<double>(cells[1]), static_cast<double>(cells[2]));
}

/// Smallest distance from each particle to any other (brute force).
std::vector<double> nearest_distances(const std::vector<Vec3>& positions) {
  std::vector<double> nearest(positions.size(), 1e300);
  for (std::size_t i = 0; i < positions.size(); ++i)
    for (std::size_t j = i + 1; j < positions.size(); ++j) {
      const double distance = (positions[j] - positions[i]).norm();
      nearest[i] = std::min(nearest[i], distance);
      nearest[j] = std::min(nearest[j], distance);
    }
  return nearest;
}

}  // namespace

TEST_CASE("dummy layers: ceil(r_e / l0) - 1") {
  CHECK(dummy_layer_count(kLayoutSpacing, 2.6 * kLayoutSpacing) == 2);
  CHECK(dummy_layer_count(kLayoutSpacing, 3.1 * kLayoutSpacing) == 3);
  CHECK(dummy_layer_count(kLayoutSpacing, 2.4 * kLayoutSpacing) == 2);
  CHECK(dummy_layer_count(kLayoutSpacing, 3.0 * kLayoutSpacing) == 2);  // w(r_e) = 0: a layer at exactly r_e adds nothing
  CHECK(dummy_layer_count(0.1, 0.3) == 2);                  // 0.3 / 0.1 = 2.9999999999999996
  CHECK_THROWS_AS(dummy_layer_count(0.0, 1.0), std::invalid_argument);
}

TEST_CASE("a fluid box is cell-centred: n_x n_y n_z particles, first layer l0/2 inside each face") {
  const std::array<std::int64_t, 3> cells{10, 7, 12};
  const Vec3 high = kOrigin + cells_to_size(cells);
  const FluidLayout layout = fluid_box_layout(kOrigin, kOrigin, high, kLayoutSpacing);
  CHECK(layout.fluid == 10 * 7 * 12);
  CHECK(layout.particles.size() == layout.fluid);
  CHECK(layout.wall == 0);
  CHECK(layout.dummy == 0);
  Vec3 low_seen = Vec3::Constant(1e300), high_seen = Vec3::Constant(-1e300);
  for (const LatticeParticle& particle : layout.particles) {
    CHECK(particle.kind == FluidKind::kFluid);
    CHECK(particle.face == -1);
    low_seen = low_seen.cwiseMin(particle.position);
    high_seen = high_seen.cwiseMax(particle.position);
  }
  for (int axis = 0; axis < 3; ++axis) {
    CHECK(low_seen[axis] - kOrigin[axis] == doctest::Approx(0.5 * kLayoutSpacing).epsilon(1e-9));
    CHECK(high[axis] - high_seen[axis] == doctest::Approx(0.5 * kLayoutSpacing).epsilon(1e-9));
  }
  // A box off the lattice keeps the cells whose centres it contains: centres 0.5 .. 3.5 l0 in [0.3, 4.2] l0.
  const FluidLayout shifted =
      fluid_box_layout(kOrigin, kOrigin + Vec3::Constant(0.3 * kLayoutSpacing), kOrigin + Vec3::Constant(4.2 * kLayoutSpacing), kLayoutSpacing);
  CHECK(shifted.fluid == 4 * 4 * 4);
  CHECK(shifted.particles.front().cell == std::array<std::int64_t, 3>{0, 0, 0});
}

TEST_CASE("tank walls and dummies: closed-form counts for r_e = 2.6 l0 and 3.1 l0, open faces, edges and corners") {
  const std::array<std::int64_t, 3> cells{10, 8, 12};
  struct Case {
    std::vector<std::string> open;
    std::array<bool, 6> closed;
  };
  const std::vector<Case> cases = {
      {{}, {true, true, true, true, true, true}},
      {{"z_max"}, {true, true, true, true, true, false}},
      {{"x_min", "z_max"}, {false, true, true, true, true, false}},
  };
  for (const double radius_ratio : {2.6, 3.1}) {
    const std::int64_t dummies = radius_ratio < 3.0 ? 2 : 3;
    for (const Case& tank : cases) {
      CAPTURE(radius_ratio);
      CAPTURE(tank.open.size());
      const FluidLayout layout =
          tank_wall_layout(kOrigin, cells_to_size(cells), tank.open, kLayoutSpacing, radius_ratio * kLayoutSpacing);
      CHECK(layout.fluid == 0);
      CHECK(layout.wall == layout_shell_count(cells, tank.closed, 1));
      CHECK(layout.dummy == layout_shell_count(cells, tank.closed, 1 + dummies) - layout_shell_count(cells, tank.closed, 1));
      CHECK(layout.particles.size() == layout.wall + layout.dummy);
      for (const LatticeParticle& particle : layout.particles) {
        // Position on the lattice; kind from the depth outside the inner box; owned by a closed face it lies beyond.
        std::int64_t depth = 0;
        for (std::size_t a = 0; a < 3; ++a) {
          CHECK(particle.position[static_cast<int>(a)] ==
                doctest::Approx(kOrigin[static_cast<int>(a)] + (static_cast<double>(particle.cell[a]) + 0.5) * kLayoutSpacing)
                    .epsilon(1e-12));
          depth = std::max({depth, -particle.cell[a], particle.cell[a] - cells[a] + 1});
        }
        CHECK(depth >= 1);
        CHECK(depth <= 1 + dummies);
        CHECK((particle.kind == FluidKind::kWall) == (depth == 1));
        REQUIRE(particle.face >= 0);
        REQUIRE(particle.face < 6);
        CHECK(tank.closed[static_cast<std::size_t>(particle.face)]);
        const std::size_t axis = static_cast<std::size_t>(particle.face) / 2;
        if (particle.face % 2 == 0) CHECK(particle.cell[axis] < 0);
        else CHECK(particle.cell[axis] >= cells[axis]);
        // The first face that claims it: no earlier face has it beyond.
        for (std::size_t earlier = 0; earlier < static_cast<std::size_t>(particle.face); ++earlier) {
          const std::size_t a = earlier / 2;
          CHECK_FALSE((earlier % 2 == 0 ? particle.cell[a] < 0 : particle.cell[a] >= cells[a]));
        }
      }
    }
  }
  CHECK_THROWS_AS(tank_wall_layout(kOrigin, Vec3(0.0503, 0.04, 0.06), {}, kLayoutSpacing, 2.6 * kLayoutSpacing), std::invalid_argument);
  CHECK_THROWS_AS(tank_wall_layout(kOrigin, cells_to_size(cells), {"top"}, kLayoutSpacing, 2.6 * kLayoutSpacing), std::invalid_argument);
}

TEST_CASE("fluid and tank share one lattice: no duplicates, nearest neighbour exactly l0") {
  const std::array<std::int64_t, 3> tank_cells{6, 5, 8};
  const std::array<std::int64_t, 3> water_cells{6, 5, 5};
  const FluidLayout walls = tank_wall_layout(kOrigin, cells_to_size(tank_cells), {"z_max"}, kLayoutSpacing, 3.1 * kLayoutSpacing);
  const FluidLayout water = fluid_box_layout(kOrigin, kOrigin, kOrigin + cells_to_size(water_cells), kLayoutSpacing);
  FluidParticles particles;
  append_layout(particles, water);
  const std::size_t first_wall = append_layout(particles, walls);
  CHECK(first_wall == water.fluid);
  CHECK(particles.size() == water.fluid + walls.wall + walls.dummy);
  CHECK_NOTHROW(check_field_sizes(particles, "fluid"));
  for (std::size_t slot = 0; slot < particles.size(); ++slot) {
    CHECK(particles.id[slot] == slot);
    CHECK(particles.velocity[slot] == Vec3::Zero());
    CHECK(particles.predicted_position[slot] == particles.position[slot]);
  }

  std::set<std::array<std::int64_t, 3>> cells;
  for (const FluidLayout* layout : {&water, &walls})
    for (const LatticeParticle& particle : layout->particles) CHECK(cells.insert(particle.cell).second);

  // Every particle's nearest other particle is exactly l0 away (rounding only): no duplicates, no gaps at the
  // fluid-wall seam (first fluid layer l0/2 inside, wall layer l0/2 outside).
  for (const double nearest : nearest_distances(particles.position))
    CHECK(nearest == doctest::Approx(kLayoutSpacing).epsilon(1e-12));
  // Each fluid particle in the first layer has a wall particle exactly l0 away across every closed face it touches.
  std::size_t seam_pairs = 0;
  for (std::size_t i = 0; i < water.fluid; ++i)
    for (std::size_t j = first_wall; j < particles.size(); ++j)
      if (particles.kind[j] == static_cast<std::int32_t>(FluidKind::kWall) &&
          std::abs((particles.position[j] - particles.position[i]).norm() - kLayoutSpacing) < 1e-12)
        ++seam_pairs;
  // Face-adjacent fluid-wall pairs: the bottom (6 x 5) and four sides over 5 water layers: 2 (6 + 5) 5.
  CHECK(seam_pairs == 6 * 5 + 2 * (6 + 5) * 5);
}
