// The contact pass's slabs: every grain once, slab order by position, each slab at least a reach thick, a multiple
// of three along a periodic axis, and every pair within the reach in the same or a neighbouring slab.
#include <doctest/doctest.h>

#include <random>
#include <set>

#include "systems/physics/dem/contact_slabs.hpp"

using namespace riffle;

namespace {
std::vector<std::uint32_t> slab_of(const ContactSlabs& slabs, std::size_t grains) {
  std::vector<std::uint32_t> of(grains, ~0u);
  for (std::uint32_t s = 0; s < slabs.count(); ++s)
    for (std::uint32_t n = slabs.offsets[s]; n < slabs.offsets[s + 1]; ++n) of[slabs.grains[n]] = s;
  return of;
}
}  // namespace

TEST_CASE("slab counts: a reach or more thick, a multiple of 6 from 6 on, of 3 along a periodic axis") {
  CHECK(contact_slab_count(1.0, 0.3, false) == 3);
  CHECK(contact_slab_count(1.0, 0.6, false) == 1);
  CHECK(contact_slab_count(1.0, 2.0, false) == 1);
  CHECK(contact_slab_count(1.0, 0.09, false) == 6);   // 11 fit: 6 keep two threads equally busy in each phase
  CHECK(contact_slab_count(1.0, 0.01, false) == 96);  // 100 fit
  CHECK(contact_slab_count(1.0, 0.2, true) == 3);     // 4 fit: slab 3 would neighbour slab 0, both in phase 0
  CHECK(contact_slab_count(1.0, 0.4, true) == 1);     // 2 fit: slab 1 neighbours slab 0 on both sides
  CHECK(contact_slab_count(1.0, 0.25, false) == 3);   // 4 would be exactly a reach thick: a hair thicker is asked
  CHECK(contact_slab_count(0.0, 0.1, false) == 1);
  CHECK(contact_slab_count(1.0, 0.0, false) == 1);
}

TEST_CASE("the slabs hold every grain once, in slot order within a slab, and pairs within the reach are neighbours") {
  std::mt19937 random(3);
  std::uniform_real_distribution<double> along(0.0, 1.0);
  const double reach = 0.04;
  for (const bool periodic_x : {false, true}) {
    CAPTURE(periodic_x);
    PeriodicBox box;
    box.low = Vec3(0.0, 0.0, 0.0);
    box.length = Vec3(1.0, 0.3, 0.2);
    box.periodic = {periodic_x, false, false};
    std::vector<Vec3> position(2000);
    for (Vec3& p : position) p = Vec3(along(random), 0.3 * along(random), 0.2 * along(random));
    const ContactSlabs slabs = contact_slabs(position, reach, box);
    CHECK(slabs.axis == 0);  // the longest axis
    CHECK(slabs.periodic == periodic_x);
    CHECK(slabs.count() == 24);  // 24 fit in the grains' span (periodic: 25 in the box, less a hair)
    const std::vector<std::uint32_t> of = slab_of(slabs, position.size());
    std::set<std::uint32_t> seen(slabs.grains.begin(), slabs.grains.end());
    CHECK(seen.size() == position.size());
    for (std::uint32_t s = 0; s < slabs.count(); ++s)
      for (std::uint32_t n = slabs.offsets[s] + 1; n < slabs.offsets[s + 1]; ++n)
        CHECK(slabs.grains[n - 1] < slabs.grains[n]);
    for (std::size_t i = 0; i < position.size(); ++i)
      for (std::size_t j = i + 1; j < position.size(); ++j) {
        Vec3 d = position[j] - position[i];
        if (periodic_x) d.x() -= std::round(d.x() / box.length.x()) * box.length.x();
        if (d.norm() < reach && !neighbouring_slabs(slabs, of[i], of[j])) {
          CAPTURE(i);
          CAPTURE(j);
          FAIL("a pair within the reach in slabs " << of[i] << " and " << of[j]);
        }
      }
    // Across the seam: the last slab neighbours the first only along a periodic axis.
    CHECK(neighbouring_slabs(slabs, 0, slabs.count() - 1) == periodic_x);
    CHECK_FALSE(neighbouring_slabs(slabs, 3, 5));
  }
}

TEST_CASE("grains in a box under three reaches long on every axis are one slab") {
  PeriodicBox box;
  box.length = Vec3(0.1, 0.1, 0.1);
  box.periodic = {true, true, false};
  const std::vector<Vec3> position{Vec3(0.01, 0.02, 0.03), Vec3(0.09, 0.05, 0.04), Vec3(0.05, 0.05, 0.05)};
  const ContactSlabs slabs = contact_slabs(position, 0.04, box);
  CHECK(slabs.count() == 1);
  CHECK(slabs.grains == std::vector<std::uint32_t>{0, 1, 2});
}
