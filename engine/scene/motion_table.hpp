#pragma once
// The CSV of a tabulated tank motion ([tank.motion] kind = "table", docs/SCENES.md): a header naming the columns,
// `t` first and then one to three of `x`, `y`, `z` (each at most once, any order), then one row per time, times in
// seconds and strictly increasing, displacements in metres. Blank lines and lines starting with '#' are skipped.
// At least 4 rows (the not-a-knot spline needs them) and at most kMaxMotionRows; the file at most 64 MiB.
#include <cstddef>
#include <string>

#include "components/model.hpp"

namespace riffle {

inline constexpr std::size_t kMaxMotionRows = 1000000;
inline constexpr std::size_t kMaxMotionFileBytes = 64u * 1024u * 1024u;

/// Parses the CSV `text` (read from `file`, which names it in messages) into `table` and computes the spline's
/// curvatures. Returns "" or one problem, "<file>:<line>: <what>" (line 0 when it concerns the whole file).
std::string parse_motion_table(const std::string& text, const std::string& file, MotionTable& table);

/// Reads the file at `path` (a regular file of at most kMaxMotionFileBytes) and parses it; "" or one problem.
std::string read_motion_table(const std::string& path, MotionTable& table);

}  // namespace riffle
