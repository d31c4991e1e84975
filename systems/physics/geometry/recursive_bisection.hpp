#pragma once
// Weighted recursive coordinate bisection (Berger & Bokhari 1987; the RCB of Zoltan and of LAMMPS's "balance rcb"):
// the domain cut into boxes, one per MPI rank, each holding an equal share of the work. At each level the points'
// longest spread is cut where the weights on either side are in proportion to the parts each side gets, so any number
// of parts works, not only powers of two. Boxes are what a particle code's ranks own: a particle's owner is found
// from its position alone, and a rank's ghosts are the particles within the interaction range outside its box.
// Chosen over Zoltan for the partition of a box-shaped tank: a few dozen lines, deterministic (ties broken by the
// point's index: the same partition for the same input on any machine), and no MPI needed to compute it.
#include <cstddef>
#include <span>
#include <vector>

#include "components/vec.hpp"

namespace riffle {

/// An axis-aligned box [low, high) (closed at the domain's upper faces).
struct PartBox {
  Vec3 low = Vec3::Zero();
  Vec3 high = Vec3::Zero();
};

/// `parts` boxes tiling `domain`, each holding about 1/parts of the total weight of `points` (weights[i] >= 0 for
/// points[i]; the points are expected inside the domain). Box k is part k; the parts are numbered depth first,
/// the lower side of each cut first. parts >= 1.
std::vector<PartBox> recursive_bisection(std::span<const Vec3> points, std::span<const double> weights,
                                         const PartBox& domain, int parts);

/// The part whose box holds `point` (the boxes of recursive_bisection; a point outside every box, or on the
/// domain's upper faces, goes to the nearest box).
std::size_t part_of(std::span<const PartBox> boxes, const Vec3& point);

/// The distance from `point` to `box` (0 inside).
double distance_to_box(const PartBox& box, const Vec3& point);

}  // namespace riffle
