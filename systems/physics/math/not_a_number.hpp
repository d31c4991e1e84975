#pragma once
// NaN as a measure's "nothing to measure" (no grains in a window, no water over a probe): written as nan to the CSVs,
// so a plot leaves a gap where a zero would read as a measured value.

#include <limits>

namespace riffle {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace riffle
