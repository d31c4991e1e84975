#pragma once
// The ranks' boxes, shared by the grains' and the water's decompositions (grain_ranks, fluid_ranks): a box per rank
// from a weighted recursive bisection (systems/physics/geometry/recursive_bisection.hpp), the work each box holds
// over all the ranks, and the boxes cut anew when that work is out of balance. A halo keeps its boxes as two corner
// lists (components/halo.hpp: box_low, box_high), rank by rank.
#include <span>
#include <vector>

#include "components/vec.hpp"
#include "systems/physics/geometry/recursive_bisection.hpp"

namespace riffle {

/// The ranks' boxes, in rank order, from their corners.
std::vector<PartBox> rank_boxes(const std::vector<Vec3>& low, const std::vector<Vec3>& high);

/// Stores `boxes` as corner lists (replacing what they held).
void store_rank_boxes(const std::vector<PartBox>& boxes, std::vector<Vec3>& low, std::vector<Vec3>& high);

/// The `weights` (one per point of this rank) each of `boxes` holds, summed over every rank's points in rank order:
/// the same on every rank. Collective.
std::vector<double> weight_per_box(std::span<const Vec3> positions, std::span<const double> weights,
                                   std::span<const PartBox> boxes);

/// Whether the boxes' work (`per_box`, weight_per_box) is out of balance: the largest box's above `above` times the
/// mean, and the mean by two points' worth (so that a few points over few ranks do not cut at every call).
bool boxes_out_of_balance(const std::vector<double>& per_box, double above);

/// The `parts` boxes of the recursive bisection of every rank's points and weights over `domain`, the points gathered
/// on every rank in rank order: the same boxes everywhere, without a choice left to any rank (a bisection of
/// distributed points would replace the gather past about 10^7 points). Collective.
std::vector<PartBox> bisect_over_ranks(std::span<const Vec3> positions, std::span<const double> weights,
                                       const PartBox& domain, int parts);

}  // namespace riffle
