#include "engine/output/output_series.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <stdexcept>

#include "engine/output/replace_file.hpp"

namespace riffle {

namespace fs = std::filesystem;

CsvSeries::CsvSeries(const fs::path& path, const std::string& header, std::optional<double> keep_up_to)
    : path_(path) {
  std::string kept;
  if (keep_up_to && fs::exists(path)) {
    std::ifstream existing(path);
    std::string line;
    std::getline(existing, line);
    if (line == header) {
      const auto fields = std::count(header.begin(), header.end(), ',');
      while (std::getline(existing, line)) {
        if (line.empty() || std::count(line.begin(), line.end(), ',') != fields) continue;
        double first = 0.0;
        try {
          first = std::stod(line.substr(0, line.find(',')));
        } catch (const std::exception&) {
          continue;
        }
        if (first <= *keep_up_to) kept += line + "\n";
      }
    }
  }
  // The header and the kept rows replace the old file in one rename, and the run appends after them: a kill while
  // the rows are copied leaves the old file as it was, so the next resume finds them again.
  replace_file(path, header + "\n" + kept, Durability::kFlush);
  file_.open(path, std::ios::app);
  if (!file_) throw std::runtime_error(path.string() + ": cannot open for writing");
}

void CsvSeries::write_row(const std::string& row) {
  file_ << row << "\n";
  file_.flush();
  if (!file_) throw std::runtime_error(path_.string() + ": cannot write");
}

void CsvSeries::write_rows(const std::string& rows) {
  file_ << rows;
  file_.flush();
  if (!file_) throw std::runtime_error(path_.string() + ": cannot write");
}

std::vector<std::string> carry_earlier_series(const fs::path& from_dir, const fs::path& to_dir,
                                              const std::vector<std::string>& names) {
  std::vector<std::string> carried;
  std::error_code error;
  if (from_dir.empty() || !fs::is_directory(from_dir, error) || fs::equivalent(from_dir, to_dir, error)) return carried;
  for (const std::string& name : names) {
    const fs::path source = from_dir / name, target = to_dir / name;
    if (fs::exists(target, error) || !fs::is_regular_file(source, error)) continue;
    // Through a temporary name and a rename, like every file a run writes: a kill leaves no half copy to be kept.
    std::ifstream in(source, std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!in && !in.eof()) throw std::runtime_error(source.string() + ": cannot read the series to carry");
    replace_file(target, text, Durability::kFlush);
    carried.push_back(name);
  }
  return carried;
}

IntervalSchedule::IntervalSchedule(double interval, double dt, double start_time)
    : interval_(interval), dt_(dt), next_(interval > 0.0 ? index(start_time) + 1.0 : 0.0) {}

double IntervalSchedule::index(double time) const { return std::floor((time + 0.5 * dt_) / interval_); }

bool IntervalSchedule::take(double time) {
  if (!(interval_ > 0.0)) return true;
  const double current = index(time);
  if (current < next_) return false;
  next_ = current + 1.0;
  return true;
}

bool IntervalSchedule::due(double time) const { return !(interval_ > 0.0) || index(time) >= next_; }

std::string format_exact(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

std::string format_value(double value) {
  if (std::isnan(value)) return "";
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", value);
  return text;
}

}  // namespace riffle
