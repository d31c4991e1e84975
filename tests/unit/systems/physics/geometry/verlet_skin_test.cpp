// When a Verlet list still holds (systems/physics/geometry/verlet_skin.hpp): the two largest moves, and the pair
// bound checked against a brute-force search of the pairs it keeps.
#include <doctest/doctest.h>

#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "systems/physics/geometry/verlet_skin.hpp"

using namespace riffle;

namespace {
using Pairs = std::set<std::pair<std::size_t, std::size_t>>;

/// Every pair (i < j) of `positions` closer than `radius`, by brute force.
Pairs pairs_within(const std::vector<Vec3>& positions, double radius) {
  Pairs pairs;
  for (std::size_t i = 0; i < positions.size(); ++i)
    for (std::size_t j = i + 1; j < positions.size(); ++j)
      if ((positions[i] - positions[j]).norm() < radius) pairs.insert({i, j});
  return pairs;
}
}  // namespace

TEST_CASE("largest_moves gives the two largest moves in the frame asked, on any thread count") {
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Vec3> built(20000), now(20000);
  std::vector<double> moves(now.size());
  const Vec3 frame_shift(0.3, -0.1, 0.2);
  for (std::size_t i = 0; i < now.size(); ++i) {
    built[i] = Vec3(unit(random), unit(random), unit(random));
    const Vec3 move = 1e-3 * Vec3(unit(random), unit(random), unit(random));
    now[i] = built[i] + frame_shift + move;
    moves[i] = move.norm();
  }
  std::sort(moves.rbegin(), moves.rend());
  for (const int threads : {1, 2}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    const LargestMoves found = largest_moves(now, built, frame_shift);
    CHECK(found.first == doctest::Approx(moves[0]).epsilon(1e-9));
    CHECK(found.second == doctest::Approx(moves[1]).epsilon(1e-9));
    // Only the first 10 slots: their own two largest.
    std::vector<double> head(10);
    for (std::size_t i = 0; i < 10; ++i) head[i] = (now[i] - built[i] - frame_shift).norm();
    std::sort(head.rbegin(), head.rend());
    const LargestMoves first_ten = largest_moves(now, built, frame_shift, 10);
    CHECK(first_ten.first == doctest::Approx(head[0]).epsilon(1e-12));
    CHECK(first_ten.second == doctest::Approx(head[1]).epsilon(1e-12));
  }
  // One slot's move equal to the largest: both entries hold it.
  std::vector<Vec3> tied = built;
  tied[3] += Vec3(0.0, 0.0, 0.5);
  tied[17] += Vec3(0.5, 0.0, 0.0);
  const LargestMoves two = largest_moves(tied, built);
  CHECK(two.first == 0.5);
  CHECK(two.second == 0.5);
  // A non-finite position counts as an infinite move: the list is never trusted.
  tied[11].x() = std::numeric_limits<double>::quiet_NaN();
  const LargestMoves broken = largest_moves(tied, built);
  CHECK(std::isinf(broken.first));
  CHECK_FALSE(skin_holds(broken, 1.0));
}

TEST_CASE("a list the pair bound keeps holds every pair, and one fast particle no longer forces a rebuild") {
  // Particles on a jittered lattice, lists at radius r + skin; then moves: most particles little, a few by up to
  // 0.9 skin. Wherever the pair bound says the list holds, every pair within r now must be in it.
  const double r = 2.1, skin = 0.3;
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Vec3> built;
  for (int x = 0; x < 9; ++x)
    for (int y = 0; y < 9; ++y)
      for (int z = 0; z < 9; ++z)
        built.push_back(Vec3(x, y, z) + 0.2 * Vec3(unit(random), unit(random), unit(random)));
  const Pairs list = pairs_within(built, r + skin);
  int held = 0, held_past_half_skin = 0;
  for (int trial = 0; trial < 120; ++trial) {
    std::vector<Vec3> now = built;
    for (Vec3& p : now) p += 0.05 * skin * Vec3(unit(random), unit(random), unit(random)).normalized();
    const int fast = 1 + trial % 3;
    for (int k = 0; k < fast; ++k) {
      const std::size_t i = std::uniform_int_distribution<std::size_t>(0, now.size() - 1)(random);
      now[i] = built[i] + (0.3 + 0.6 * (unit(random) + 1.0) / 2.0) * skin *
                              Vec3(unit(random), unit(random), unit(random)).normalized();
    }
    const LargestMoves moves = largest_moves(now, built);
    if (!skin_holds(moves, skin)) continue;
    ++held;
    if (moves.first > 0.5 * skin) ++held_past_half_skin;
    for (const auto& pair : pairs_within(now, r)) REQUIRE_MESSAGE(list.count(pair) == 1, "trial ", trial);
  }
  MESSAGE(held, " of 120 trials kept the list, ", held_past_half_skin, " of them with a particle past half the skin");
  CHECK(held >= 30);
  CHECK(held_past_half_skin >= 15);  // the lists the "half the skin each" rule would have thrown away
  CHECK_FALSE(skin_holds(LargestMoves{0.6 * skin, 0.0}, skin, /*across_ranks=*/true));
  CHECK(skin_holds(LargestMoves{0.6 * skin, 0.0}, skin));
}

TEST_CASE("two particles closing on each other by just over the skin together: the bound says rebuild") {
  const double r = 2.1, skin = 0.3;
  const std::vector<Vec3> built{Vec3::Zero(), Vec3(r + skin + 1e-6, 0.0, 0.0)};
  REQUIRE(pairs_within(built, r + skin).empty());
  for (const double share : {0.5, 0.8}) {  // the pair's closing split evenly, or mostly on one
    const double closing = skin + 1e-4;
    const std::vector<Vec3> now{Vec3(share * closing, 0.0, 0.0), built[1] - Vec3((1.0 - share) * closing, 0.0, 0.0)};
    CHECK(pairs_within(now, r).size() == 1);  // a pair the list does not hold
    CHECK_FALSE(skin_holds(largest_moves(now, built), skin));
  }
}
