// Crash-safe outputs, one run per output folder, stop requests inside long steps, and the run settings that name
// where the outputs go (run.name) or how long the run is (dt against end_time). The command-line side (--until,
// --out, signals, two processes into one folder) is in tests/cli/test_cli.sh.
#include <doctest/doctest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "engine/output/checkpoint.hpp"
#include "engine/setup/initial_state.hpp"
#include "engine/output/output_lock.hpp"
#include "engine/output/output_series.hpp"
#include "engine/output/replace_file.hpp"
#include "engine/run/simulation.hpp"
#include "engine/run/stepper.hpp"
#include "engine/run/registry.hpp"
#include "tests/support/test_support.hpp"

using namespace riffle;
namespace fs = std::filesystem;

namespace {

ino_t inode_of(const fs::path& path) {
  struct stat status {};
  REQUIRE(::stat(path.c_str(), &status) == 0);
  return status.st_ino;
}

std::string contents(std::istream& in) {
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string file_text(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  return contents(file);
}

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  file << text;
}

/// Files in `directory` (and below) whose name ends in ".tmp".
int temporary_files_in(const fs::path& directory) {
  int count = 0;
  for (const auto& entry : fs::recursive_directory_iterator(directory))
    if (entry.path().extension() == ".tmp") ++count;
  return count;
}

RunOutcome run_small(const fs::path& out, double until) {
  RunOptions options;
  options.out_dir = out.string();
  options.threads = 1;
  options.until = until;
  return Simulation::from_model(test::small_model())->run(options);
}

/// The problems parse_scene reports for the small scene with `find` replaced by `replace`.
std::vector<std::string> output_problems_with(const std::string& find, const std::string& replace) {
  std::string text = test::small_scene_text();
  const std::size_t at = text.find(find);
  REQUIRE(at != std::string::npos);
  text.replace(at, find.size(), replace);
  try {
    parse_scene(text, "named.toml");
  } catch (const SceneError& error) {
    return error.problems();
  }
  return {};
}

}  // namespace

TEST_CASE("replace_file replaces a file by rename: a reader of the old file still sees all of it") {
  const fs::path dir = test::scratch_dir("replace_file");
  const fs::path path = dir / "table.csv";
  replace_file(path, "first version\n", Durability::kFlush);
  CHECK(file_text(path) == "first version\n");
  const ino_t before = inode_of(path);
  std::ifstream old_reader(path, std::ios::binary);
  replace_file(path, "second, longer version\n", Durability::kSync);
  CHECK(file_text(path) == "second, longer version\n");
  CHECK(inode_of(path) != before);  // a new file renamed over the name, never the old one truncated
  CHECK(contents(old_reader) == "first version\n");
  CHECK(temporary_files_in(dir) == 0);
}

TEST_CASE("replace_file leaves the old file whole and no temporary file when it cannot write") {
  const fs::path dir = test::scratch_dir("replace_file_fails");
  const fs::path path = dir / "kept.txt";
  replace_file(path, "kept\n", Durability::kFlush);
  fs::create_directory(dir / "blocker");  // a directory cannot be replaced by a file: the rename fails
  CHECK_THROWS_WITH_AS(replace_file(dir / "blocker", "new\n", Durability::kFlush),
                       doctest::Contains("cannot rename the temporary file"), std::runtime_error);
  CHECK(file_text(path) == "kept\n");
  CHECK(fs::is_directory(dir / "blocker"));
  CHECK(temporary_files_in(dir) == 0);
}

TEST_CASE("temporary file names are unique per process and per call, beside the target") {
  const fs::path target = "/some/dir/final.ckpt";
  const fs::path first = unique_temporary_path(target), second = unique_temporary_path(target);
  CHECK(first != second);
  CHECK(first.parent_path() == target.parent_path());
  CHECK(first.filename().string().rfind("final.ckpt." + std::to_string(::getpid()) + ".", 0) == 0);
  CHECK(first.extension() == ".tmp");
}

TEST_CASE("write_checkpoint replaces an existing checkpoint by rename") {
  const fs::path dir = test::scratch_dir("write_checkpoint");
  const fs::path path = dir / "step.ckpt";
  auto simulation = Simulation::from_model(test::small_model());
  write_checkpoint(path.string(), simulation->checkpoint_data());
  const std::string first = file_text(path);
  const ino_t before = inode_of(path);
  std::ifstream old_reader(path, std::ios::binary);
  simulation->step();
  write_checkpoint(path.string(), simulation->checkpoint_data());
  CHECK(inode_of(path) != before);
  CHECK(contents(old_reader) == first);
  CHECK(file_text(path) != first);
  CHECK(temporary_files_in(dir) == 0);
}

TEST_CASE("a finished run replaces checkpoints/final.ckpt by rename, never in place") {
  // Before the fix final.ckpt was overwritten in place (fs::copy_file): a kill during the copy left it truncated.
  const fs::path out = test::scratch_dir("final_ckpt");
  REQUIRE(run_small(out, 0.002).exit_code == kExitOk);
  const fs::path final_path = out / "checkpoints" / "final.ckpt";
  const std::string first = file_text(final_path);
  REQUIRE(first.rfind("RIFFLECP", 0) == 0);
  const ino_t before = inode_of(final_path);
  std::ifstream old_reader(final_path, std::ios::binary);
  REQUIRE(run_small(out, 0.003).exit_code == kExitOk);
  CHECK(inode_of(final_path) != before);
  CHECK(contents(old_reader) == first);  // whoever had the old final.ckpt open still reads all of it
  CHECK(file_text(final_path) == file_text(out / "checkpoints" / "step_0000000003.ckpt"));
  CHECK(temporary_files_in(out) == 0);
}

TEST_CASE("a resumed CSV series keeps its rows by rename, then appends") {
  // Before the fix the file was truncated and the kept rows rewritten in place: a kill in between lost them.
  const fs::path dir = test::scratch_dir("csv_series");
  const fs::path path = dir / "diagnostics.csv";
  write_text(path, "step,value\n1,10\n2,20\n3,30\n4,4");  // a torn last row, as a kill leaves it
  const ino_t before = inode_of(path);
  std::ifstream old_reader(path, std::ios::binary);
  {
    CsvSeries series(path, "step,value", 2.0);
    CHECK(inode_of(path) != before);
    CHECK(file_text(path) == "step,value\n1,10\n2,20\n");
    series.write_row("3,31");
  }
  CHECK(file_text(path) == "step,value\n1,10\n2,20\n3,31\n");
  CHECK(contents(old_reader) == "step,value\n1,10\n2,20\n3,30\n4,4");
  CHECK(temporary_files_in(dir) == 0);
}

TEST_CASE("a resumed CSV series with other columns goes on under them and keeps the earlier file whole") {
  // Before, a resume whose series had another header (another rank count, probe or system timer) dropped every
  // earlier row silently.
  const fs::path dir = test::scratch_dir("csv_series_columns");
  const fs::path path = dir / "diagnostics.csv";
  const std::string earlier = "step,value,wall_a_s\n1,10,0.1\n2,20,0.2\n3,30,0.3\n3,3";  // a torn last row
  write_text(path, earlier);
  {
    // wall_a_s no longer written, wall_b_s new: the rows to step 2 under the new columns, matched by name.
    CsvSeries series(path, "step,wall_b_s,value", 2.0);
    REQUIRE(series.set_aside());
    CHECK(series.rows_carried());
    CHECK(*series.set_aside() == dir / "diagnostics.before_resume.csv");
    series.write_row("3,0.5,31");
  }
  CHECK(file_text(dir / "diagnostics.before_resume.csv") == earlier);
  CHECK(file_text(path) == "step,wall_b_s,value\n1,,10\n2,,20\n3,0.5,31\n");
  // A second such resume keeps both earlier files; with another first column no row can be placed by its time.
  write_text(path, earlier);
  {
    CsvSeries series(path, "time_s,value", 2.0);
    REQUIRE(series.set_aside());
    CHECK_FALSE(series.rows_carried());
    CHECK(*series.set_aside() == dir / "diagnostics.before_resume.2.csv");
  }
  CHECK(file_text(path) == "time_s,value\n");
  CHECK(file_text(dir / "diagnostics.before_resume.csv") == earlier);
  CHECK(file_text(dir / "diagnostics.before_resume.2.csv") == earlier);
  // The same header continues in place and sets nothing aside; an empty file (killed before its header) neither.
  {
    CsvSeries series(path, "time_s,value", 2.0);
    CHECK_FALSE(series.set_aside());
  }
  write_text(path, "");
  {
    CsvSeries series(path, "step,value", 2.0);
    CHECK_FALSE(series.set_aside());
  }
  CHECK(!fs::exists(dir / "diagnostics.before_resume.3.csv"));
  CHECK(temporary_files_in(dir) == 0);
}

TEST_CASE("a resume into another folder starts its series with the rows before the checkpoint") {
  const fs::path from = test::scratch_dir("carry_from"), to = test::scratch_dir("carry_to");
  write_text(from / "diagnostics.csv", "step,value\n1,10\n2,20\n3,30\n");
  write_text(from / "class_centroids.csv", "time_s,z\n0,1\n");
  write_text(to / "class_centroids.csv", "time_s,z\n0,7\n");  // the new folder's own file is never replaced
  const std::vector<std::string> carried =
      carry_earlier_series(from, to, {"diagnostics.csv", "class_centroids.csv", "probe_absent.csv"});
  CHECK(carried == std::vector<std::string>{"diagnostics.csv"});
  CHECK(file_text(to / "class_centroids.csv") == "time_s,z\n0,7\n");
  CHECK(!fs::exists(to / "probe_absent.csv"));
  {
    // The run's writer then keeps the rows up to the checkpoint (step 2), as in a resume in place.
    CsvSeries series(to / "diagnostics.csv", "step,value", 2.0);
    series.write_row("3,31");
  }
  CHECK(file_text(to / "diagnostics.csv") == "step,value\n1,10\n2,20\n3,31\n");
  CHECK(file_text(from / "diagnostics.csv") == "step,value\n1,10\n2,20\n3,30\n");  // the source untouched
  // Into its own folder (a resume in place) or from a folder that is not there, nothing is copied.
  CHECK(carry_earlier_series(from, from, {"diagnostics.csv"}).empty());
  CHECK(carry_earlier_series(from / "missing", to, {"probe_absent.csv"}).empty());
  CHECK(temporary_files_in(to) == 0);
}

TEST_CASE("one output folder, one run: the lock refuses a second holder until the first lets go") {
  const fs::path dir = test::scratch_dir("output_lock");
  {
    OutputLock first(dir);
    const std::string holder = "another riffle run (pid " + std::to_string(::getpid()) + ")";
    CHECK_THROWS_WITH_AS(OutputLock{dir}, doctest::Contains(holder.c_str()), OutputLockError);
  }
  CHECK_NOTHROW(OutputLock{dir});  // released with its descriptor: no stale lock
}

TEST_CASE("a run into a folder another run holds is refused before it writes anything") {
  // Before the fix both runs wrote: they collided on checkpoint temporaries and interleaved diagnostics.csv rows.
  const fs::path out = test::scratch_dir("locked_run");
  OutputLock other_run(out);
  const RunOutcome outcome = run_small(out, 0.002);
  CHECK(outcome.exit_code == kExitIoError);
  CHECK(outcome.message.find("another riffle run") != std::string::npos);
  CHECK(outcome.message.find(out.string()) != std::string::npos);
  CHECK_FALSE(fs::exists(out / "diagnostics.csv"));
  CHECK_FALSE(fs::exists(out / "riffle.log"));
  CHECK_FALSE(fs::exists(out / "checkpoints"));
}

TEST_CASE("a run whose riffle.log cannot be opened exits 4 naming it, instead of aborting") {
  const fs::path out = test::scratch_dir("log_blocked");
  fs::create_directories(out / "riffle.log");  // a directory where the log file goes
  const RunOutcome outcome = run_small(out, 0.002);
  CHECK(outcome.exit_code == kExitIoError);
  CHECK(outcome.message.find((out / "riffle.log").string() + ": cannot open the log file") != std::string::npos);
}

TEST_CASE("an output directory that cannot be created exits 4 naming it") {
  const fs::path dir = test::scratch_dir("out_blocked");
  write_text(dir / "file", "a file, not a directory\n");
  const RunOutcome outcome = run_small(dir / "file" / "out", 0.002);
  CHECK(outcome.exit_code == kExitIoError);
  CHECK(outcome.message.find("cannot create the output directory '" + (dir / "file" / "out").string() + "'") !=
        std::string::npos);
}

TEST_CASE("a stop request abandons a step that goes on past the grace period, and only then") {
  const Model model = test::small_model();
  World world = initial_world(model);
  Stepper stepper(build_pipeline(model), world, model);
  stepper.compute_initial_forces();
  std::atomic<int> stop{0};

  stepper.set_stop_flag(&stop, 0.0);
  stepper.step();  // no request: the step finishes
  CHECK_FALSE(stepper.last_step_abandoned());
  CHECK(world.step == 1);
  const double time = world.time;

  stop = SIGINT;
  stepper.set_stop_flag(&stop, 1e9);  // a request, but the step finishes well within the grace period
  stepper.step();
  CHECK_FALSE(stepper.last_step_abandoned());
  CHECK(world.step == 2);

  stepper.set_stop_flag(&stop, 0.0);  // grace 0: the first sub-step that sees the request abandons the step
  const double before = world.time;
  stepper.step();
  CHECK(stepper.last_step_abandoned());
  CHECK(world.step == 2);  // neither the step nor the time advance: the world is mid-step
  CHECK(world.time == before);
  CHECK(time < before);
}

TEST_CASE("run.name must be one plain folder name") {
  struct Case {
    const char* name;
    const char* message;
  };
  const Case cases[] = {
      {"\"../../..\"", "expected a plain folder name without '/'"},
      {"\"a/b\"", "expected a plain folder name without '/'"},
      {"\"..\"", "\"..\" is not a folder name"},
      {"\".\"", "\".\" is not a folder name"},
      {"\"\"", "expected a non-empty name"},
      {"\"nul\\u0000here\"", "without control characters"},
      {"\"tab\\there\"", "without control characters"},
  };
  for (const Case& bad : cases) {
    CAPTURE(bad.name);
    const std::vector<std::string> problems = output_problems_with("name = \"small\"", std::string("name = ") + bad.name);
    REQUIRE(problems.size() == 1);
    CHECK(problems[0].rfind("named.toml:3:8: run.name: ", 0) == 0);
    CHECK(problems[0].find(bad.message) != std::string::npos);
  }
  const std::string long_name = "\"" + std::string(201, 'x') + "\"";
  const std::vector<std::string> problems = output_problems_with("name = \"small\"", "name = " + long_name);
  REQUIRE(problems.size() == 1);
  CHECK(problems[0].find("expected at most 200 bytes") != std::string::npos);
  CHECK(output_problems_with("name = \"small\"", "name = \"run 2, é_ok.v1\"").empty());
}

TEST_CASE("a dt longer than end_time is refused: the run would take no step") {
  const std::vector<std::string> problems = output_problems_with("dt = 1.0e-3", "dt = 0.06");
  REQUIRE(problems.size() == 1);
  CHECK(problems[0].rfind("named.toml:5:6: run.dt: dt = 0.06 s is longer than end_time = 0.05 s", 0) == 0);
  CHECK(output_problems_with("dt = 1.0e-3", "dt = 0.05").empty());  // one step exactly
}

TEST_CASE("the temporary files a killed run left behind are removed by the next run into the folder, nothing else") {
  CHECK(is_temporary_name(unique_temporary_path("dir/final.ckpt").filename().string()));
  CHECK(is_temporary_name("step_0000000010.ckpt.4242.7.tmp"));
  CHECK_FALSE(is_temporary_name("notes.tmp"));
  CHECK_FALSE(is_temporary_name("a.12.tmp"));
  CHECK_FALSE(is_temporary_name(".1.2.tmp"));
  CHECK_FALSE(is_temporary_name("a.1x.2.tmp"));
  CHECK_FALSE(is_temporary_name("final.ckpt.1.2.tmpx"));

  const fs::path out = test::scratch_dir("stale_temporaries");
  fs::create_directories(out / "checkpoints");
  write_text(out / "checkpoints" / "final.ckpt.999999.3.tmp", "half a checkpoint");
  write_text(out / "solids.pvd.999999.0.tmp", "half a series");
  write_text(out / "checkpoints" / "notes.tmp", "the user's");
  REQUIRE(run_small(out, 0.002).exit_code == kExitOk);
  CHECK_FALSE(fs::exists(out / "checkpoints" / "final.ckpt.999999.3.tmp"));
  CHECK_FALSE(fs::exists(out / "solids.pvd.999999.0.tmp"));
  CHECK(file_text(out / "checkpoints" / "notes.tmp") == "the user's");
}
