#pragma once
// Random numbers that are a pure function of where they are used: a draw is named by (seed, counter, entity), so a
// run gives the same numbers on any thread count, in any order of the loop, and after a resume, with no generator
// state to carry in a checkpoint. The bits come from SplitMix64's mixing function (Steele, Lea & Flood 2014, "Fast
// splittable pseudorandom number generators", OOPSLA; the finaliser of Java's SplittableRandom), chained over the
// three names; normals from the Box-Muller transform.
#include <cstdint>

#include "components/vec.hpp"

namespace riffle {

/// SplitMix64's finaliser: a bijection of 64-bit words whose output bits each depend on every input bit.
std::uint64_t splitmix64(std::uint64_t word);

/// A uniform number in (0, 1) (53 random bits, never 0 or 1) named by (seed, counter, entity, lane).
double counter_uniform(std::uint64_t seed, std::uint64_t counter, std::uint64_t entity, std::uint32_t lane);

/// Three independent standard normal numbers named by (seed, counter, entity).
Vec3 counter_normals(std::uint64_t seed, std::uint64_t counter, std::uint64_t entity);

}  // namespace riffle
