#include <doctest/doctest.h>

#include <vector>

#include "systems/physics/ranks/rank_boxes.hpp"

using namespace riffle;

TEST_CASE("rank boxes: out of balance only past the ratio and by two points' worth") {
  // Two boxes: 11 and 9 points, mean 10: 11 / 10 = 1.1 is not above 1.1.
  CHECK_FALSE(boxes_out_of_balance({11.0, 9.0}, 1.1));
  CHECK(boxes_out_of_balance({12.0, 8.0}, 1.1));
  // Three points over two boxes: 2 / 1.5 = 1.33 passes the ratio, but the largest is not two points past the mean.
  CHECK_FALSE(boxes_out_of_balance({2.0, 1.0}, 1.1));
  CHECK(boxes_out_of_balance({4.0, 0.0}, 1.1));
  CHECK_FALSE(boxes_out_of_balance({0.0, 0.0}, 1.1));
  CHECK_FALSE(boxes_out_of_balance({}, 1.1));
}

TEST_CASE("rank boxes: corners stored and read back, weights summed per box, the bisection halves the work") {
  const std::vector<PartBox> two = {{Vec3(0, 0, 0), Vec3(0.5, 1, 1)}, {Vec3(0.5, 0, 0), Vec3(1, 1, 1)}};
  std::vector<Vec3> low{Vec3(9, 9, 9)}, high;
  store_rank_boxes(two, low, high);
  REQUIRE(low.size() == 2);
  const std::vector<PartBox> back = rank_boxes(low, high);
  CHECK(back[1].low.x() == 0.5);
  CHECK(back[0].high.x() == 0.5);
  // Ten points along x at 0.05, 0.15, ..., 0.95; the last four weigh 3: 6 + 4 * 3 = 18 in all.
  std::vector<Vec3> points;
  std::vector<double> weights;
  for (int i = 0; i < 10; ++i) {
    points.emplace_back(0.05 + 0.1 * i, 0.5, 0.5);
    weights.push_back(i >= 6 ? 3.0 : 1.0);
  }
  const std::vector<double> per_box = weight_per_box(points, weights, back);
  CHECK(per_box[0] == doctest::Approx(5.0));
  CHECK(per_box[1] == doctest::Approx(13.0));
  CHECK(boxes_out_of_balance(per_box, 1.1));
  // One rank: the bisection of its own points, cut where each side holds half the weight (9 and 9).
  const std::vector<PartBox> cut = bisect_over_ranks(points, weights, PartBox{Vec3(0, 0, 0), Vec3(1, 1, 1)}, 2);
  REQUIRE(cut.size() == 2);
  const std::vector<double> balanced = weight_per_box(points, weights, cut);
  CHECK(balanced[0] == doctest::Approx(9.0));
  CHECK(balanced[1] == doctest::Approx(9.0));
  CHECK_FALSE(boxes_out_of_balance(balanced, 1.1));
}
