#pragma once
// Batched pair geometry for the MPS pair loops. A pair loop copies the offsets of up to kPairBatch neighbours into
// structure-of-arrays scratch, evaluates their distance, 1/r^2 and kernel weight in one straight-line pass that the
// compiler vectorises (the divisions and square roots are what a scalar pair loop waits for), then accumulates in
// list order as before. Every value is the same correctly rounded operation as in WendlandKernel, in the same order,
// so the batched loops give bit-identical results to the scalar ones, with or without the AVX2 copy.
#include <cstddef>
#include <cstdint>

#include "components/vec.hpp"
#include "systems/physics/mps/mps_common.hpp"
#include "systems/physics/mps/mps_kernel.hpp"

namespace riffle {

inline constexpr std::size_t kPairBatch = 64;

struct FluidPairBatch {
  Vec3 offset(std::size_t k) const { return Vec3(dx[k], dy[k], dz[k]); }

  std::size_t count = 0;  ///< pairs in use, <= kPairBatch
  alignas(64) double dx[kPairBatch], dy[kPairBatch], dz[kPairBatch];  ///< [m] r_j - r_i
  alignas(64) double distance_squared[kPairBatch];                     ///< [m^2]
  alignas(64) double distance[kPairBatch];                             ///< [m]
  alignas(64) double inverse_squared[kPairBatch];                      ///< [1/m^2] 1 / r^2 (inf at r = 0)
  alignas(64) double weight[kPairBatch];                               ///< [1] w(r), 0 at r >= r_e
  std::uint32_t slot[kPairBatch];                                      ///< the neighbour's slot
};

/// Fills distance, inverse_squared and weight of pairs [0, batch.count) from distance_squared.
void evaluate_pair_geometry(FluidPairBatch& batch, const WendlandKernel& kernel);
/// Fills only the weight (the same values as evaluate_pair_geometry's): for the loops that need nothing else (the
/// grains' sampling), without the division for 1/r^2.
void evaluate_pair_weights(FluidPairBatch& batch, const WendlandKernel& kernel);

/// Walks `list` a batch at a time (`batch` is the caller's scratch: declared beside the loop that uses it, it keeps
/// the measured speed of the prediction; inside this function it cost 30 %): fills the batch's offsets, evaluates its geometry and calls pair(batch, k) on its
/// pairs in list order. With kCut, only the neighbours with |offset_of(j)|^2 < radius_squared enter the batch.
template <bool kCut, class OffsetOf, class Pair>
void for_each_batched_pair(NeighbourRange list, double radius_squared, const WendlandKernel& kernel,
                           FluidPairBatch& batch, OffsetOf&& offset_of, Pair&& pair) {
  batch.count = 0;
  const auto flush = [&] {
    evaluate_pair_geometry(batch, kernel);
    for (std::size_t k = 0; k < batch.count; ++k) pair(static_cast<const FluidPairBatch&>(batch), k);
    batch.count = 0;
  };
  for (const std::uint32_t j : list) {
    const Vec3 offset = offset_of(j);
    const std::size_t k = batch.count;
    batch.slot[k] = j;
    batch.dx[k] = offset[0];
    batch.dy[k] = offset[1];
    batch.dz[k] = offset[2];
    batch.distance_squared[k] = offset.squaredNorm();
    // The cut writes every entry and keeps it by advancing the end: whether a full-list entry lies within r_e is
    // random to a branch predictor. Without the cut the end does not wait for the distance.
    if constexpr (kCut)
      batch.count += batch.distance_squared[k] < radius_squared ? 1 : 0;
    else
      ++batch.count;
    if (batch.count == kPairBatch) flush();
  }
  if (batch.count > 0) flush();
}

/// Calls pair(batch, k) for every neighbour j in `list` with |offset_of(j)|^2 < radius_squared, in list order, with
/// the batch's geometry of that pair evaluated: the scalar loop it replaces, with the divisions, square roots and
/// kernels done a batch at a time. For the full (skin) lists.
template <class OffsetOf, class Pair>
void for_each_pair_within(NeighbourRange list, double radius_squared, const WendlandKernel& kernel,
                          FluidPairBatch& batch, OffsetOf&& offset_of, Pair&& pair) {
  for_each_batched_pair<true>(list, radius_squared, kernel, batch, offset_of, pair);
}

/// The same for a near list (near_neighbours_of: already cut at r_e at the positions offset_of reads), every entry.
template <class OffsetOf, class Pair>
void for_each_near_pair(NeighbourRange near, const WendlandKernel& kernel, FluidPairBatch& batch, OffsetOf&& offset_of,
                        Pair&& pair) {
  for_each_batched_pair<false>(near, 0.0, kernel, batch, offset_of, pair);
}

}  // namespace riffle
