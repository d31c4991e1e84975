#pragma once
// When a Verlet list (pairs within a radius r + skin at the build) still holds every pair within r: the grains' and
// the MPS particles' lists both ask it.
//
// A pair's distance changes by at most the sum of its two members' displacements since the build, measured in any
// frame that translates (a common shift moves both). So the list holds while the two largest displacements add up to
// no more than the skin (Allen & Tildesley, Computer Simulation of Liquids, 2nd ed., sec. 5.3.1). The usual "each
// particle within half the skin" is the same bound with the largest taken twice: it throws a list away when one fast
// particle (a splash, a grain thrown off the bed) has used its half while every other has barely moved.
#include <cstddef>
#include <vector>

#include "components/vec.hpp"

namespace riffle {

/// The two largest displacements [m] of a set of particles since a list's build (first >= second >= 0).
struct LargestMoves {
  double first = 0.0;
  double second = 0.0;
};

/// The two largest |positions[i] - built[i] - frame_shift| over the first `count` slots (all of `positions`
/// by default): `frame_shift` is how far the frame the moves are measured in moved since the build (the tank's
/// displacement, or zero in the lab). Non-finite moves count as infinite. In parallel (oneTBB); the result does not
/// depend on the thread count.
LargestMoves largest_moves(const std::vector<Vec3>& positions, const std::vector<Vec3>& built,
                           const Vec3& frame_shift = Vec3::Zero(),
                           std::size_t count = static_cast<std::size_t>(-1));

/// Whether a list built with `skin` still holds every pair within its cut radius when the particles have moved by
/// `moves`: the pair bound, first + second <= skin. Where a pair may join particles whose moves were measured
/// apart (another MPI rank's particles), only the largest is known for both members: `across_ranks` takes it twice.
inline bool skin_holds(const LargestMoves& moves, double skin, bool across_ranks = false) {
  return (across_ranks ? 2.0 * moves.first : moves.first + moves.second) <= skin;
}

}  // namespace riffle
