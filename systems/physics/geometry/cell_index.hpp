#pragma once
// The one clamp every grid's cell lookup and size goes through.
#include <algorithm>

namespace riffle {

/// `value` (a cell coordinate, already floored) clamped to [0, top] in floating point, before any conversion to an
/// integer: a grain or particle thrown far out (1e300 m) or a NaN has no integer cell, and std::clamp passes NaN
/// through. NaN lands in cell 0.
inline double clamp_to_cells(double value, double top) { return value >= 0.0 ? std::min(value, top) : 0.0; }

}  // namespace riffle
