#include "engine/scene/motion_table.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

#include "engine/toml/scene_reader.hpp"
#include "systems/physics/math/cubic_spline.hpp"

namespace riffle {

namespace {

std::string trimmed(const std::string& text) {
  const std::size_t first = text.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  const std::size_t last = text.find_last_not_of(" \t\r");
  return text.substr(first, last - first + 1);
}

std::vector<std::string> fields_of(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    fields.push_back(trimmed(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return fields;
}

std::string quoted(const std::string& text) {
  constexpr std::size_t kShown = 40;  // a binary file's "field" could be megabytes long
  return "\"" + (text.size() > kShown ? text.substr(0, kShown) + "..." : text) + "\"";
}

}  // namespace

std::string parse_motion_table(const std::string& text, const std::string& file, MotionTable& table) {
  table = MotionTable{};
  table.file = file;
  auto at = [&](std::size_t line, const std::string& what) {
    return file + ":" + std::to_string(line) + ": " + what;
  };
  std::istringstream stream(text);
  std::string line;
  std::size_t line_number = 0;
  std::vector<int> axis_of_column;  // column k >= 1 holds axis axis_of_column[k - 1]
  bool header_read = false;
  while (std::getline(stream, line)) {
    ++line_number;
    // A spreadsheet's UTF-8 byte-order mark before the header is not part of it.
    if (line_number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
    const std::string content = trimmed(line);
    if (content.empty() || content[0] == '#') continue;
    const std::vector<std::string> fields = fields_of(content);
    if (!header_read) {
      if (fields[0] != "t")
        return at(line_number, "expected the header \"t,x\" (or t and any of x, y, z), got " + quoted(content));
      if (fields.size() < 2) return at(line_number, "the header names no displacement column (x, y or z)");
      if (fields.size() > 4) return at(line_number, "the header has more than 4 columns (t and x, y, z)");
      for (std::size_t k = 1; k < fields.size(); ++k) {
        const std::string& name = fields[k];
        const int axis = name == "x" ? 0 : name == "y" ? 1 : name == "z" ? 2 : -1;
        if (axis < 0)
          return at(line_number, "column " + std::to_string(k + 1) + " of the header is " + quoted(name) +
                                     "; expected x, y or z");
        for (int seen : axis_of_column)
          if (seen == axis) return at(line_number, "the header names " + name + " twice");
        axis_of_column.push_back(axis);
      }
      header_read = true;
      continue;
    }
    if (fields.size() != axis_of_column.size() + 1)
      return at(line_number, "expected " + std::to_string(axis_of_column.size() + 1) + " comma-separated numbers "
                             "as in the header, got " + std::to_string(fields.size()) + " fields");
    if (table.time.size() >= kMaxMotionRows)
      return at(line_number, "more than " + std::to_string(kMaxMotionRows) + " rows; a motion table may have at most "
                             "that many");
    double values[4] = {0.0, 0.0, 0.0, 0.0};
    for (std::size_t k = 0; k < fields.size(); ++k) {
      const std::string& field = fields[k];
      char* end = nullptr;
      errno = 0;
      const double value = field.empty() ? 0.0 : std::strtod(field.c_str(), &end);
      const std::string column = k == 0 ? "t" : std::string(1, "xyz"[axis_of_column[k - 1]]);
      if (field.empty() || end != field.c_str() + field.size())
        return at(line_number, "column " + column + ": expected a number, got " + quoted(field));
      if (!std::isfinite(value))
        return at(line_number, "column " + column + ": expected a finite number, got " + quoted(field));
      values[k] = value;
    }
    if (!table.time.empty() && !(values[0] > table.time.back()))
      return at(line_number, "the times must increase strictly: t = " + format_number(values[0]) +
                             " s follows t = " + format_number(table.time.back()) + " s");
    table.time.push_back(values[0]);
    for (std::size_t k = 1; k < fields.size(); ++k)
      table.displacement[static_cast<std::size_t>(axis_of_column[k - 1])].push_back(values[k]);
  }
  if (!header_read) return at(0, "no header line \"t,x\" (or t and any of x, y, z) and no rows");
  if (table.time.size() < 4)
    return at(0, "has " + std::to_string(table.time.size()) + " rows; a motion table needs at least 4 (the "
                 "not-a-knot cubic spline)");
  // Spacing far below the times' rounding would make the spline's divisions meaningless.
  for (std::size_t i = 1; i < table.time.size(); ++i)
    if (table.time[i] - table.time[i - 1] <
        1e-12 * std::max({1.0, std::abs(table.time[i]), std::abs(table.time[i - 1])}))
      return at(0, "rows " + std::to_string(i) + " and " + std::to_string(i + 1) + " are closer in time than 1e-12 s");
  for (std::size_t a = 0; a < 3; ++a)
    if (!table.displacement[a].empty())
      table.curvature[a] = not_a_knot_curvatures(table.time, table.displacement[a]);
  for (std::size_t a = 0; a < 3; ++a)
    for (double curvature : table.curvature[a])
      if (!std::isfinite(curvature))
        return at(0, "the spline through the table overflows (displacements or time steps too extreme)");
  return "";
}

std::string read_motion_table(const std::string& path, MotionTable& table) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) return path + ": cannot open the motion table (does it exist?)";
  if (S_ISDIR(info.st_mode)) return path + ": is a directory, not a motion table";
  if (!S_ISREG(info.st_mode)) return path + ": is not a regular file (a FIFO, device or socket)";
  if (static_cast<std::uint64_t>(info.st_size) > kMaxMotionFileBytes)
    return path + ": the motion table is " + std::to_string(info.st_size) + " bytes, more than the 64 MiB allowed";
  std::ifstream file(path, std::ios::binary);
  if (!file) return path + ": cannot open the motion table";
  std::string text;
  char chunk[1 << 16];
  while (file && text.size() <= kMaxMotionFileBytes) {
    file.read(chunk, sizeof chunk);
    text.append(chunk, static_cast<std::size_t>(file.gcount()));
  }
  if (file.bad()) return path + ": error while reading the motion table";
  if (text.size() > kMaxMotionFileBytes) return path + ": the motion table grew past 64 MiB while it was read";
  return parse_motion_table(text, path, table);
}

}  // namespace riffle
