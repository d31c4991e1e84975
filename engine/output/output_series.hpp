#pragma once
// Building blocks of the CSV outputs written while a run goes (diagnostics.csv, probes, bed_profile.csv): a file
// of rows that is continued, not repeated, when a run resumes from a checkpoint, and a schedule of rows every so
// many seconds that depends only on the simulated time, so a resumed run writes exactly the rows the
// uninterrupted run would have written.
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

namespace riffle {

/// A CSV file written row by row. Every write_row() is flushed, so a crash loses at most the row being written.
class CsvSeries {
 public:
  /// Replaces `path` with `header` (without the newline) and opens it for appending. With `keep_up_to` set (a
  /// resumed run), the rows of the existing file whose first column is <= *keep_up_to are kept, provided its
  /// header equals `header`; rows with another field count than their header (a torn last line) are dropped. An
  /// existing file with another header (the resumed run writes other columns) is first copied whole to
  /// `<stem>.before_resume.csv` (set_aside() names it); its rows are then kept under `header`'s columns, matched by
  /// name (a column not in `header` left out, one new in it left empty), if its first column is `header`'s first
  /// (rows_carried()), else none. The replacement is a rename of a temporary file (engine/output/replace_file.hpp):
  /// a kill never loses the kept rows.
  /// Throws std::runtime_error if the file cannot be written, std::filesystem::filesystem_error if it cannot be set aside.
  CsvSeries(const std::filesystem::path& path, const std::string& header, std::optional<double> keep_up_to);

  /// Appends one row (without the newline) and flushes.
  void write_row(const std::string& row);
  /// Appends several rows (each ending in a newline) and flushes once.
  void write_rows(const std::string& rows);
  const std::filesystem::path& path() const { return path_; }
  /// Where an earlier file with another header was copied at the resume, if one was.
  const std::optional<std::filesystem::path>& set_aside() const { return set_aside_; }
  /// With set_aside(): whether that file's rows up to the resume were kept here under this series' columns.
  bool rows_carried() const { return rows_carried_; }

 private:
  std::filesystem::path path_;
  std::optional<std::filesystem::path> set_aside_;
  bool rows_carried_ = false;
  std::ofstream file_;
};

/// A run resumed into another folder than its checkpoint's starts its series there with the rows before the
/// checkpoint: each of `names` that `to_dir` lacks and `from_dir` (the checkpoint's run folder) holds is copied
/// across, and the CsvSeries the run opens on it then keeps the rows up to the checkpoint, as in a resume in place.
/// So a folder a run resumed into holds the whole run's series (S and the centroids from t = 0, not from the
/// resume). A file already in `to_dir` is left as it is. Returns the names copied; throws std::runtime_error if a
/// copy fails.
std::vector<std::string> carry_earlier_series(const std::filesystem::path& from_dir, const std::filesystem::path& to_dir,
                                              const std::vector<std::string>& names);

/// The rows `interval` seconds apart: one on the first output of a fresh run (t = 0), then one after every step
/// whose end time reaches the next multiple of the interval (within half a step), at most one per step; interval 0
/// means every step. The state is a function of the time of the last step only, so the schedule of a run resumed
/// at time t continues exactly like the uninterrupted run's.
class IntervalSchedule {
 public:
  /// `start_time`: the world's time when the run (or resumed run) starts.
  IntervalSchedule(double interval, double dt, double start_time);
  /// True if a row is due at `time` (the end of the step just taken); marks it done.
  bool take(double time);
  /// True if take(time) would be (nothing marked).
  bool due(double time) const;

 private:
  double index(double time) const;  ///< floor((time + dt/2) / interval): an integer, held exactly in a double

  double interval_;
  double dt_;
  double next_;
};

/// "%.17g": enough digits to read back as the same double (times in a first column must compare exactly on
/// resume).
std::string format_exact(double value);
/// Appends ",field" to a CSV row.
inline void append_field(std::string& row, const std::string& field) {
  row += ',';
  row += field;
}
/// "%.9g", or an empty field for a NaN (an undefined value, e.g. a mean over nothing).
std::string format_value(double value);

}  // namespace riffle
