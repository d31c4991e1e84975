// The packed start's packing (systems/physics/mps/particle_packing.hpp). What it must do, whatever its constants:
//  - move the water off the lattice (a disordered arrangement: particles a fraction of l0 from their sites, no two
//    closer than the lattice's next-nearest spacing allows under the random offset's reach) with a number density
//    as uniform as the projection holds it (the density term keeps n within a few tenths of a percent of n0);
//  - leave walls, dummies and the water within r_e of a free surface exactly where they were, so that the surface
//    and the walls' no-slip planes stay where the scene put them;
//  - give the same arrangement every time, and keep the water inside the period of a periodic box.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/setup/fluid_layout.hpp"
#include "systems/physics/mps/mps_kernel.hpp"
#include "systems/physics/mps/particle_packing.hpp"

namespace riffle {
namespace {

struct Water {
  std::vector<Vec3> positions;
  std::vector<char> fluid;
};

Water water_in_tank(const Vec3& size, double l0, const std::vector<std::string>& open_faces,
                    const std::array<bool, 3>& periodic) {
  Water water;
  for (const LatticeParticle& p : fluid_box_layout(Vec3::Zero(), Vec3::Zero(), size, l0).particles) {
    water.positions.push_back(p.position);
    water.fluid.push_back(1);
  }
  for (const LatticeParticle& p : tank_wall_layout(Vec3::Zero(), size, open_faces, l0, 2.4 * l0, periodic).particles) {
    water.positions.push_back(p.position);
    water.fluid.push_back(0);
  }
  return water;
}

double closest_pair(const std::vector<Vec3>& positions, const PeriodicBox& box) {
  double closest = 1e9;
  for (std::size_t i = 0; i < positions.size(); ++i)
    for (std::size_t j = i + 1; j < positions.size(); ++j) {
      Vec3 d = positions[j] - positions[i];
      for (int a = 0; a < 3; ++a)
        if (box.periodic[static_cast<std::size_t>(a)]) d[a] -= box.length[a] * std::round(d[a] / box.length[a]);
      closest = std::min(closest, d.norm());
    }
  return closest;
}

}  // namespace

TEST_CASE("packing moves the water off the lattice to a uniform number density, walls and surface water in place") {
  const double l0 = 0.01;
  const Vec3 size(0.12, 0.12, 0.12);
  Water water = water_in_tank(size, l0, {"z_max"}, {false, false, false});
  const std::vector<Vec3> lattice = water.positions;
  PackingSettings settings;
  settings.spacing = l0;
  settings.effective_radius = 2.4 * l0;
  const PeriodicBox box;  // no periodic axis
  const PackingReport report = pack_particles(water.positions, water.fluid, box, settings);

  // Every water particle deeper than r_e below the surface (z = 0.12) and with a complete kernel moved; the rest
  // and every wall or dummy particle stayed bit for bit.
  std::size_t moved = 0, surface_kept = 0;
  for (std::size_t i = 0; i < lattice.size(); ++i) {
    const bool changed = water.positions[i] != lattice[i];
    if (!water.fluid[i]) {
      CHECK_FALSE(changed);
      continue;
    }
    if (lattice[i].z() > size.z() - 2.4 * l0) {
      CHECK_FALSE(changed);
      ++surface_kept;
    }
    moved += changed ? 1 : 0;
  }
  CHECK(moved == report.moved);
  CHECK(surface_kept > 0);
  CHECK(moved > 1000);
  // Off the lattice: a fifth of the offset's reach or more on average, and the offset's spread of n mostly gone.
  CHECK(report.mean_offset > 0.1);
  CHECK(report.mean_offset < 0.35);
  CHECK(report.spread_after_offset > 0.03);
  CHECK(report.spread_after_packing < 0.01);
  CHECK(report.spread_after_packing < 0.2 * report.spread_after_offset);
  // Nobody inside another's core: the lattice's spacing less twice the offset's diagonal reach would be 0.31 l0.
  CHECK(closest_pair(water.positions, box) > 0.5 * l0);
  // Every water particle still inside the tank, off its walls by a third of a spacing at least.
  for (std::size_t i = 0; i < water.positions.size(); ++i)
    if (water.fluid[i]) {
      CHECK((water.positions[i].array() > l0 / 3.0).all());
      CHECK((water.positions[i].array() < size.array() - l0 / 3.0).all());
    }

  // The same arrangement again.
  Water again = water_in_tank(size, l0, {"z_max"}, {false, false, false});
  pack_particles(again.positions, again.fluid, box, settings);
  CHECK(again.positions == water.positions);
}

TEST_CASE("packing in a box periodic along x and y reaches across the seams and keeps the water in the period") {
  const double l0 = 0.01;
  const Vec3 size(0.1, 0.1, 0.1);
  Water water = water_in_tank(size, l0, {"z_max"}, {true, true, false});
  PeriodicBox box;
  box.length = size;
  box.periodic = {true, true, false};
  PackingSettings settings;
  settings.spacing = l0;
  settings.effective_radius = 2.4 * l0;
  const PackingReport report = pack_particles(water.positions, water.fluid, box, settings);
  // With the seams joined every column is complete to the surface layer: all but the top r_e of water move.
  std::size_t deep = 0;
  for (std::size_t i = 0; i < water.positions.size(); ++i)
    if (water.fluid[i] && water.positions[i].z() < size.z() - 2.4 * l0 - 0.5 * l0) ++deep;
  CHECK(report.moved >= deep - 200);  // those near the surface layer's depth may or may not count as deep
  CHECK(report.spread_after_packing < 0.01);
  for (std::size_t i = 0; i < water.positions.size(); ++i)
    if (water.fluid[i]) {
      CHECK(water.positions[i].x() >= 0.0);
      CHECK(water.positions[i].x() < size.x());
      CHECK(water.positions[i].y() >= 0.0);
      CHECK(water.positions[i].y() < size.y());
    }
  CHECK(closest_pair(water.positions, box) > 0.5 * l0);
}

}  // namespace riffle
