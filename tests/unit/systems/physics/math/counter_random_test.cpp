// Counter-based random numbers (systems/physics/math/counter_random.hpp): a draw depends on its name alone, and the
// normals have the standard normal's moments within their sampling error.
#include <doctest/doctest.h>

#include <cmath>
#include <algorithm>
#include <cstdint>

#include "systems/physics/math/counter_random.hpp"

using namespace riffle;

TEST_CASE("counter random: a draw is named by (seed, counter, entity) and by nothing else") {
  CHECK(counter_normals(7, 3, 11) == counter_normals(7, 3, 11));
  CHECK(counter_normals(7, 3, 11) != counter_normals(7, 3, 12));
  CHECK(counter_normals(7, 3, 11) != counter_normals(7, 4, 11));
  CHECK(counter_normals(7, 3, 11) != counter_normals(8, 3, 11));
  CHECK(counter_normals(7, 3, 11) != counter_normals(7, 11, 3));  // the names do not commute
  CHECK(splitmix64(0) != 0);
}

TEST_CASE("counter random: uniforms lie strictly inside (0, 1) and normals have mean 0, variance 1, no correlation") {
  constexpr int kDraws = 200000;
  double sum[3] = {0, 0, 0}, square[3] = {0, 0, 0}, cross[3] = {0, 0, 0}, fourth = 0.0;
  double smallest = 1.0, largest = 0.0;
  for (int i = 0; i < kDraws; ++i) {
    const double u = counter_uniform(1, static_cast<std::uint64_t>(i), 5, 0);
    smallest = std::min(smallest, u);
    largest = std::max(largest, u);
    const Vec3 n = counter_normals(1, static_cast<std::uint64_t>(i / 100), static_cast<std::uint64_t>(i % 100));
    for (int k = 0; k < 3; ++k) {
      sum[k] += n[k];
      square[k] += n[k] * n[k];
      cross[k] += n[k] * n[(k + 1) % 3];
    }
    fourth += n.x() * n.x() * n.x() * n.x();
  }
  CHECK(smallest > 0.0);
  CHECK(largest < 1.0);
  // Four standard errors: sigma/sqrt(N) for a mean, sqrt(2/N) for a variance, 1/sqrt(N) for a correlation.
  const double n = kDraws;
  for (int k = 0; k < 3; ++k) {
    CAPTURE(k);
    CHECK(std::abs(sum[k] / n) < 4.0 / std::sqrt(n));
    CHECK(std::abs(square[k] / n - 1.0) < 4.0 * std::sqrt(2.0 / n));
    CHECK(std::abs(cross[k] / n) < 4.0 / std::sqrt(n));
  }
  CHECK(std::abs(fourth / n - 3.0) < 4.0 * std::sqrt(96.0 / n));  // the normal's kurtosis 3 (variance of x^4: 96)
}
