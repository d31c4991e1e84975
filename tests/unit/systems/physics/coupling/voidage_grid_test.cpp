// The smoothed voidage grid (systems/physics/coupling/voidage_grid.hpp; docs/COUPLING.md, "The voidage at a grain"): the
// binomial pass keeps both deposits' totals, a grain's own share read back is its whole reading when it is alone
// (whatever its place in a cell), and points outside the bounds or not finite stay safe.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "systems/physics/coupling/voidage_grid.hpp"

namespace {
double total_fluid(const riffle::VoidageGrid& grid) {
  double sum = 0.0;
  for (std::size_t n = 0; n < grid.node_count(); ++n) sum += grid.fluid_volume(n);
  return sum;
}

/// A 10 x 10 x 10 lattice of fluid points, 1 cm apart.
std::vector<riffle::Vec3> fluid_lattice() {
  std::vector<riffle::Vec3> fluid;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      for (int k = 0; k < 10; ++k) fluid.emplace_back(0.005 + 0.01 * i, 0.005 + 0.01 * j, 0.005 + 0.01 * k);
  return fluid;
}
}  // namespace

TEST_CASE("voidage grid: smoothing keeps the deposits' totals") {
  const std::vector<riffle::Vec3> fluid = fluid_lattice();
  riffle::VoidageGrid grid;
  grid.build({{0.05, 0.05, 0.05}}, {1e-6}, fluid, fluid.size(), 1e-6, 0.013, riffle::Vec3::Constant(-1.0),
             riffle::Vec3::Constant(1.0));
  const double before = total_fluid(grid);
  CHECK(before == doctest::Approx(1e-3).epsilon(1e-12));
  grid.smooth();
  // The build leaves a free node at each end of every axis, so nothing is filtered off the grid.
  CHECK(total_fluid(grid) == doctest::Approx(before).epsilon(1e-12));
}

TEST_CASE("voidage grid: a lone grain's own share is its whole reading, smoothed or not") {
  const std::vector<riffle::Vec3> fluid = fluid_lattice();
  for (const bool smoothed : {false, true})
    for (const riffle::Vec3& point : {riffle::Vec3(0.05, 0.05, 0.05), riffle::Vec3(0.0131, 0.0477, 0.0912),
                                      riffle::Vec3(0.005, 0.005, 0.005)}) {
      CAPTURE(smoothed);
      riffle::VoidageGrid grid;
      grid.build({point}, {5.2e-7}, fluid, fluid.size(), 1e-6, 0.0134, riffle::Vec3::Constant(-1.0),
                 riffle::Vec3::Constant(1.0));
      if (smoothed) grid.smooth();
      const riffle::GrainSolidFraction read = grid.grain_fraction(point, 5.2e-7);
      CHECK(read.included > 0.0);
      CHECK(read.own == doctest::Approx(read.included).epsilon(1e-12));
      if (!smoothed) CHECK(read.included == doctest::Approx(grid.solid_fraction(point)).epsilon(1e-12));
    }
}

TEST_CASE("voidage grid: points outside the bounds or not finite read safely") {
  const std::vector<riffle::Vec3> fluid = fluid_lattice();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<riffle::Vec3> grains = {{0.05, 0.05, 0.05}, {nan, 0.0, 0.0}, {1e300, -1e300, 0.0}};
  riffle::VoidageGrid grid;
  grid.build(grains, {1e-7, 1e-7, 1e-7}, fluid, fluid.size(), 1e-6, 0.013, riffle::Vec3::Zero(),
             riffle::Vec3::Constant(0.1));
  grid.smooth();
  for (const riffle::Vec3& point : grains) {
    const riffle::GrainSolidFraction read = grid.grain_fraction(point, 1e-7);
    CHECK(std::isfinite(read.included));
    CHECK(std::isfinite(read.own));
  }
  CHECK(static_cast<double>(grid.node_count()) <= riffle::voidage_node_limit(grains.size() + fluid.size()));
}

TEST_CASE("voidage: the hard-sphere structure factor and the self correction") {
  // Carnahan-Starling: S(0) = 1 - 8 phi + O(phi^2) for a dilute suspension (the excluded volume of a sphere is 8 V).
  CHECK(riffle::hard_sphere_structure_factor(0.0) == 1.0);
  CHECK(riffle::hard_sphere_structure_factor(1e-4) == doctest::Approx(1.0 - 8e-4).epsilon(1e-6));
  CHECK(riffle::hard_sphere_structure_factor(0.6) ==
        doctest::Approx(std::pow(0.4, 4) / (1 + 2.4 + 1.44 - 0.864 + 0.1296)));
  // A lone grain (no others) reads nothing, whatever its own share.
  CHECK(riffle::self_corrected_solid_fraction(0.0, 0.2) == 0.0);
  // In a dense packing (S(0) ~ 0) the grain's own volume comes back nearly whole.
  CHECK(riffle::self_corrected_solid_fraction(0.55, 0.05) == doctest::Approx(0.6).epsilon(1e-3));
  // The fixed point: phi = others + own (1 - S(phi)).
  const double others = 0.08, own = 0.04, phi = riffle::self_corrected_solid_fraction(others, own);
  CHECK(phi == doctest::Approx(others + own * (1.0 - riffle::hard_sphere_structure_factor(phi))).epsilon(1e-3));
}

// Periodic along x and y (a 0.1 m period over the lattice, which joins its image at 1 cm): the grid wraps, so the
// fluid field repeats along x and y across the seam, the smoothing keeps the totals round the ring, and a grain on
// the seam reads what the same grain half a period away reads (the period is 8 whole cells of 12.5 mm, asked 12 mm).
TEST_CASE("voidage grid: periodic axes wrap the deposits, the smoothing and the read back") {
  const std::vector<riffle::Vec3> fluid = fluid_lattice();
  riffle::PeriodicBox box;
  box.low = riffle::Vec3::Zero();
  box.length = riffle::Vec3(0.1, 0.1, 0.1);
  box.periodic = {true, true, false};
  const auto build = [&](const riffle::Vec3& grain, bool smoothed) {
    riffle::VoidageGrid grid;
    grid.build({grain}, {2e-6}, fluid, fluid.size(), 1e-6, 0.012, riffle::Vec3::Constant(-1.0),
               riffle::Vec3::Constant(1.0), box);
    if (smoothed) grid.smooth();
    return grid;
  };
  for (const bool smoothed : {false, true}) {
    CAPTURE(smoothed);
    const riffle::VoidageGrid seam = build({0.001, 0.099, 0.05}, smoothed);
    CHECK(total_fluid(seam) == doctest::Approx(1e-3).epsilon(1e-12));
    // The same along x and y wherever the lattice is (nodes 12.5 mm apart over points 10 mm apart repeat every
    // 4 nodes): the cell at the seam holds what the cell half a period away holds (a grid that did not wrap would
    // hold less at its ends).
    const riffle::CloudInCellStencil a = seam.stencil({0.001, 0.001, 0.05});
    const riffle::CloudInCellStencil b = seam.stencil({0.051, 0.051, 0.05});
    for (std::size_t c = 0; c < 8; ++c)
      CHECK(seam.fluid_volume(a.node[c]) == doctest::Approx(seam.fluid_volume(b.node[c])).epsilon(1e-12));
    const riffle::VoidageGrid middle = build({0.051, 0.049, 0.05}, smoothed);
    const riffle::GrainSolidFraction on_seam = seam.grain_fraction({0.001, 0.099, 0.05}, 2e-6);
    const riffle::GrainSolidFraction away = middle.grain_fraction({0.051, 0.049, 0.05}, 2e-6);
    CHECK(on_seam.included > 0.0);
    CHECK(on_seam.included == doctest::Approx(away.included).epsilon(1e-12));
    CHECK(on_seam.own == doctest::Approx(away.own).epsilon(1e-12));
    CHECK(seam.solid_fraction({0.001, 0.099, 0.05}) == doctest::Approx(middle.solid_fraction({0.051, 0.049, 0.05}))
                                                           .epsilon(1e-12));
  }
}

// Periodic axes take the whole period in whole cells whatever the points span, so the node limit must count them:
// two grains in a 40 m x 40 m periodic channel with 1 cm cells asked for 4000 x 4000 nodes along x and y (16e6 per
// layer, two arrays) before the check did.
TEST_CASE("voidage grid: a long period with few points stays within the node limit") {
  riffle::PeriodicBox box;
  box.low = riffle::Vec3::Zero();
  box.length = riffle::Vec3(40.0, 40.0, 1.0);
  box.periodic = {true, true, false};
  riffle::VoidageGrid grid;
  const std::vector<riffle::Vec3> grains = {{1.0, 1.0, 0.1}};
  const std::vector<riffle::Vec3> fluid = {{39.9999, 1.0, 0.1}};  // just below the seam at x = 40 m
  grid.build(grains, {1e-6}, fluid, 1, 1e-6, 0.01, riffle::Vec3::Zero(), riffle::Vec3(40.0, 40.0, 1.0), box);
  CHECK(static_cast<double>(grid.node_count()) <= riffle::voidage_node_limit(2));
  CHECK(grid.node_count() > 1000);  // coarsened only as far as needed
  // Still a wrapping grid: the water just below the seam lands on the node at x = 0, the one nearest a point just
  // above it.
  CHECK(total_fluid(grid) == doctest::Approx(1e-6).epsilon(1e-12));
  const riffle::CloudInCellStencil above_seam = grid.stencil({0.0001, 1.0, 0.1});
  double largest = 0.0;
  for (std::size_t c = 0; c < 8; ++c) largest = std::max(largest, grid.fluid_volume(above_seam.node[c]));
  CHECK(largest > 0.5e-6);
}

TEST_CASE("voidage grid: the box's volume per node sums to the box, per-axis cells, and equals a fine fluid's deposit") {
  // A grid with cells 13 x 13 x 4 mm over points spanning the box [0, 0.1]^3: the nodes' shares of the box sum to its
  // volume (the tents sum to one inside the grid), and match the deposit of a fluid filling the box on a lattice 1 mm
  // apart to the lattice's quadrature error (well under 1 % per node that the box covers a quarter of or more).
  const riffle::Vec3 low = riffle::Vec3::Zero(), high = riffle::Vec3::Constant(0.1);
  const riffle::Vec3 cells(0.013, 0.013, 0.004);
  const std::vector<riffle::Vec3> corners{low, high};
  riffle::VoidageGrid box;
  box.build(corners, {0.0, 0.0}, corners, 0, 0.0, cells, riffle::Vec3::Constant(-1.0), riffle::Vec3::Constant(1.0));
  box.fill_box_volume(low, high);
  CHECK(total_fluid(box) == doctest::Approx(1e-3).epsilon(1e-12));
  std::vector<riffle::Vec3> fine;
  for (int i = 0; i < 100; ++i)
    for (int j = 0; j < 100; ++j)
      for (int k = 0; k < 100; ++k) fine.emplace_back(0.0005 + 0.001 * i, 0.0005 + 0.001 * j, 0.0005 + 0.001 * k);
  fine.push_back(low);  // the same bounds as the box's grid
  fine.push_back(high);
  riffle::VoidageGrid water;
  water.build(corners, {0.0, 0.0}, fine, fine.size() - 2, 1e-9, cells, riffle::Vec3::Constant(-1.0),
              riffle::Vec3::Constant(1.0));
  REQUIRE(water.node_count() == box.node_count());
  const double full = cells.prod();
  double worst = 0.0;
  for (std::size_t n = 0; n < box.node_count(); ++n)
    if (box.fluid_volume(n) > 0.25 * full)
      worst = std::max(worst, std::abs(water.fluid_volume(n) / box.fluid_volume(n) - 1.0));
  MESSAGE("worst relative difference between the box's volume and a 1 mm fluid's deposit: " << worst);
  CHECK(worst < 0.01);
  // Smoothing keeps the total.
  box.smooth();
  CHECK(total_fluid(box) == doctest::Approx(1e-3).epsilon(1e-12));
}

TEST_CASE("voidage grid: a lattice anchored below its points puts its nodes where the grid over every point does") {
  // One grid over two grains far apart; a second over the upper grain alone, anchored at the lower one's corner:
  // the upper grain's solid fraction is the same (its nodes are the same nodes, placed from the anchor by whole cells),
  // to rounding.
  const std::vector<riffle::Vec3> both{riffle::Vec3(0.013, 0.021, 0.017), riffle::Vec3(0.301, 0.207, 0.143)};
  const std::vector<double> volumes{1e-7, 2e-7};
  riffle::VoidageGrid whole, part;
  whole.build(both, volumes, both, 0, 0.0, 0.0123, riffle::Vec3::Zero(), riffle::Vec3::Constant(1.0));
  part.anchor_lattice(both[0]);
  part.build(std::vector<riffle::Vec3>{both[1]}, std::vector<double>{volumes[1]}, both, 0, 0.0, 0.0123, riffle::Vec3::Zero(),
             riffle::Vec3::Constant(1.0));
  whole.fill_box_volume(riffle::Vec3::Zero(), riffle::Vec3::Constant(1.0));
  part.fill_box_volume(riffle::Vec3::Zero(), riffle::Vec3::Constant(1.0));
  CHECK(part.solid_fraction(both[1]) == doctest::Approx(whole.solid_fraction(both[1])).epsilon(1e-12));
  CHECK(part.solid_fraction(both[1]) > 0.0);
  // Without the anchor the lattice starts at the upper grain itself: other nodes, another reading.
  riffle::VoidageGrid unanchored;
  unanchored.build(std::vector<riffle::Vec3>{both[1]}, std::vector<double>{volumes[1]}, both, 0, 0.0, 0.0123, riffle::Vec3::Zero(),
                   riffle::Vec3::Constant(1.0));
  unanchored.fill_box_volume(riffle::Vec3::Zero(), riffle::Vec3::Constant(1.0));
  CHECK(unanchored.solid_fraction(both[1]) != doctest::Approx(whole.solid_fraction(both[1])).epsilon(1e-6));
}
