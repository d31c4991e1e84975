#include "engine/output/output_series.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <stdexcept>

#include "engine/output/replace_file.hpp"

namespace riffle {

namespace fs = std::filesystem;

namespace {

/// `<stem>.before_resume.csv` beside `path`, or `<stem>.before_resume.<k>.csv` for the first k from 2 that is free.
fs::path set_aside_path(const fs::path& path) {
  const std::string stem = path.stem().string() + ".before_resume";
  fs::path candidate = path.parent_path() / (stem + path.extension().string());
  for (int k = 2; fs::exists(candidate); ++k)
    candidate = path.parent_path() / (stem + "." + std::to_string(k) + path.extension().string());
  return candidate;
}

/// The comma-separated fields of a line (no quoting: riffle's series hold numbers and plain names).
std::vector<std::string> split_fields(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t begin = 0;
  for (;;) {
    const std::size_t comma = line.find(',', begin);
    fields.push_back(line.substr(begin, comma - begin));
    if (comma == std::string::npos) return fields;
    begin = comma + 1;
  }
}

}  // namespace

CsvSeries::CsvSeries(const fs::path& path, const std::string& header, std::optional<double> keep_up_to)
    : path_(path) {
  std::string kept;
  if (keep_up_to && fs::exists(path)) {
    std::ifstream existing(path);
    std::string earlier_header;
    std::getline(existing, earlier_header);
    // An empty file (killed before its header was written) has nothing to keep.
    if (!earlier_header.empty()) {
      const std::vector<std::string> earlier_columns = split_fields(earlier_header);
      const std::vector<std::string> columns = split_fields(header);
      // Another header: the resumed run writes other columns (on another rank count, with another system or probe
      // setting, by another riffle). The rows are carried under this run's columns, matched by name (a column the
      // run no longer writes left out, a new one left empty), provided the first column (the time or step the rows
      // are kept by) is the same; and the earlier file is kept whole beside the new one, so nothing is lost.
      const bool same = earlier_header == header;
      std::vector<std::size_t> source(columns.size(), std::string::npos);
      for (std::size_t k = 0; k < columns.size(); ++k) {
        const auto found = std::find(earlier_columns.begin(), earlier_columns.end(), columns[k]);
        if (found != earlier_columns.end()) source[k] = static_cast<std::size_t>(found - earlier_columns.begin());
      }
      const bool carried = same || source.front() == 0;
      std::string line;
      while (carried && std::getline(existing, line)) {
        // A row with another field count than its header is a torn last line.
        if (line.empty() || static_cast<std::size_t>(std::count(line.begin(), line.end(), ',')) + 1 !=
                                earlier_columns.size())
          continue;
        double first = 0.0;
        try {
          first = std::stod(line.substr(0, line.find(',')));
        } catch (const std::exception&) {
          continue;
        }
        if (first > *keep_up_to) continue;
        if (same) {
          kept += line + "\n";
          continue;
        }
        const std::vector<std::string> fields = split_fields(line);
        for (std::size_t k = 0; k < columns.size(); ++k) {
          if (k > 0) kept += ',';
          if (source[k] != std::string::npos) kept += fields[source[k]];
        }
        kept += '\n';
      }
      if (!same) {
        existing.close();
        set_aside_ = set_aside_path(path);
        fs::copy_file(path, *set_aside_);
        rows_carried_ = carried;
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
