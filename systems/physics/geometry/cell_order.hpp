#pragma once
// Slot orders that put particles of the same grid cell next to each other in memory (grains and MPS particles):
// pair loops then gather neighbours from a few cache lines instead of the whole array.
#include <cstddef>
#include <vector>

#include "components/vec.hpp"

namespace riffle {

/// Order of the first `count` entries of `positions` sorted by the linear index (z, y, x) of their cell in a grid of
/// `cell_size` anchored at `origin` (cells below the origin clamp to 0); ties keep the current order, so the result
/// is a pure function of the positions. Entry k of the result is the old slot that goes to slot k.
std::vector<std::size_t> cell_order(const std::vector<Vec3>& positions, std::size_t count, const Vec3& origin,
                                    double cell_size);

}  // namespace riffle
