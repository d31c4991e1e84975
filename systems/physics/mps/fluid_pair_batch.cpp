#include "systems/physics/mps/fluid_pair_batch.hpp"

#include <cmath>

namespace riffle {

// As in solid_contacts.cpp: the portable build also carries an AVX2 copy (4-wide divisions and square roots), picked
// at load time; AVX2 without FMA performs the same correctly rounded operations as SSE2, so both copies agree bit for
// bit. This file is compiled with -fno-math-errno (sqrt never sees a negative argument) so that sqrt vectorises.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(__AVX2__) && !defined(__FMA__)
#define RIFFLE_PAIR_KERNEL_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define RIFFLE_PAIR_KERNEL_CLONES
#endif

RIFFLE_PAIR_KERNEL_CLONES void evaluate_pair_geometry(FluidPairBatch& batch, const WendlandKernel& kernel) {
  const WendlandKernel local = kernel;  // by value: the batch stores cannot alias it
  const double effective_radius = local.effective_radius;
  const std::size_t count = batch.count;
  for (std::size_t k = 0; k < count; ++k) {
    const double distance_squared = batch.distance_squared[k];
    const double distance = std::sqrt(distance_squared);
    // WendlandKernel::weight with its clip at r_e as a select.
    const double weight = local.weight_inside(distance);
    batch.distance[k] = distance;
    batch.inverse_squared[k] = 1.0 / distance_squared;
    batch.weight[k] = distance >= effective_radius ? 0.0 : weight;
  }
}

RIFFLE_PAIR_KERNEL_CLONES void evaluate_pair_weights(FluidPairBatch& batch, const WendlandKernel& kernel) {
  const WendlandKernel local = kernel;
  const double effective_radius = local.effective_radius;
  const std::size_t count = batch.count;
  for (std::size_t k = 0; k < count; ++k) {
    const double distance = std::sqrt(batch.distance_squared[k]);
    const double weight = local.weight_inside(distance);
    batch.weight[k] = distance >= effective_radius ? 0.0 : weight;
  }
}

}  // namespace riffle
