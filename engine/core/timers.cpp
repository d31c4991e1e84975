#include "engine/core/timers.hpp"

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

}  // namespace riffle
