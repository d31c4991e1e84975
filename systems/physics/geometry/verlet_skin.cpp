#include "systems/physics/geometry/verlet_skin.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace riffle {
namespace {
/// `moves` with the move `d` taken in.
LargestMoves with_move(LargestMoves moves, double d) {
  if (d > moves.first) return {d, moves.first};
  if (d > moves.second) moves.second = d;
  return moves;
}
}  // namespace

LargestMoves largest_moves(const std::vector<Vec3>& positions, const std::vector<Vec3>& built, const Vec3& frame_shift,
                           std::size_t count) {
  count = std::min({count, positions.size(), built.size()});
  // Squared moves while scanning (one root at the end); a NaN compares false, so it is caught apart.
  const LargestMoves squared = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, count, 4096), LargestMoves{},
      [&](const tbb::blocked_range<std::size_t>& range, LargestMoves moves) {
        for (std::size_t i = range.begin(); i < range.end(); ++i) {
          const double d2 = (positions[i] - built[i] - frame_shift).squaredNorm();
          if (d2 > moves.second || std::isnan(d2))
            moves = with_move(moves, std::isnan(d2) ? std::numeric_limits<double>::infinity() : d2);
        }
        return moves;
      },
      [](LargestMoves a, const LargestMoves& b) { return with_move(with_move(a, b.first), b.second); });
  return {std::sqrt(squared.first), std::sqrt(squared.second)};
}

}  // namespace riffle
