// Probes ([[output.probes]], engine/probes.*): scene reading and its errors (file:line:column: key), the id -> slot
// map across reorderings, wall reaction forces, and end to end: a run writes the probe, bed-profile and centroid
// files with the expected rows, and a resumed run drops the rows after its checkpoint and continues the same series.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "systems/physics/measures/bed_statistics.hpp"
#include "engine/output/probes.hpp"
#include "engine/scene/output_scene.hpp"
#include "engine/scene/scene.hpp"
#include "engine/run/simulation.hpp"
#include "tests/support/test_support.hpp"
#include "tests/support/scene_builder.hpp"

using namespace riffle;
using riffle::test::SceneBuilder, riffle::test::TomlValue;
namespace fs = std::filesystem;

namespace {

/// 81 grains with contacts in a shaken open-top box: 9 large grains (class 1, ids 0-8) on the floor and 72 small
/// ones (class 0, ids 9-80) falling onto them. `output` is appended as the [output] table's body.
std::string contact_scene(const std::string& output) {
  return SceneBuilder().run({.name = "probes", .end_time = 0.04, .dt = 1.0e-3})
      .material("grain", {.density = 2500.0, .young_modulus = 1.0e7, .poisson_ratio = 0.3})
      .tank({.size = {0.04, 0.04, 0.06}, .open_faces = {"z_max"}, .wall_material = "grain"})
      .tank_motion({.amplitude = 0.005, .frequency = 2.0}).contact({.restitution = 0.5, .friction = 0.4})
      .block({.min = {0.005, 0.005, 0.005}, .max = {0.035, 0.035, 0.015}, .spacing = 0.0101, .radius = 0.005,
              .material = "grain"})
      .set("size_class", 1)
      .block({.min = {0.005, 0.005, 0.02}, .max = {0.035, 0.035, 0.03}, .spacing = 0.0051, .radius = 0.0025,
              .material = "grain"})
      .output().toml() + output;
}

std::vector<std::string> probe_problems(const std::string& text) { return test::problems_of(text, "probes.toml"); }


std::string first_field(const std::string& line) { return line.substr(0, line.find(',')); }


}  // namespace

TEST_CASE("[[output.probes]] are read with their defaults") {
  const Model model = parse_scene(contact_scene(SceneBuilder(SceneBuilder::kSpaced)
      .probe("grains").set("ids", std::vector<int>{0, 5, 17}).set("interval", 0.01)
      .probe("wall_forces").set("name", "walls")
      .probe("grains").set("name", "top").set("file", "top_grain.csv").set("ids", std::vector<int>{80}).toml()),
                                  "probes.toml");
  REQUIRE(model.output.probes.size() == 3);
  const ProbeModel& grains = model.output.probes[0];
  CHECK(grains.kind == ProbeModel::Kind::kGrains);
  CHECK(grains.name == "grains");
  CHECK(grains.file == "probe_grains.csv");
  CHECK(grains.interval == 0.01);
  CHECK(grains.ids == std::vector<std::uint64_t>{0, 5, 17});
  const ProbeModel& walls = model.output.probes[1];
  CHECK(walls.kind == ProbeModel::Kind::kWallForces);
  CHECK(walls.file == "probe_walls.csv");
  CHECK(walls.interval == 0.0);  // every step
  CHECK(walls.ids.empty());
  CHECK(model.output.probes[2].file == "top_grain.csv");
  CHECK(model.output.probes[2].ids == std::vector<std::uint64_t>{80});
}

TEST_CASE("bad probes are reported as file:line:column: key: message") {
  struct Bad {
    const char* probe;    // the [[output.probes]] table
    const char* at;       // where the problem is reported ('^' = the column)
    const char* key;
    const char* message;  // fragment
  };
  const std::vector<Bad> cases = {
      {"kind = \"grains\"\nids = [0, 81, 3]\n", "ids = [0, ^81", "output.probes[0].ids[1]",
       "unknown grain id 81: the scene has 81 grains (ids 0 to 80)"},
      {"kind = \"grains\"\nids = [0, 3, 3]\n", "ids = [0, 3, ^3", "output.probes[0].ids[2]",
       "grain id 3 is listed twice"},
      {"kind = \"grains\"\nids = [0, -1]\n", "ids = [0, ^-1", "output.probes[0].ids[1]",
       "expected an integer in [0, 9223372036854775807], got -1"},
      {"kind = \"grains\"\nids = [0, 1.5]\n", "ids = [0, ^1.5", "output.probes[0].ids[1]", "got a number"},
      {"kind = \"grains\"\nids = 4\n", "ids = ^4", "output.probes[0].ids", "expected an array of integers"},
      {"kind = \"grains\"\nids = []\n", "ids = ^[]", "output.probes[0].ids", "expected at least one grain id"},
      {"kind = \"grains\"\n", "^[[output.probes]]", "output.probes[0].ids", "missing required key"},
      {"kind = \"grains\"\nids = [1]\ninterval = -0.5\n", "interval = ^-0.5", "output.probes[0].interval",
       "expected a number >= 0 [s], got -0.5"},
      {"kind = \"grain\"\n", "kind = ^\"grain\"", "output.probes[0].kind",
       "expected one of \"grains\", \"wall_forces\", \"fluid_pressure\", \"wave_gauge\", \"surge_front\", "
       "\"fluid_totals\", \"pressure_transducer\", \"driven_flow\", \"moving_fraction\", \"packing_density\", "
       "\"bedload_flux\", \"velocity_profile\", \"bed_shear_stress\", \"mean_flow_profile\", \"bedload_transport\", got \"grain\""},
      {"ids = [1]\n", "^[[output.probes]]", "output.probes[0].kind", "missing required key"},
      {"kind = \"wall_forces\"\nids = [1]\n", "^ids = [1]", "output.probes[0].ids", "unknown key"},
      {"kind = \"grains\"\nids = [1]\nfile = \"../x.csv\"\n", "file = ^\"../x.csv\"", "output.probes[0].file",
       "expected a plain file name"},
      {"kind = \"grains\"\nids = [1]\nfile = \"diagnostics.csv\"\n", "file = ^\"diagnostics.csv\"",
       "output.probes[0].file", "is an output riffle writes itself"},
      {"kind = \"grains\"\nids = [1]\nname = \"a b\"\n", "name = ^\"a b\"", "output.probes[0].name",
       "expected a name of letters"},
      {"kind = \"grains\"\nids = [1]\ncolour = \"red\"\n", "^colour", "output.probes[0].colour", "unknown key"},
      {"kind = 3\nids = [1]\n", "kind = ^3", "output.probes[0].kind", "expected a string, got an integer"},
      {"kind = \"grains\"\nids = [[1]]\n", "ids = [^[1]]", "output.probes[0].ids[0]", "got an array"},
      {"kind = \"grains\"\nids = [1]\nname = 5\n", "name = ^5", "output.probes[0].name", "expected a string"},
      {"kind = \"grains\"\nids = [1]\nfile = \"\"\n", "file = ^\"\"", "output.probes[0].file",
       "expected a plain file name"},
      {"kind = \"grains\"\nids = [1]\ninterval = \"often\"\n", "interval = ^\"often\"",
       "output.probes[0].interval", "got a string"},
  };
  for (const Bad& bad : cases) {
    const std::string text = contact_scene(std::string("\n[[output.probes]]\n") + bad.probe);
    CAPTURE(text);
    const std::vector<std::string> problems = probe_problems(text);
    std::string all_problems;
    for (const std::string& problem : problems) all_problems += problem + "\n";
    CAPTURE(all_problems);
    REQUIRE(problems.size() == 1);
    const std::string expected_start = test::first_location("probes.toml", text, bad.at) + bad.key + ": ";
    CHECK_MESSAGE(problems[0].rfind(expected_start, 0) == 0, problems[0], " should start with ", expected_start);
    CHECK_MESSAGE(problems[0].find(bad.message) != std::string::npos, problems[0]);
  }

  SUBCASE("two probes writing the same file") {
    const std::string text = contact_scene(
        "[[output.probes]]\nkind = \"wall_forces\"\n[[output.probes]]\nkind = \"wall_forces\"\ninterval = 0.1\n");
    const std::vector<std::string> problems = probe_problems(text);
    REQUIRE(problems.size() == 1);
    CHECK(problems[0].find("output.probes[1].name: another probe (\"wall_forces\") already writes "
                           "\"probe_wall_forces.csv\"") != std::string::npos);
  }
  SUBCASE("wall forces without [contact]") {
    const std::string text = test::small_scene_text("\n[output]\n[[output.probes]]\nkind = \"wall_forces\"\n");
    const std::vector<std::string> problems = probe_problems(text);
    REQUIRE(problems.size() == 1);
    CHECK(problems[0].find("output.probes[0].kind: wall forces need [contact]") != std::string::npos);
  }
}

TEST_CASE("fuzz: mutated probe tables give a sane model or a SceneError, nothing else") {
  const std::vector<std::string> values = {"0", "-1", "81", "1.5", "\"grains\"", "\"wall_forces\"", "[]", "[0, 0]",
                                           "[80]", "[[1]]", "\"\"", "\"x/y\"", "true", "{ a = 1 }", "1e308", "nan",
                                           "9223372036854775807", "[0, \"a\"]", "\"diagnostics.csv\""};
  // Mostly good values (so that many scenes pass and the accepted models get checked), sometimes anything.
  const std::vector<std::pair<std::string, std::vector<std::string>>> good = {
      {"kind", {"\"grains\"", "\"wall_forces\""}},
      {"ids", {"[0]", "[3, 80]", "[80, 0, 1]"}},
      {"interval", {"0", "0.01", "1.0e-4"}},
      {"name", {"\"a\"", "\"b-1\"", "\"c.2\""}},
      {"file", {"\"p.csv\"", "\"q.csv\""}},
      {"other", {}}};
  std::mt19937 random(12345);
  std::size_t accepted = 0;
  for (int round = 0; round < 300; ++round) {
    std::string probes;
    const int tables = static_cast<int>(random() % 3) + 1;
    for (int t = 0; t < tables; ++t) {
      probes += "[[output.probes]]\n";
      for (const auto& [key, choices] : good) {
        if (random() % 4 == 0 || (key == "other" && random() % 8 != 0)) continue;
        const bool wild = choices.empty() || random() % 6 == 0;
        probes += key + " = " + (wild ? values[random() % values.size()] : choices[random() % choices.size()]) + "\n";
      }
    }
    const std::string text = contact_scene(probes);
    try {
      const Model model = parse_scene(text, "fuzz.toml");
      ++accepted;
      for (const ProbeModel& probe : model.output.probes) {
        CHECK(probe.interval >= 0.0);
        for (std::uint64_t id : probe.ids) CHECK(id < 81);
        CHECK(probe.file.find('/') == std::string::npos);
      }
    } catch (const SceneError& error) {
      for (const std::string& problem : error.problems()) CHECK(problem.rfind("fuzz.toml:", 0) == 0);
    } catch (const std::exception& error) {
      FAIL_CHECK("unexpected exception: ", error.what(), "\n", text);
    }
  }
  MESSAGE("probe fuzz: ", accepted, " accepted of 300");
}

TEST_CASE("GrainSlotMap follows grain ids across reorderings") {
  Solids solids;
  for (int k = 0; k < 6; ++k) solids.add(Vec3(k, 0, 0), Vec3::Zero(), 0.1, 1000.0, 0, 0);
  GrainSlotMap map({4, 1, 99});
  CHECK(map.refresh(solids));  // first use builds the map
  CHECK(map.slot(0) == 4);
  CHECK(map.slot(1) == 1);
  CHECK(map.slot(2) == GrainSlotMap::kNone);  // no grain has id 99
  GrainSlotMap present({4, 1});
  CHECK(present.refresh(solids));
  CHECK_FALSE(present.refresh(solids));  // nothing moved: no rebuild
  permute_fields(solids, {5, 4, 3, 2, 1, 0});
  CHECK(present.refresh(solids));  // slots changed: rebuilt
  CHECK(present.slot(0) == 1);
  CHECK(present.slot(1) == 4);
  CHECK(solids.id[present.slot(0)] == 4);
  CHECK(solids.position[present.slot(0)].x() == 4.0);
}

TEST_CASE("wall reaction forces are minus the sum of the grain-wall contact forces per wall") {
  Contacts contacts;
  CHECK(wall_reaction_forces(contacts, 3).empty());  // not built yet: unknown
  contacts.valid = true;
  contacts.wall_pair_wall = {2, 0, 2, 1};
  contacts.wall_pair_force = {Vec3(0, 0, 1.5), Vec3(2, 0, 0), Vec3(0.25, 0, 0.5), Vec3::Zero()};
  const std::vector<Vec3> forces = wall_reaction_forces(contacts, 3);
  REQUIRE(forces.size() == 3);
  CHECK(forces[0] == Vec3(-2, 0, 0));
  CHECK(forces[1] == Vec3(0, 0, 0));
  CHECK(forces[2] == Vec3(-0.25, 0, -2.0));
}

TEST_CASE("a run writes the probes, the bed profile and the class centroids, and a resume continues them") {
  const std::string output = R"(bed_profile_interval = 0.01
checkpoint_interval = 0.02

[[output.probes]]
kind = "grains"
ids = [0, 5, 17]
interval = 0.01

[[output.probes]]
kind = "wall_forces"
interval = 0.005
)";
  const fs::path directory = test::scratch_dir("probes_run");
  const fs::path a = directory / "a";
  auto simulation = Simulation::from_model(parse_scene(contact_scene(output), "probes.toml"));
  RunOptions options;
  options.out_dir = a.string();
  options.threads = 2;
  REQUIRE(simulation->run(options).exit_code == kExitOk);

  // Grains: a row at t = 0 and every 0.01 s up to 0.04: 5 rows, 2 + 3 x 31 columns, the first 12 of each grain as
  // before the fluid's forces were added (tools read them by position), then the voidage, the undisturbed fluid
  // velocity and each force by source.
  const std::vector<std::string> grains = test::file_lines(a / "probe_grains.csv");
  REQUIRE(grains.size() == 6);
  CHECK(grains[0].rfind("time_s,step,grain0_x_m,grain0_y_m,grain0_z_m,grain0_vx_m_s,grain0_vy_m_s,grain0_vz_m_s,"
                        "grain0_wx_rad_s,grain0_wy_rad_s,grain0_wz_rad_s,grain0_fx_N,grain0_fy_N,grain0_fz_N,"
                        "grain0_voidage_1,grain0_ux_m_s,grain0_uy_m_s,grain0_uz_m_s,grain0_drag_fx_N,grain0_drag_fy_N,"
                        "grain0_drag_fz_N,grain0_pressure_fx_N,grain0_pressure_fy_N,grain0_pressure_fz_N,"
                        "grain0_added_mass_fx_N,grain0_added_mass_fy_N,grain0_added_mass_fz_N,grain0_history_fx_N,"
                        "grain0_history_fy_N,grain0_history_fz_N,grain0_lubrication_fx_N,grain0_lubrication_fy_N,"
                        "grain0_lubrication_fz_N,grain5_x_m,", 0) == 0);
  CHECK(grains[0].find(",grain17_fz_N,grain17_voidage_1,") != std::string::npos);
  const std::string last_column = ",grain17_lubrication_fz_N";
  CHECK(grains[0].size() - grains[0].rfind(last_column) == last_column.size());
  const std::vector<std::string> steps = {"0", "10", "20", "30", "40"};
  for (std::size_t row = 1; row < grains.size(); ++row) {
    CAPTURE(grains[row]);
    CHECK(std::count(grains[row].begin(), grains[row].end(), ',') == 1 + 3 * 31);
    CHECK(grains[row].substr(grains[row].find(',') + 1, steps[row - 1].size() + 1) == steps[row - 1] + ",");
  }
  CHECK(grains[1].rfind("0,0,0.005,0.005,0.005,", 0) == 0);  // grain 0 starts at (0.005, 0.005, 0.005)

  // Wall forces: 5 walls (z_max is open), a row every 0.005 s: 9 rows; t = 0 has no contact list yet (empty).
  const std::vector<std::string> walls = test::file_lines(a / "probe_wall_forces.csv");
  REQUIRE(walls.size() == 10);
  CHECK(walls[0] == "time_s,step,x_min_fx_N,x_min_fy_N,x_min_fz_N,x_max_fx_N,x_max_fy_N,x_max_fz_N,y_min_fx_N,"
                    "y_min_fy_N,y_min_fz_N,y_max_fx_N,y_max_fy_N,y_max_fz_N,z_min_fx_N,z_min_fy_N,z_min_fz_N");
  // New runs compute their initial contact forces: at t = 0 the grains are apart, so every wall force is zero.
  CHECK(walls[1] == "0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0");
  // Until the small grains land (about t = 0.039 s), only the 9 large grains rest on the floor: the floor carries
  // their weight, pushed downwards, 9 m g = 9 x 2500 x 4/3 pi (5 mm)^3 x 9.81 = 0.1156 N, after a short settling.
  const std::string at_30_ms = walls[7];
  REQUIRE(first_field(at_30_ms).rfind("0.03", 0) == 0);
  CHECK(std::stod(at_30_ms.substr(at_30_ms.rfind(',') + 1)) ==
        doctest::Approx(-9 * 2500.0 * 4.0 / 3.0 * 3.14159265358979 * 1.25e-7 * 9.81).epsilon(0.01));

  // Bed profile: 12 layers of 5 mm (the smallest diameter) over the 6 cm tank, at 5 times; centroids at 5 times.
  const std::vector<std::string> profile = test::file_lines(a / "bed_profile.csv");
  REQUIRE(profile.size() == 1 + 5 * 12);
  CHECK(profile[0] == "time_s,t_over_T,layer,z_low_m,z_high_m,grains,contacts,coordination_number,"
                      "mean_dimensionless_overlap");
  CHECK(profile[2] == "0,0,1,0.005,0.01,9,0,0,");  // large grains' centres at 5 mm: layer 1; none touching at t = 0
  const std::vector<std::string> centroids = test::file_lines(a / "class_centroids.csv");
  REQUIRE(centroids.size() == 6);
  CHECK(centroids[0] == "time_s,t_over_T,class_0_centroid_m,class_1_centroid_m");
  CHECK(centroids[1] == "0,0,0.02255,0.005");  // small grains at 20, 25.1 mm (36 each) - large at 5 mm
  CHECK(first_field(centroids[5]) == first_field(profile.back()));
  std::size_t grains_at_end = 0;
  for (std::size_t row = profile.size() - 12; row < profile.size(); ++row) {
    std::istringstream fields(profile[row]);
    std::string field;
    for (int k = 0; k < 6; ++k) std::getline(fields, field, ',');
    grains_at_end += std::stoul(field);
  }
  CHECK(grains_at_end == 81);

  // Resume from the step-20 checkpoint into a copy of the run: the rows after t = 0.02 are dropped and written
  // again, identically.
  const fs::path b = directory / "b";
  fs::copy(a, b, fs::copy_options::recursive);
  auto resumed = Simulation::from_checkpoint((b / "checkpoints" / "step_0000000020.ckpt").string());
  options.out_dir = b.string();
  options.threads = 1;
  REQUIRE(resumed->run(options).exit_code == kExitOk);
  for (const char* file : {"probe_grains.csv", "probe_wall_forces.csv", "bed_profile.csv", "class_centroids.csv"}) {
    CAPTURE(file);
    CHECK(test::file_text(b / file) == test::file_text(a / file));
  }
  // A resume that stops earlier leaves no rows from the first run's later times behind.
  const fs::path c = directory / "c";
  fs::copy(a, c, fs::copy_options::recursive);
  auto shorter = Simulation::from_checkpoint((c / "checkpoints" / "step_0000000020.ckpt").string());
  options.out_dir = c.string();
  options.until = 0.025;
  REQUIRE(shorter->run(options).exit_code == kExitOk);
  const std::vector<std::string> short_walls = test::file_lines(c / "probe_wall_forces.csv");
  REQUIRE(short_walls.size() == 7);  // t = 0, 0.005, ..., 0.025
  CHECK(short_walls.back() == walls[6]);
  CHECK(test::file_lines(c / "class_centroids.csv").size() == 4);  // t = 0, 0.01, 0.02

  // Resume from a's step-20 checkpoint into a new folder: its series start with a's rows up to t = 0.02 and go on
  // as a's did, so the folder holds the whole run's (S and the centroids from t = 0, not from the resume).
  const fs::path d = directory / "d";
  auto elsewhere = Simulation::from_checkpoint((a / "checkpoints" / "step_0000000020.ckpt").string());
  options.out_dir = d.string();
  options.until.reset();
  REQUIRE(elsewhere->run(options).exit_code == kExitOk);
  for (const char* file : {"probe_grains.csv", "probe_wall_forces.csv", "bed_profile.csv", "class_centroids.csv"}) {
    CAPTURE(file);
    CHECK(test::file_text(d / file) == test::file_text(a / file));
  }
}

TEST_CASE("a grains probe writes a grain past a periodic face at its place in the period") {
  // A lone 2 mm grain flying at 1 m/s along x through the seam of a 4 cm periodic box from 0.1 mm before it: its
  // state passes x = L and is wrapped only at the neighbour rebuild that follows (its skin of 0.5 mm half used up,
  // 0.15 mm past the face), but every probe row gives x in [0, L], as the VTK frames do (L itself where a position a
  // rounding below it is printed to the probe's 9 digits).
  const std::string text =
      SceneBuilder().run({.name = "seam_probe", .end_time = 0.002, .dt = 1.0e-5, .solid_substeps = 2,
                          .gravity = {0.0, 0.0, 0.0}})
          .material("grain", {.density = 2650.0, .young_modulus = 1.0e8, .poisson_ratio = 0.3})
          .tank({.size = {0.04, 0.02, 0.02}, .wall_material = "grain"})
          .set("periodic", TomlValue::verbatim("[\"x\"]"))
          .contact({.restitution = 0.8, .friction = 0.5}).solids()
          .sphere({.position = {0.0399, 0.01, 0.01}, .radius = 0.001, .material = "grain", .velocity = {1.0, 0.0, 0.0}})
          .output().toml() +
      "[[output.probes]]\nkind = \"grains\"\nids = [0]\ninterval = 1.0e-5\n";
  const Model model = parse_scene(text, "seam_probe.toml");
  // The state: past the face for some steps after the crossing (the test is about something).
  auto stepped = Simulation::from_model(model);
  double farthest = 0.0;
  while (stepped->world().time < 0.002 - 1e-12) {
    stepped->step();
    farthest = std::max(farthest, stepped->world().solids->position[0].x() - 0.04);
  }
  CHECK(farthest > 1.0e-4);
  // The probe: every row inside the period.
  const fs::path directory = test::scratch_dir("seam_probe");
  auto simulation = Simulation::from_model(model);
  RunOptions options;
  options.out_dir = directory.string();
  REQUIRE(simulation->run(options).exit_code == kExitOk);
  const std::vector<std::string> rows = test::file_lines(directory / "probe_grains.csv");
  REQUIRE(rows.size() == 202);  // the header, t = 0 and 200 steps
  for (std::size_t row = 1; row < rows.size(); ++row) {
    const std::string& line = rows[row];
    const std::size_t x_start = line.find(',', line.find(',') + 1) + 1;
    const double x = std::stod(line.substr(x_start, line.find(',', x_start) - x_start));
    CAPTURE(line);
    CHECK(x >= 0.0);
    CHECK(x <= 0.04);
  }
}

TEST_CASE("with [solids] initial_state, probe ids cover its grains and then the scene's own") {
  const fs::path directory = test::scratch_dir("probes_initial_state");
  // A checkpoint holding the 81 grains of the contact scene (ids 0-80).
  write_checkpoint((directory / "bed.ckpt").string(),
                   Simulation::from_model(parse_scene(contact_scene(""), "probes.toml"))->checkpoint_data());
  auto scene = [&](const std::string& ids) {
    return SceneBuilder().run({.end_time = 0.01, .dt = 1.0e-3})
        .material("grain", {.density = 2500.0, .young_modulus = 1.0e7, .poisson_ratio = 0.3})
        .tank({.size = {0.04, 0.04, 0.06}, .wall_material = "grain"}).contact({.restitution = 0.5, .friction = 0.4})
        .solids().set("initial_state", "bed.ckpt")
        .sphere({.position = {0.02, 0.02, 0.05}, .radius = 0.004, .material = "grain"})
        .output().probe("grains").set("ids", TomlValue::verbatim(ids)).toml();
  };
  const std::string scene_file = (directory / "continued.toml").string();
  const Model model = parse_scene(scene(std::string("[0, 80, 81]")), scene_file);
  CHECK(model.output.probes[0].ids == std::vector<std::uint64_t>{0, 80, 81});  // 81: the scene's own sphere
  const std::string bad = scene("[0, 82]");
  CHECK_THROWS_WITH_AS(parse_scene(bad, scene_file),
                       doctest::Contains("output.probes[0].ids[1]: unknown grain id 82: the scene has 82 grains "
                                         "(ids 0 to 81)"),
                       SceneError);
  const World world = Simulation::from_model(model)->world();
  CHECK(world.solids->id.back() == 81);
}
