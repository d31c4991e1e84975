#include "engine/core/timers.hpp"

#include <algorithm>
#include <cstdio>
#include <string>

namespace riffle {

namespace {
struct Row {
  double mean_ms, share_percent, items_per_second;
};
Row derive(const SystemTimer& timer, double stepping_seconds) {
  Row row{};
  row.mean_ms = timer.calls ? 1e3 * timer.total_seconds / static_cast<double>(timer.calls) : 0.0;
  row.share_percent = stepping_seconds > 0.0 ? 100.0 * timer.total_seconds / stepping_seconds : 0.0;
  row.items_per_second = timer.total_seconds > 0.0 ? static_cast<double>(timer.items) / timer.total_seconds : 0.0;
  return row;
}
}  // namespace

std::string format_timing_table(const std::vector<SystemTimer>& timers, double stepping_seconds) {
  std::string out;
  char line[256];
  std::snprintf(line, sizeof line, "%-24s %-12s %10s %11s %11s %8s %14s\n", "system", "phase", "calls", "total [s]",
                "mean [ms]", "share", "items/s");
  out += line;
  for (const SystemTimer& timer : timers) {
    const Row row = derive(timer, stepping_seconds);
    std::snprintf(line, sizeof line, "%-24s %-12s %10llu %11.4f %11.5f %7.1f%% %14.4g\n", timer.name.c_str(),
                  timer.phase.c_str(), static_cast<unsigned long long>(timer.calls), timer.total_seconds,
                  row.mean_ms, row.share_percent, row.items_per_second);
    out += line;
  }
  std::snprintf(line, sizeof line, "%-24s %-12s %10s %11.4f   (shares can add past 100%% when systems overlap)\n",
                "stepping (wall)", "", "", stepping_seconds);
  out += line;
  return out;
}

std::string format_timing_csv(const std::vector<SystemTimer>& timers, double stepping_seconds) {
  std::string out = "system,phase,calls,total_s,mean_s,share,items,items_per_s\n";
  char line[256];
  for (const SystemTimer& timer : timers) {
    const Row row = derive(timer, stepping_seconds);
    std::snprintf(line, sizeof line, "%s,%s,%llu,%.9g,%.9g,%.6g,%llu,%.9g\n", timer.name.c_str(),
                  timer.phase.c_str(), static_cast<unsigned long long>(timer.calls), timer.total_seconds,
                  row.mean_ms * 1e-3, row.share_percent * 1e-2, static_cast<unsigned long long>(timer.items),
                  row.items_per_second);
    out += line;
  }
  std::snprintf(line, sizeof line, "stepping,all,,%.9g,,1,,\n", stepping_seconds);
  out += line;
  return out;
}

std::string format_rank_timing_table(const std::vector<RankTimers>& ranks) {
  std::string out;
  if (ranks.empty()) return out;
  char line[256];
  std::snprintf(line, sizeof line, "%-26s %-12s %11s %11s %6s %10s %8s\n", "system", "phase", "mean [s]", "slowest [s]",
                "rank", "imbalance", "share");
  out += line;
  const double count = static_cast<double>(ranks.size());
  double mean_stepping = 0.0;
  for (const RankTimers& rank : ranks) mean_stepping += rank.stepping_seconds / count;
  for (std::size_t t = 0; t < ranks[0].timers.size(); ++t) {
    double mean = 0.0, slowest = -1.0;
    std::size_t slowest_rank = 0;
    std::uint64_t calls = 0;
    for (std::size_t r = 0; r < ranks.size(); ++r) {
      const SystemTimer& timer = ranks[r].timers[t];
      mean += timer.total_seconds / count;
      calls += timer.calls;
      if (timer.total_seconds > slowest) {
        slowest = timer.total_seconds;
        slowest_rank = r;
      }
    }
    if (calls == 0) continue;  // a system no rank ran (a branch this scene does not use)
    const SystemTimer& first = ranks[0].timers[t];
    std::snprintf(line, sizeof line, "%-26s %-12s %11.4f %11.4f %6zu %10.3f %7.1f%%\n", first.name.c_str(),
                  first.phase.c_str(), mean, slowest, slowest_rank, mean > 0.0 ? slowest / mean : 1.0,
                  mean_stepping > 0.0 ? 100.0 * mean / mean_stepping : 0.0);
    out += line;
  }
  double slowest_stepping = 0.0;
  for (const RankTimers& rank : ranks) slowest_stepping = std::max(slowest_stepping, rank.stepping_seconds);
  std::snprintf(line, sizeof line, "%-26s %-12s %11.4f %11.4f   (the ranks' stepping, MPI waits included)\n",
                "stepping (wall)", "", mean_stepping, slowest_stepping);
  out += line;
  return out;
}

std::string format_rank_timing_csv(const std::vector<RankTimers>& ranks) {
  std::string out = "rank,system,phase,calls,total_s,items\n";
  char line[256];
  for (std::size_t r = 0; r < ranks.size(); ++r)
    for (const SystemTimer& timer : ranks[r].timers) {
      std::snprintf(line, sizeof line, "%zu,%s,%s,%llu,%.9g,%llu\n", r, timer.name.c_str(), timer.phase.c_str(),
                    static_cast<unsigned long long>(timer.calls), timer.total_seconds,
                    static_cast<unsigned long long>(timer.items));
      out += line;
    }
  for (std::size_t r = 0; r < ranks.size(); ++r) {
    std::snprintf(line, sizeof line, "%zu,stepping,all,,%.9g,\n", r, ranks[r].stepping_seconds);
    out += line;
  }
  return out;
}

}  // namespace riffle
