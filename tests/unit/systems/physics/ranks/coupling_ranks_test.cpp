#include <doctest/doctest.h>

#include <vector>

#include "systems/physics/ranks/coupling_ranks.hpp"

using namespace riffle;

TEST_CASE("coupling ranks: a point near a box within the reach along every axis, or through a periodic seam") {
  const PartBox part{Vec3(0.0, 0.0, 0.0), Vec3(0.5, 1.0, 1.0)};
  const PeriodicBox none;
  CHECK(near_part(Vec3(0.25, 0.5, 0.5), part, 0.0, none));
  CHECK(near_part(Vec3(0.59, 0.5, 0.5), part, 0.1, none));
  CHECK_FALSE(near_part(Vec3(0.61, 0.5, 0.5), part, 0.1, none));
  CHECK_FALSE(near_part(Vec3(0.59, 1.2, 0.5), part, 0.1, none));  // near along x, not along y
  // Periodic along x over [0, 1): 0.95 lies 0.05 from the box's low face through the seam; 0.8 lies 0.2 from either.
  PeriodicBox periodic;
  periodic.length = Vec3(1.0, 1.0, 1.0);
  periodic.periodic = {true, false, false};
  CHECK_FALSE(near_part(Vec3(0.95, 0.5, 0.5), part, 0.1, none));
  CHECK(near_part(Vec3(0.95, 0.5, 0.5), part, 0.1, periodic));
  CHECK_FALSE(near_part(Vec3(0.8, 0.5, 0.5), part, 0.1, periodic));
  // Not along y, whose axis is not periodic.
  CHECK_FALSE(near_part(Vec3(0.25, 1.95, 0.5), part, 0.1, periodic));
}

TEST_CASE("coupling ranks: on one rank nothing is sent, and the exchange delivers nothing") {
  CouplingBoxes boxes;
  boxes.of_rank = {{PartBox{Vec3(0, 0, 0), Vec3(1, 1, 1)}}};
  boxes.reach = 10.0;
  const std::vector<Vec3> points{Vec3(0.5, 0.5, 0.5), Vec3(5, 5, 5)};
  const std::vector<std::vector<std::uint32_t>> near = indices_near_other_ranks(points, boxes, PeriodicBox{});
  REQUIRE(near.size() == 1);
  CHECK(near[0].empty());  // this rank's own: never sent to itself
  int unpacked = 0;
  const std::size_t received = exchange_records(
      near, [&](ByteWriter& out, std::uint32_t i) { out.put(points[i]); },
      [&](ByteReader& in) { (void)in.get<Vec3>(), ++unpacked; });
  CHECK(received == 0);
  CHECK(unpacked == 0);
  // The lowest corner of the points and of the others given.
  const std::vector<Vec3> more{Vec3(-1, 7, 7)};
  const Vec3 low = lowest_corner_over_ranks(points, more);
  CHECK(low.x() == -1.0);
  CHECK(low.y() == 0.5);
  CHECK(low.z() == 0.5);
}
