// Number density and free-surface flag on a still water column in a tank with wall and dummy particles
// (systems/fluid_number_density.hpp; numerics.md Secs. 1.1, 3.1 and 3.4).
#include <doctest/doctest.h>

#include <cmath>

#include "engine/fluid_layout.hpp"
#include "systems/fluid_neighbours.hpp"
#include "systems/fluid_number_density.hpp"

using namespace riffle;

namespace {

constexpr double kSpacing = 0.005;  // [m] l0
const Vec3 kOrigin(-0.02, 0.01, 0.0);
constexpr std::int64_t kColumn[3] = {10, 10, 12};  // water layers along x, y, z

struct Column {
  FluidParticles particles;
  FluidNeighbours neighbours;
  std::size_t fluid = 0;
};

/// The water column in an open-top tank `tank_layers` high, neighbours and number density computed.
Column still_column(double radius_ratio, std::int64_t tank_layers, std::int64_t dummy_layers_removed = 0) {
  const double radius = radius_ratio * kSpacing;
  Column column;
  const Vec3 water = kSpacing * Vec3(kColumn[0], kColumn[1], kColumn[2]);
  const Vec3 tank = kSpacing * Vec3(kColumn[0], kColumn[1], static_cast<double>(tank_layers));
  column.fluid = fluid_box_layout(kOrigin, kOrigin, kOrigin + water, kSpacing).fluid;
  append_layout(column.particles, fluid_box_layout(kOrigin, kOrigin, kOrigin + water, kSpacing));
  FluidLayout walls = tank_wall_layout(kOrigin, tank, {"z_max"}, kSpacing, radius);
  if (dummy_layers_removed > 0) {
    // Drop the outermost dummy layers (to show that ceil(r_e/l0) - 1 layers are needed, not fewer).
    const std::int64_t keep = dummy_layer_count(kSpacing, radius) + 1 - dummy_layers_removed;
    std::erase_if(walls.particles, [&](const LatticeParticle& particle) {
      const std::int64_t cells[3] = {kColumn[0], kColumn[1], tank_layers};
      for (std::size_t a = 0; a < 3; ++a)
        if (-particle.cell[a] > keep || particle.cell[a] - cells[a] + 1 > keep) return true;
      return false;
    });
  }
  append_layout(column.particles, walls);
  build_fluid_neighbours(column.particles.position, radius, column.neighbours);
  const double n0 = lattice_constants(3, kSpacing, radius).number_density;
  compute_number_density(column.particles, column.neighbours, WendlandKernel{radius}, n0, 0.93);
  return column;
}

/// Layer index (0 = bottom) of a fluid particle.
std::int64_t layer_of(const Vec3& position) {
  return static_cast<std::int64_t>(std::floor((position[2] - kOrigin[2]) / kSpacing));
}

/// Independent half-space sum: n of a particle `below` layers under the top layer of a perfect lattice filling
/// z <= top (full support sideways and below).
double half_space_density(double radius_ratio, std::int64_t below) {
  const WendlandKernel kernel{radius_ratio * kSpacing};
  const auto reach = static_cast<std::int64_t>(std::ceil(radius_ratio));
  double sum = 0.0;
  for (std::int64_t i = -reach; i <= reach; ++i)
    for (std::int64_t j = -reach; j <= reach; ++j)
      for (std::int64_t k = -reach; k <= std::min(reach, below); ++k) {
        if (i == 0 && j == 0 && k == 0) continue;
        sum += kernel.weight(kSpacing * std::sqrt(static_cast<double>(i * i + j * j + k * k)));
      }
  return sum;
}

}  // namespace

TEST_CASE("still water column: n = n0 wherever the support is full, walls included, and only the top layer is surface") {
  for (const double ratio : {2.6, 3.1}) {
    CAPTURE(ratio);
    const Column column = still_column(ratio, kColumn[2]);  // walls up to the water surface
    const double n0 = lattice_constants(3, kSpacing, ratio * kSpacing).number_density;
    const auto reach = static_cast<std::int64_t>(std::floor(ratio));  // layers above that a particle sees
    std::size_t surface = 0, checked_full = 0;
    for (std::size_t i = 0; i < column.fluid; ++i) {
      const std::int64_t below_top = kColumn[2] - 1 - layer_of(column.particles.position[i]);
      const double n = column.particles.number_density[i];
      if (below_top >= reach) {
        // Full support: interior, next to the side walls and the bottom, in the corners (dummies complete it).
        CHECK(n / n0 == doctest::Approx(1.0).epsilon(1e-12));
        ++checked_full;
      } else {
        CHECK(n / half_space_density(ratio, below_top) == doctest::Approx(1.0).epsilon(1e-12));
      }
      CHECK(column.particles.free_surface[i] == (below_top == 0 ? 1 : 0));
      surface += static_cast<std::size_t>(column.particles.free_surface[i]);
    }
    CHECK(surface == static_cast<std::size_t>(kColumn[0] * kColumn[1]));
    CHECK(checked_full == static_cast<std::size_t>(kColumn[0] * kColumn[1] * (kColumn[2] - reach)));
    for (std::size_t i = column.fluid; i < column.particles.size(); ++i) CHECK(column.particles.free_surface[i] == 0);
  }
  // numerics 3.4, half-space lattice, 3D: r_e = 2.6 l0 gives 0.74 and 0.996 for the top two layers, 3.1 l0 0.71
  // and 0.977; beta = 0.93 separates both.
  const double n0_26 = lattice_constants(3, kSpacing, 2.6 * kSpacing).number_density;
  const double n0_31 = lattice_constants(3, kSpacing, 3.1 * kSpacing).number_density;
  CHECK(half_space_density(2.6, 0) / n0_26 == doctest::Approx(0.74).epsilon(0.01));
  CHECK(half_space_density(2.6, 1) / n0_26 == doctest::Approx(0.996).epsilon(0.001));
  CHECK(half_space_density(3.1, 0) / n0_31 == doctest::Approx(0.71).epsilon(0.01));
  CHECK(half_space_density(3.1, 1) / n0_31 == doctest::Approx(0.977).epsilon(0.001));
}

TEST_CASE("ceil(r_e/l0) - 1 dummy layers give the wall particles full support too, and one fewer does not") {
  // A fluid particle on a wall needs floor(r_e/l0) layers beyond it (wall + 1 dummy at 2.6 l0, wall + 2 at 3.1 l0);
  // the wall particle itself needs one more, which the spec's ceil(r_e/l0) - 1 dummy layers provide.
  for (const double ratio : {2.6, 3.1}) {
    CAPTURE(ratio);
    const double n0 = lattice_constants(3, kSpacing, ratio * kSpacing).number_density;
    const auto reach = static_cast<std::int64_t>(std::floor(ratio));
    for (const std::int64_t removed : {0, 1, 2}) {
      CAPTURE(removed);
      const Column column = still_column(ratio, kColumn[2], removed);
      bool fluid_full = true, walls_full = true;
      std::size_t walls_checked = 0;
      for (std::size_t i = 0; i < column.particles.size(); ++i) {
        if (layer_of(column.particles.position[i]) > kColumn[2] - 1 - reach) continue;  // support reaches the air
        const bool full = std::abs(column.particles.number_density[i] / n0 - 1.0) < 1e-12;
        if (column.particles.kind[i] == static_cast<std::int32_t>(FluidKind::kFluid)) fluid_full = fluid_full && full;
        if (column.particles.kind[i] == static_cast<std::int32_t>(FluidKind::kWall)) {
          walls_full = walls_full && full;
          ++walls_checked;
        }
      }
      CHECK(walls_checked > 0);
      CHECK(walls_full == (removed == 0));
      CHECK(fluid_full == (removed <= 1));
    }
  }
}

TEST_CASE("taller tank: the walls above the water raise n near them, but still only the top layer is surface") {
  const Column column = still_column(2.6, kColumn[2] + 4);
  std::size_t surface = 0;
  for (std::size_t i = 0; i < column.fluid; ++i) {
    const std::int64_t below_top = kColumn[2] - 1 - layer_of(column.particles.position[i]);
    CHECK(column.particles.free_surface[i] == (below_top == 0 ? 1 : 0));
    surface += static_cast<std::size_t>(column.particles.free_surface[i]);
  }
  CHECK(surface == static_cast<std::size_t>(kColumn[0] * kColumn[1]));
}

TEST_CASE("the neighbour and number-density systems run through checked component access") {
  const double radius = 2.6 * kSpacing;
  World world;
  world.fluid.emplace();
  world.fluid_neighbours.emplace();
  const Vec3 water = kSpacing * Vec3(kColumn[0], kColumn[1], kColumn[2]);
  append_layout(*world.fluid, fluid_box_layout(kOrigin, kOrigin, kOrigin + water, kSpacing));
  append_layout(*world.fluid, tank_wall_layout(kOrigin, water, {"z_max"}, kSpacing, radius));
  CHECK(world.has(ComponentId::kFluid));
  CHECK(world.has(ComponentId::kFluidNeighbours));
  CHECK(component_name(ComponentId::kFluid) == "fluid");
  CHECK(component_name(ComponentId::kFluidNeighbours) == "fluid_neighbours");
  const Model model;
  FluidNeighbourSearch search(radius);
  FluidNumberDensity density({kSpacing, radius, 0.93});
  CHECK(density.reference_density() == lattice_constants(3, kSpacing, radius).number_density);
  for (System* system : std::initializer_list<System*>{&search, &density}) {
    const Access access = system->access();
    SystemContext context(world, model, *system, access, 0.0, 1e-3);
    system->run(context);
    CHECK(context.items() == world.fluid->size());
  }
  const Column reference = still_column(2.6, kColumn[2]);
  CHECK(world.fluid->number_density == reference.particles.number_density);
  CHECK(world.fluid->free_surface == reference.particles.free_surface);
  CHECK(world.fluid_neighbours->slots == reference.neighbours.slots);
}
