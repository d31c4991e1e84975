#include "engine/output/output_series.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
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
