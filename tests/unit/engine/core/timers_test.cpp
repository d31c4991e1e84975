#include <doctest/doctest.h>

#include <sstream>
#include <string>
#include <vector>

#include "engine/core/timers.hpp"

using namespace riffle;

namespace {
SystemTimer timer(const std::string& name, std::uint64_t calls, double seconds, std::uint64_t items = 0) {
  SystemTimer t;
  t.name = name;
  t.phase = "step";
  t.calls = calls;
  t.total_seconds = seconds;
  t.items = items;
  return t;
}

/// The whitespace-separated fields of the table's line that starts with `name`.
std::vector<std::string> row_of(const std::string& table, const std::string& name) {
  std::istringstream lines(table);
  std::string line;
  while (std::getline(lines, line))
    if (line.rfind(name + " ", 0) == 0) {
      std::istringstream words(line);
      std::vector<std::string> fields;
      for (std::string word; words >> word;) fields.push_back(word);
      return fields;
    }
  return {};
}
}  // namespace

TEST_CASE("timings over ranks: each system's mean, slowest rank and imbalance, systems no rank ran are left out") {
  // Three ranks: the pressure solve takes 1, 2 and 3 s (mean 2, slowest rank 2, imbalance 1.5); the search 1 s on
  // each; a branch no rank ran. Stepping 4, 5 and 6 s (mean 5).
  std::vector<RankTimers> ranks(3);
  for (std::size_t r = 0; r < 3; ++r) {
    ranks[r].timers = {timer("fluid_pressure", 10, 1.0 + static_cast<double>(r)), timer("fluid_neighbours", 10, 1.0),
                       timer("unused branch", 0, 0.0)};
    ranks[r].stepping_seconds = 4.0 + static_cast<double>(r);
  }
  const std::string table = format_rank_timing_table(ranks);
  const std::vector<std::string> pressure = row_of(table, "fluid_pressure");
  REQUIRE(pressure.size() == 7);
  CHECK(std::stod(pressure[2]) == doctest::Approx(2.0));  // mean
  CHECK(std::stod(pressure[3]) == doctest::Approx(3.0));  // slowest
  CHECK(pressure[4] == "2");                              // its rank
  CHECK(std::stod(pressure[5]) == doctest::Approx(1.5));  // imbalance
  CHECK(pressure[6] == "40.0%");                          // 2 s of the mean stepping 5 s
  const std::vector<std::string> search = row_of(table, "fluid_neighbours");
  REQUIRE(search.size() == 7);
  CHECK(search[4] == "0");  // all equal: the first rank
  CHECK(std::stod(search[5]) == doctest::Approx(1.0));
  CHECK(row_of(table, "unused").empty());
  CHECK(table.find("stepping (wall)") != std::string::npos);

  const std::string csv = format_rank_timing_csv(ranks);
  std::istringstream lines(csv);
  std::string line;
  std::vector<std::string> rows;
  while (std::getline(lines, line)) rows.push_back(line);
  REQUIRE(rows.size() == 1 + 3 * 3 + 3);  // header, three systems on three ranks, a stepping row per rank
  CHECK(rows[0] == "rank,system,phase,calls,total_s,items");
  CHECK(rows[4] == "1,fluid_pressure,step,10,2,0");
  CHECK(rows[12] == "2,stepping,all,,6,");
  CHECK(format_rank_timing_table({}).empty());
}
