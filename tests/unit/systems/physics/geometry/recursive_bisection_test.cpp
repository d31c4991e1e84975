// Weighted recursive coordinate bisection: boxes that tile the domain, each point in one box, and equal shares of
// the weight, for powers of two and not, uniform and skewed weights.
#include <doctest/doctest.h>

#include <algorithm>
#include <vector>

#include "systems/physics/geometry/recursive_bisection.hpp"

using namespace riffle;

namespace {
/// Points on an nx x ny x nz lattice of spacing 1 (cell centres), the domain the lattice's box.
struct BisectionLattice {
  std::vector<Vec3> points;
  PartBox domain;
  BisectionLattice(int nx, int ny, int nz) {
    for (int z = 0; z < nz; ++z)
      for (int y = 0; y < ny; ++y)
        for (int x = 0; x < nx; ++x) points.emplace_back(x + 0.5, y + 0.5, z + 0.5);
    domain = {Vec3::Zero(), Vec3(nx, ny, nz)};
  }
};

std::vector<double> part_weights(const std::vector<PartBox>& boxes, const std::vector<Vec3>& points,
                                 const std::vector<double>& weights) {
  std::vector<double> sums(boxes.size(), 0.0);
  for (std::size_t i = 0; i < points.size(); ++i) sums[part_of(boxes, points[i])] += weights[i];
  return sums;
}

double volume(const PartBox& box) { return (box.high - box.low).prod(); }
}  // namespace

TEST_CASE("recursive bisection tiles the domain and gives every point one box") {
  const BisectionLattice lattice(24, 16, 6);
  const std::vector<double> weights(lattice.points.size(), 1.0);
  for (const int parts : {1, 2, 3, 4, 5, 7, 8, 16}) {
    CAPTURE(parts);
    const std::vector<PartBox> boxes = recursive_bisection(lattice.points, weights, lattice.domain, parts);
    REQUIRE(boxes.size() == static_cast<std::size_t>(parts));
    double total_volume = 0.0;
    for (const PartBox& box : boxes) {
      total_volume += volume(box);
      CHECK((box.low.array() >= lattice.domain.low.array()).all());
      CHECK((box.high.array() <= lattice.domain.high.array()).all());
    }
    CHECK(total_volume == doctest::Approx(volume(lattice.domain)).epsilon(1e-12));
    // Each point strictly inside exactly one box (the cuts fall between lattice planes).
    for (const Vec3& point : lattice.points) {
      int holders = 0;
      for (const PartBox& box : boxes)
        holders += (point.array() > box.low.array()).all() && (point.array() < box.high.array()).all() ? 1 : 0;
      CHECK(holders == 1);
    }
  }
}

TEST_CASE("recursive bisection shares uniform weights to within one lattice plane a cut") {
  // 2304 points. Every cut falls between lattice planes, so a part can miss its share by at most one plane of
  // points per cut above it: at 8 parts (3 cuts, planes of at most 16 x 6 = 96 points) within 3 * 96 / 2304 of the
  // mean; with a power of two along the long axis, exactly.
  const BisectionLattice lattice(24, 16, 6);
  const std::vector<double> weights(lattice.points.size(), 1.0);
  const std::vector<PartBox> four = recursive_bisection(lattice.points, weights, lattice.domain, 4);
  for (const double sum : part_weights(four, lattice.points, weights)) CHECK(sum == 576.0);
  const std::vector<PartBox> three = recursive_bisection(lattice.points, weights, lattice.domain, 3);
  for (const double sum : part_weights(three, lattice.points, weights)) CHECK(sum == 768.0);  // 8 planes of 96 each
  const std::vector<PartBox> seven = recursive_bisection(lattice.points, weights, lattice.domain, 7);
  const std::vector<double> sums = part_weights(seven, lattice.points, weights);
  const double mean = 2304.0 / 7.0;
  for (const double sum : sums) CHECK(std::abs(sum - mean) <= 3.0 * 96.0);
}

TEST_CASE("recursive bisection follows the weights, not the volume") {
  // The lower half along x (12 planes of 96 points) weighs 3 a point, the upper half 1: 4608 in all, half of it in
  // the first 8 planes (8 x 96 x 3 = 2304), so the cut sits at x = 8, not at the middle (12).
  const BisectionLattice lattice(24, 16, 6);
  std::vector<double> weights(lattice.points.size());
  for (std::size_t i = 0; i < weights.size(); ++i) weights[i] = lattice.points[i].x() < 12.0 ? 3.0 : 1.0;
  const std::vector<PartBox> boxes = recursive_bisection(lattice.points, weights, lattice.domain, 2);
  CHECK(boxes[0].high.x() == doctest::Approx(8.0));
  const std::vector<double> sums = part_weights(boxes, lattice.points, weights);
  CHECK(sums[0] == doctest::Approx(sums[1]));
  // Weightless points leave the cut in proportion to the parts.
  const std::vector<double> zero(lattice.points.size(), 0.0);
  CHECK(recursive_bisection(lattice.points, zero, lattice.domain, 2)[0].high.x() == doctest::Approx(12.0));
}

TEST_CASE("recursive bisection keeps points of equal coordinate on one side, and is the same on every call") {
  // Four columns of points with equal x; 3 parts cannot split them 4/3 : 8/3 exactly, and no column is cut.
  std::vector<Vec3> points;
  for (int x = 0; x < 4; ++x)
    for (int k = 0; k < 10; ++k) points.emplace_back(x + 0.5, 0.5, 0.1 * k + 0.05);
  const std::vector<double> weights(points.size(), 1.0);
  const PartBox domain{Vec3::Zero(), Vec3(4.0, 1.0, 1.0)};
  const std::vector<PartBox> boxes = recursive_bisection(points, weights, domain, 2);
  for (int x = 0; x < 4; ++x) {
    std::size_t first = part_of(boxes, points[static_cast<std::size_t>(10 * x)]);
    for (int k = 1; k < 10; ++k) CHECK(part_of(boxes, points[static_cast<std::size_t>(10 * x + k)]) == first);
  }
  const std::vector<PartBox> again = recursive_bisection(points, weights, domain, 2);
  for (std::size_t k = 0; k < boxes.size(); ++k) {
    CHECK(again[k].low == boxes[k].low);
    CHECK(again[k].high == boxes[k].high);
  }
  CHECK(distance_to_box(boxes[0], Vec3(5.0, 0.5, 0.5)) > 0.0);
  CHECK(distance_to_box(boxes[0], boxes[0].low + Vec3::Constant(1e-3)) == 0.0);
}
