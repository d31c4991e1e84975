#pragma once
// Wall-clock accounting per system. Each scheduler node owns one SystemTimer and is the only writer of it.
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace riffle {

struct SystemTimer {
  std::string name;           ///< system name
  std::string phase;          ///< "step", "substep", "end_of_step"
  std::uint64_t calls = 0;
  double total_seconds = 0.0;
  double last_seconds = 0.0;  ///< the latest call, for the per-step diagnostics row
  std::uint64_t items = 0;    ///< entities processed, summed over calls

  void add(double seconds, std::uint64_t processed) {
    ++calls;
    total_seconds += seconds;
    last_seconds = seconds;
    items += processed;
  }
};

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// Formats the timing table (calls, total and mean time, share of the stepping time, items per second).
std::string format_timing_table(const std::vector<SystemTimer>& timers, double stepping_seconds);
/// The same table as CSV with a header row.
std::string format_timing_csv(const std::vector<SystemTimer>& timers, double stepping_seconds);

}  // namespace riffle
