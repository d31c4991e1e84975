#include "systems/physics/math/counter_random.hpp"

#include <cmath>

namespace riffle {

namespace {
constexpr double kTwoPi = 6.28318530717958647692;
constexpr std::uint64_t kGoldenGamma = 0x9e3779b97f4a7c15ULL;  // SplitMix64's increment
}  // namespace

std::uint64_t splitmix64(std::uint64_t word) {
  word += kGoldenGamma;
  word = (word ^ (word >> 30)) * 0xbf58476d1ce4e5b9ULL;
  word = (word ^ (word >> 27)) * 0x94d049bb133111ebULL;
  return word ^ (word >> 31);
}

double counter_uniform(std::uint64_t seed, std::uint64_t counter, std::uint64_t entity, std::uint32_t lane) {
  // Each name is mixed in before the next, so that (a, b) and (b, a) draw different numbers.
  std::uint64_t word = splitmix64(seed);
  word = splitmix64(word ^ counter);
  word = splitmix64(word ^ entity);
  word = splitmix64(word ^ lane);
  return (static_cast<double>(word >> 11) + 0.5) * 0x1.0p-53;  // the centre of one of 2^53 bins: in (0, 1)
}

Vec3 counter_normals(std::uint64_t seed, std::uint64_t counter, std::uint64_t entity) {
  const auto pair = [&](std::uint32_t lane) {
    const double radius = std::sqrt(-2.0 * std::log(counter_uniform(seed, counter, entity, lane)));
    const double angle = kTwoPi * counter_uniform(seed, counter, entity, lane + 1);
    return Vec3(radius * std::cos(angle), radius * std::sin(angle), 0.0);
  };
  const Vec3 first = pair(0), second = pair(2);
  return Vec3(first.x(), first.y(), second.x());
}

}  // namespace riffle
