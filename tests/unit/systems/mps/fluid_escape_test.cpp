// What counts as an escaped fluid particle (systems/physics/geometry/domain.hpp) and how the MPS table is compacted when
// one is removed (components/soa.hpp keep_fields), on hand-made cases with known answers.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "components/fluid.hpp"
#include "components/soa.hpp"
#include "systems/physics/geometry/domain.hpp"

using namespace riffle;

TEST_CASE("distance outside a box: 0 inside and on it, Euclidean to the nearest face, edge or corner") {
  const Vec3 low(0.0, 0.0, 0.0), high(1.0, 2.0, 3.0);
  CHECK(distance_outside_box(low, high, Vec3(0.5, 1.0, 1.5)) == 0.0);
  CHECK(distance_outside_box(low, high, Vec3(1.0, 2.0, 3.0)) == 0.0);
  CHECK(distance_outside_box(low, high, Vec3(0.5, 1.0, 3.25)) == 0.25);       // above a face
  CHECK(distance_outside_box(low, high, Vec3(-0.5, 1.0, 1.5)) == 0.5);        // beside one
  CHECK(distance_outside_box(low, high, Vec3(1.3, 1.0, 3.4)) == doctest::Approx(0.5).epsilon(1e-15));  // edge 3-4-5
  CHECK(distance_outside_box(low, high, Vec3(-1.0, -2.0, 5.0)) == 3.0);       // corner: sqrt(1 + 4 + 4)
}

TEST_CASE("a fluid particle escapes when it leaves the domain, or alone beyond escape_distance, a NaN never does") {
  const DomainBox domain{Vec3(-0.1, -0.1, -0.1), Vec3(1.1, 1.1, 1.5)};
  const Vec3 tank_low = Vec3::Zero(), tank_high = Vec3::Ones();
  const Vec3 still = Vec3::Zero();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const auto kind = [&](const Vec3& position, const Vec3& velocity, double density, double distance) {
    return fluid_escape_kind(position, velocity, density, domain, tank_low, tank_high, distance);
  };
  // In the water, and spray inside the tank (lone or not): stays.
  CHECK(kind(Vec3(0.5, 0.5, 0.5), still, 20.0, 0.1) == FluidEscapeKind::kNone);
  CHECK(kind(Vec3(0.5, 0.5, 0.9), still, 0.0, 0.1) == FluidEscapeKind::kNone);
  // Outside the domain box, whatever its neighbours: left the domain.
  CHECK(kind(Vec3(0.5, 0.5, 1.6), still, 3.0, inf) == FluidEscapeKind::kLeftDomain);
  CHECK(kind(Vec3(-0.2, 0.5, 0.5), still, 0.0, 0.1) == FluidEscapeKind::kLeftDomain);
  // Above the open top, inside the domain: alone and farther than the distance flies free; with a neighbour
  // (a sheet, not a droplet), nearer, or without an escape_distance, it stays.
  CHECK(kind(Vec3(0.5, 0.5, 1.2), still, 0.0, 0.1) == FluidEscapeKind::kFlewFree);
  CHECK(kind(Vec3(0.5, 0.5, 1.2), still, 1e-3, 0.1) == FluidEscapeKind::kNone);
  CHECK(kind(Vec3(0.5, 0.5, 1.05), still, 0.0, 0.1) == FluidEscapeKind::kNone);
  CHECK(kind(Vec3(0.5, 0.5, 1.2), still, 0.0, inf) == FluidEscapeKind::kNone);
  // Non-finite: never removed (fluid_checks stops the run naming it).
  CHECK(kind(Vec3(nan, 0.5, 0.5), still, 0.0, 0.1) == FluidEscapeKind::kNone);
  CHECK(kind(Vec3(0.5, 0.5, 1.2), Vec3(0.0, nan, 0.0), 0.0, 0.1) == FluidEscapeKind::kNone);
  CHECK(kind(Vec3(0.5, 0.5, 2.0), Vec3(inf, 0.0, 0.0), 0.0, 0.1) == FluidEscapeKind::kNone);
}

TEST_CASE("keep_fields drops slots and keeps every field of the others together, in order") {
  FluidParticles particles;
  for (int k = 0; k < 6; ++k)
    particles.add(Vec3(k, 0.0, 0.0), Vec3(0.0, k, 0.0), k < 4 ? FluidKind::kFluid : FluidKind::kWall);
  for (std::size_t i = 0; i < particles.size(); ++i) particles.pressure[i] = 10.0 * static_cast<double>(i);
  keep_fields(particles, {0, 2, 4, 5});  // fluid slots 1 and 3 go
  REQUIRE(particles.size() == 4);
  CHECK_NOTHROW(check_field_sizes(particles, "fluid"));
  CHECK(particles.id == std::vector<EntityId>{0, 2, 4, 5});
  CHECK(particles.kind == std::vector<std::int32_t>{0, 0, 1, 1});
  CHECK(particles.pressure == std::vector<double>{0.0, 20.0, 40.0, 50.0});
  CHECK(particles.position[1] == Vec3(2.0, 0.0, 0.0));
  CHECK(particles.velocity[3] == Vec3(0.0, 5.0, 0.0));
  CHECK(particles.next_id == 6);  // removed ids are not reused
}
