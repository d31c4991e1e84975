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

/// One MPI rank's timers (every rank lists the same systems in the same order) and its stepping time.
struct RankTimers {
  std::vector<SystemTimer> timers;
  double stepping_seconds = 0.0;
};

/// The per-system table of a run over ranks: for each system run by any rank, its time on the average rank, on the
/// slowest rank (and which), the imbalance (slowest over mean: the time the others wait for that rank at the next
/// exchange, if nothing overlaps it) and the mean's share of the mean stepping time. Rows as `ranks[0]` lists them.
std::string format_rank_timing_table(const std::vector<RankTimers>& ranks);
/// Every rank's rows as CSV (rank,system,phase,calls,total_s,items) with a header row, then a stepping row per rank.
std::string format_rank_timing_csv(const std::vector<RankTimers>& ranks);

}  // namespace riffle
