// The contact pass's slabs: every grain once, slab order by position, each slab at least a reach thick, a multiple
// of three along a periodic axis, and every pair within the reach in the same or a neighbouring slab.
#include <doctest/doctest.h>

#include <algorithm>
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

TEST_CASE("the slabs' schedule orders every two tasks that write common grains, lower phase first, and zeroes once") {
  for (std::uint32_t slabs = 1; slabs <= 14; ++slabs)
    for (const bool periodic : {false, true}) {
      if (periodic && slabs % 3 != 0 && slabs != 1) continue;  // contact_slab_count gives no other periodic count
      CAPTURE(slabs);
      CAPTURE(periodic);
      const ContactSlabSchedule schedule = contact_slab_schedule(slabs, periodic);
      const auto distance = [&](std::uint32_t a, std::uint32_t b) {
        const std::uint32_t d = a > b ? a - b : b - a;
        return periodic ? std::min(d, slabs - d) : d;
      };
      const auto ordered = [&](std::uint32_t a, std::uint32_t b) {  // a runs before b
        return std::find(schedule.after[a].begin(), schedule.after[a].end(), b) != schedule.after[a].end();
      };
      std::vector<std::uint32_t> waits(slabs, 0), zeroed(slabs, 0);
      for (std::uint32_t a = 0; a < slabs; ++a) {
        for (const std::uint32_t b : schedule.after[a]) {
          CHECK(a % 3 < b % 3);  // lower phase first: no cycle
          ++waits[b];
        }
        for (const std::uint32_t s : schedule.zeroes[a]) ++zeroed[s];
        // Tasks two slabs apart or closer write common grains (task s writes slabs s - 1 to s + 1): one waits for the
        // other.
        for (std::uint32_t b = a + 1; b < slabs; ++b)
          if (distance(a, b) <= 2) CHECK(ordered(a, b) != ordered(b, a));
      }
      CHECK(waits == schedule.waits_for);
      for (std::uint32_t s = 0; s < slabs; ++s) {
        CHECK(zeroed[s] == 1);
        // The task that zeroes slab s runs before every other task writing it.
        std::uint32_t zeroer = 0;
        for (std::uint32_t a = 0; a < slabs; ++a)
          if (std::find(schedule.zeroes[a].begin(), schedule.zeroes[a].end(), s) != schedule.zeroes[a].end()) zeroer = a;
        CHECK(distance(zeroer, s) <= 1);
        for (std::uint32_t writer = 0; writer < slabs; ++writer)
          if (writer != zeroer && distance(writer, s) <= 1) CHECK(ordered(zeroer, writer));
      }
    }
}
