// Tank motion beyond the seed's sinusoid: the cubic spline (systems/physics/math/cubic_spline.hpp) against its theory, the
// sinusoid's phase and start time against the closed form, the CSV motion table and every new [tank.motion] key's
// validation (file, line and key in each message), and a resumed run that detects a changed table.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "engine/output/checkpoint_validation.hpp"
#include "engine/run/simulation.hpp"
#include "engine/scene/motion_table.hpp"
#include "engine/scene/scene.hpp"
#include "engine/setup/initial_state.hpp"
#include "systems/physics/math/cubic_spline.hpp"
#include "systems/physics/geometry/tank_kinematics.hpp"
#include "tests/support/test_support.hpp"

using namespace riffle;

namespace {

using test::joined;


/// A sampled A sin(w t + phi) on [0, periods T] at `per_period` points per period.
struct SampledSine {
  double amplitude = 0.01, frequency = 1.7, phi = 0.3;
  std::vector<double> t, y, m;
  SampledSine(int per_period, int periods) {
    const double h = 1.0 / (frequency * per_period);
    for (int i = 0; i <= per_period * periods; ++i) {
      t.push_back(i * h);
      y.push_back(amplitude * std::sin(omega() * t.back() + phi));
    }
    m = not_a_knot_curvatures(t, y);
  }
  double omega() const { return 2.0 * std::numbers::pi * frequency; }
  double h() const { return t[1] - t[0]; }
};

struct SplineErrors {
  double value = 0.0, slope = 0.0, curvature = 0.0;        // over the whole table
  double interior_slope = 0.0;                               // five intervals away from each end
};

SplineErrors errors_of(const SampledSine& sine) {
  SplineErrors errors;
  const double w = sine.omega(), a = sine.amplitude, h = sine.h();
  for (double s = 0.0; s <= sine.t.back(); s += h / 37.0) {
    const SplinePoint p = spline_at(sine.t, sine.y, sine.m, s);
    const double phase = w * s + sine.phi;
    errors.value = std::max(errors.value, std::abs(p.value - a * std::sin(phase)));
    const double slope = std::abs(p.slope - a * w * std::cos(phase));
    errors.slope = std::max(errors.slope, slope);
    errors.curvature = std::max(errors.curvature, std::abs(p.curvature + a * w * w * std::sin(phase)));
    if (s > 5.0 * h && s < sine.t.back() - 5.0 * h) errors.interior_slope = std::max(errors.interior_slope, slope);
  }
  return errors;
}

std::string write_file(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path) << text;
  return path.string();
}

/// A sine table "t,x" of `rows` rows at spacing h from t0.
std::string sine_csv(double amplitude, double frequency, double h, int rows, double t0 = 0.0) {
  std::string text = "# a sampled sinusoid\nt,x\n";
  char line[128];
  for (int i = 0; i < rows; ++i) {
    const double t = t0 + i * h;
    std::snprintf(line, sizeof line, "%.17g,%.17g\n", t, amplitude * std::sin(2.0 * std::numbers::pi * frequency * t));
    text += line;
  }
  return text;
}

/// A scene with only a tank and `motion` as its [tank.motion] body.
std::string motion_scene(const std::string& motion, double end_time = 0.1) {
  return "[run]\nend_time = " + std::to_string(end_time) +
         "\ndt = 1.0e-3\n\n[materials.glass]\ndensity = 2500.0\n\n[tank]\nsize = [0.2, 0.1, 0.1]\n"
         "wall_material = \"glass\"\n\n[tank.motion]\n" + motion;
}

using test::problems_of;

bool mentions_in_order(const std::vector<std::string>& problems, const std::string& start, const std::string& fragment) {
  return std::any_of(problems.begin(), problems.end(), [&](const std::string& line) {
    return line.rfind(start, 0) == 0 && line.find(fragment) != std::string::npos;
  });
}


}  // namespace

TEST_CASE("cubic spline: a cubic is reproduced exactly on uneven knots (not-a-knot ends)") {
  const std::vector<double> t = {-0.3, 0.0, 0.05, 0.4, 0.45, 1.0, 1.7};
  auto cubic = [](double s) { return 0.2 - 1.5 * s + 0.7 * s * s - 2.1 * s * s * s; };
  std::vector<double> y;
  for (double s : t) y.push_back(cubic(s));
  const std::vector<double> m = not_a_knot_curvatures(t, y);
  for (double s = -0.3; s <= 1.7; s += 0.0131) {
    const SplinePoint p = spline_at(t, y, m, s);
    CHECK(p.value == doctest::Approx(cubic(s)).epsilon(1e-12).scale(1.0));
    CHECK(p.slope == doctest::Approx(-1.5 + 1.4 * s - 6.3 * s * s).epsilon(1e-11).scale(1.0));
    CHECK(p.curvature == doctest::Approx(1.4 - 12.6 * s).epsilon(1e-10).scale(1.0));
  }
  // Four knots: the one cubic through them.
  const std::vector<double> t4 = {0.0, 0.3, 0.5, 1.1};
  std::vector<double> y4;
  for (double s : t4) y4.push_back(cubic(s));
  CHECK(spline_at(t4, y4, not_a_knot_curvatures(t4, y4), 0.8).value == doctest::Approx(cubic(0.8)).epsilon(1e-12));
  CHECK_THROWS(not_a_knot_curvatures({0.0, 1.0, 2.0}, {0.0, 1.0, 2.0}));
  CHECK_THROWS(not_a_knot_curvatures({0.0, 1.0, 1.0, 2.0}, {0.0, 1.0, 2.0, 3.0}));
}

TEST_CASE("cubic spline: a sampled sinusoid within the spline's error bounds (Hall & Meyer 1976)") {
  // |s - f| <= 5/384 h^4 |f''''|, |s' - f'| <= 1/24 h^3 |f''''|, |s'' - f''| <= 3/8 h^2 |f''''| for the complete
  // spline; the not-a-knot spline meets the value and curvature bounds everywhere and the slope bound away from
  // the ends; at the ends its slope error is O(h^3) with a larger constant (measured 1.1-1.4x the bound).
  SplineErrors previous;
  for (int per_period : {50, 100, 200}) {
    CAPTURE(per_period);
    const SampledSine sine(per_period, 3);
    const double h = sine.h(), f4 = sine.amplitude * std::pow(sine.omega(), 4);
    const SplineErrors errors = errors_of(sine);
    CHECK(errors.value <= 5.0 / 384.0 * std::pow(h, 4) * f4);
    CHECK(errors.curvature <= 3.0 / 8.0 * h * h * f4);
    CHECK(errors.interior_slope <= 1.0 / 24.0 * std::pow(h, 3) * f4);
    CHECK(errors.slope <= 2.0 / 24.0 * std::pow(h, 3) * f4);
    if (per_period > 50) {  // orders: 4, 3, 2 (halving h)
      CHECK(std::log2(previous.value / errors.value) > 3.8);
      CHECK(std::log2(previous.slope / errors.slope) > 2.8);
      CHECK(std::log2(previous.curvature / errors.curvature) > 1.9);
    }
    previous = errors;
  }
}

TEST_CASE("cubic spline: the largest |s| is found exactly, between knots too") {
  const SampledSine coarse(8, 1);  // 8 points per period: the peaks fall between knots
  double sampled = 0.0;
  for (double s = 0.0; s <= coarse.t.back(); s += 1e-5)
    sampled = std::max(sampled, std::abs(spline_at(coarse.t, coarse.y, coarse.m, s).value));
  const double exact = spline_max_abs(coarse.t, coarse.y, coarse.m);
  CHECK(exact >= sampled);
  CHECK(exact == doctest::Approx(sampled).epsilon(1e-8));
  CHECK(exact > *std::max_element(coarse.y.begin(), coarse.y.end()));
}

TEST_CASE("sinusoid: defaults are the seed's x = -A r(t) sin(2 pi f t) to the bit") {
  TankMotionModel motion;
  motion.kind = TankMotionModel::Kind::kSinusoidal;
  motion.amplitude = 0.01;
  motion.frequency = 1.7;
  motion.ramp_time = 0.3;
  const double omega = 2.0 * std::numbers::pi * motion.frequency;
  for (double t = 0.0; t < 1.0; t += 0.0173) {
    const Ramp r = start_up_ramp(t, motion.ramp_time);
    CHECK(tank_kinematics(motion, t).displacement[0] == -motion.amplitude * r.value * std::sin(omega * t));
  }
}

TEST_CASE("sinusoid with phase -90 deg and a start time: x = A cos(w (t - t0)) from rest") {
  const std::string scene = motion_scene(
      "kind = \"sinusoidal\"\namplitude = 0.02\nfrequency = 1.25\nphase = -90\nstart_time = 0.2\n");
  const Model model = parse_scene(scene, "cosine.toml");
  const TankMotionModel& motion = model.tank.motion;
  CHECK(motion.phase == doctest::Approx(-std::numbers::pi / 2).epsilon(1e-15));
  CHECK(motion.start_time == 0.2);
  const double a = 0.02, w = 2.0 * std::numbers::pi * 1.25;
  for (double t = 0.0; t < 2.0; t += 0.0071) {
    const TankMotion tank = tank_kinematics(motion, t);
    const double tau = std::max(0.0, t - 0.2);
    CHECK(tank.displacement[0] == doctest::Approx(a * std::cos(w * tau)).epsilon(1e-12).scale(a));
    if (t < 0.2) {  // at rest, displaced by A
      CHECK(tank.velocity.norm() == 0.0);
      CHECK(tank.acceleration.norm() == 0.0);
    } else {
      CHECK(tank.velocity[0] == doctest::Approx(-a * w * std::sin(w * tau)).epsilon(1e-12).scale(a * w));
      CHECK(tank.acceleration[0] == doctest::Approx(-a * w * w * std::cos(w * tau)).epsilon(1e-12).scale(a * w * w));
    }
  }
  // With a ramp the motion starts from zero displacement at start_time, C2.
  const Model ramped = parse_scene(motion_scene("kind = \"sinusoidal\"\namplitude = 0.02\nfrequency = 1.25\n"
                                                "phase = -90\nstart_time = 0.2\nramp_time = 0.4\n"),
                                   "ramped.toml");
  CHECK(tank_kinematics(ramped.tank.motion, 0.1).displacement.norm() == 0.0);
  CHECK(tank_kinematics(ramped.tank.motion, 0.2).displacement.norm() == 0.0);
  CHECK(tank_kinematics(ramped.tank.motion, 0.7).displacement[0] ==
        doctest::Approx(a * std::cos(w * 0.5)).epsilon(1e-12));
}

TEST_CASE("a cosine start places the walls, the water and the grains displaced by A at t = 0") {
  std::string scene = test::fluid_scene_text();
  scene.replace(scene.find("frequency = 1.7"), 15, "frequency = 1.7\nphase = -90");
  const Model model = parse_scene(scene, "cosine_fluid.toml");
  const Model still = parse_scene(test::fluid_scene_text(), "fluid.toml");
  const World world = initial_world(model);
  const World reference = initial_world(still);  // the seed's motion starts at x = 0
  REQUIRE(world.fluid->size() == reference.fluid->size());
  const Vec3 shift(0.01, 0.0, 0.0);
  CHECK(world.tank_motion->displacement.isApprox(shift, 1e-15));
  CHECK(world.tank_motion->velocity.norm() < 1e-15);
  for (std::size_t i = 0; i < world.fluid->size(); ++i)
    CHECK((world.fluid->position[i] - (reference.fluid->position[i] + shift)).norm() < 1e-15);
  for (std::size_t wall = 0; wall < world.walls->size(); ++wall)
    CHECK((world.walls->point[wall] - (reference.walls->point[wall] + shift)).norm() < 1e-15);
  // Grains (test::small_scene_text: a block of them, a ramp that the phase does not change at t = 0, so no ramp).
  std::string grains = test::small_scene_text();
  grains.replace(grains.find("ramp_time = 0.2"), 15, "phase = -90");
  const World shaken = initial_world(parse_scene(grains, "cosine_grains.toml"));
  const World resting = initial_world(test::small_model());
  REQUIRE(shaken.solids->size() == resting.solids->size());
  REQUIRE(shaken.solids->size() > 0);
  for (std::size_t i = 0; i < shaken.solids->size(); ++i)
    CHECK((shaken.solids->position[i] - (resting.solids->position[i] + shift)).norm() < 1e-15);
}

TEST_CASE("motion table: a sampled sinusoid gives the analytic kinematics within the spline's bounds") {
  const double a = 0.01, f = 1.7, w = 2.0 * std::numbers::pi * f, h = 1.0 / (200.0 * f);
  MotionTable table;
  REQUIRE(parse_motion_table(sine_csv(a, f, h, 2 * 200 + 1), "sine.csv", table) == "");
  TankMotionModel motion;
  motion.kind = TankMotionModel::Kind::kTable;
  motion.table = table;
  const double f4 = a * std::pow(w, 4);
  for (double t = 0.0; t <= table.time.back(); t += h / 7.0) {
    const TankMotion tank = tank_kinematics(motion, t);
    CHECK(std::abs(tank.displacement[0] - a * std::sin(w * t)) <= 5.0 / 384.0 * std::pow(h, 4) * f4);
    CHECK(std::abs(tank.velocity[0] - a * w * std::cos(w * t)) <= 2.0 / 24.0 * std::pow(h, 3) * f4);
    CHECK(std::abs(tank.acceleration[0] + a * w * w * std::sin(w * t)) <= 3.0 / 8.0 * h * h * f4);
    CHECK(tank.displacement[1] == 0.0);
    CHECK(tank.displacement[2] == 0.0);
  }
  // Outside the table: at rest at the end's displacement.
  const TankMotion after = tank_kinematics(motion, table.time.back() + 1.0);
  CHECK(after.displacement[0] == doctest::Approx(table.displacement[0].back()).epsilon(1e-12).scale(a));
  CHECK(after.velocity.norm() == 0.0);
  CHECK(after.acceleration.norm() == 0.0);
  CHECK(tank_motion_sweep(motion)[0] == doctest::Approx(a).epsilon(1e-8));
  CHECK(tank_motion_sweep(motion)[1] == 0.0);
}

TEST_CASE("motion table: columns in any order, comments and blank lines, bad files name their line") {
  MotionTable table;
  REQUIRE(parse_motion_table("# header follows\n\nt, z ,x\n0,0,1\n0.1,1,1\n\n0.2,2,1\n0.3,3,1\n", "ok.csv", table) ==
          "");
  CHECK(table.time.size() == 4);
  CHECK(table.displacement[2][3] == 3.0);
  CHECK(table.displacement[0][0] == 1.0);
  CHECK(table.displacement[1].empty());
  REQUIRE(parse_motion_table("\xEF\xBB\xBFt,x\r\n0,0\r\n1,1\r\n2,2\r\n3,3\r\n", "excel.csv", table) == "");
  CHECK(table.displacement[0][3] == 3.0);
  struct Bad {
    const char* text;
    const char* problem;
  };
  const std::vector<Bad> cases = {
      {"", "m.csv:0: no header"},
      {"time,x\n0,0\n", "m.csv:1: expected the header \"t,x\""},
      {"t\n0\n", "m.csv:1: the header names no displacement column"},
      {"t,x,w\n", "m.csv:1: column 3 of the header is \"w\"; expected x, y or z"},
      {"t,x,x\n", "m.csv:1: the header names x twice"},
      {"t,x\n0,0\n0.1,abc\n", "m.csv:3: column x: expected a number, got \"abc\""},
      {"t,x\n0,0\n0.1,\n", "m.csv:3: column x: expected a number, got \"\""},
      {"t,x\n0,0\n0.1,nan\n", "m.csv:3: column x: expected a finite number, got \"nan\""},
      {"t,x\n0,0\n0.1,1e999\n", "m.csv:3: column x: expected a finite number"},
      {"t,x\n0,0\n0.1,1,2\n", "m.csv:3: expected 2 comma-separated numbers as in the header, got 3 fields"},
      {"t,x\n0,0\n0.2,0\n0.1,0\n", "m.csv:4: the times must increase strictly: t = 0.1 s follows t = 0.2 s"},
      {"t,x\n0,0\n0,0\n", "m.csv:3: the times must increase strictly"},
      {"t,x\n0,0\n0.1,0\n0.2,0\n", "m.csv:0: has 3 rows; a motion table needs at least 4"},
  };
  for (const Bad& bad : cases) {
    CAPTURE(bad.text);
    const std::string problem = parse_motion_table(bad.text, "m.csv", table);
    CHECK_MESSAGE(problem.find(bad.problem) == 0, problem);
  }
}

TEST_CASE("motion table: more than the row cap is refused while reading, not after") {
  std::string text = "t,x\n";
  text.reserve(16 * (kMaxMotionRows + 2));
  for (std::size_t i = 0; i <= kMaxMotionRows; ++i) text += std::to_string(i) + ",0\n";
  MotionTable table;
  const std::string problem = parse_motion_table(text, "big.csv", table);
  CHECK(problem.find("big.csv:" + std::to_string(kMaxMotionRows + 2) + ": more than 1000000 rows") == 0);
  CHECK(table.time.size() == kMaxMotionRows);
}

TEST_CASE("[tank.motion] new keys: phase in degrees, start_time, kind = table and its file") {
  const auto dir = test::scratch_dir("motion_keys");
  const std::string scene_file = (dir / "scene.toml").string();
  write_file(dir / "sine.csv", sine_csv(0.01, 1.7, 0.001, 200));  // 0 .. 0.199 s
  write_file(dir / "short.csv", "t,x\n0,0\n0.01,1e-4\n0.02,4e-4\n0.03,9e-4\n");
  write_file(dir / "bad.csv", "t,x\n0,0\n0.01,0\n0.02,oops\n0.03,0\n");
  write_file(dir / "late.csv", sine_csv(0.01, 1.7, 0.001, 200, 0.05));

  // A good table is read relative to the scene file.
  const Model model = parse_scene(motion_scene("kind = \"table\"\nfile = \"sine.csv\"\n"), scene_file);
  CHECK(model.tank.motion.kind == TankMotionModel::Kind::kTable);
  CHECK(model.tank.motion.table.time.size() == 200);
  CHECK(model.tank.motion.table.file == (dir / "sine.csv").string());

  struct Bad {
    std::string motion;
    std::string start;     // "scene.toml:line:column: key: " expected at the start of a problem
    std::string fragment;  // in that problem
  };
  const std::string at = scene_file + ":";
  const std::vector<Bad> cases = {
      {"kind = \"sinusoidal\"\namplitude = 0.01\nfrequency = 1\nphase = \"90 deg\"\n", at + "16:9: tank.motion.phase: ",
       "expected a number in [-360, 360] [deg], got a string"},
      {"kind = \"sinusoidal\"\namplitude = 0.01\nfrequency = 1\nphase = 450\n", at + "16:9: tank.motion.phase: ",
       "got 450"},
      {"kind = \"sinusoidal\"\namplitude = 0.01\nfrequency = 1\nstart_time = -1\n",
       at + "16:14: tank.motion.start_time: ", "expected a number >= 0 [s], got -1"},
      {"kind = \"table\"\n", at + "12:1: tank.motion.file: ", "missing required key"},
      {"kind = \"table\"\nfile = \"none.csv\"\n", at + "14:8: tank.motion.file: ",
       (dir / "none.csv").string() + ": cannot open the motion table"},
      {"kind = \"table\"\nfile = \"bad.csv\"\n", at + "14:8: tank.motion.file: ",
       (dir / "bad.csv").string() + ":4: column x: expected a number, got \"oops\""},
      {"kind = \"table\"\nfile = \".\"\n", at + "14:8: tank.motion.file: ", "is a directory"},
      {"kind = \"table\"\nfile = \"sine.csv\"\namplitude = 0.01\n", at + "15:1: tank.motion.amplitude: ",
       "unknown key"},
      {"kind = \"sinusoidal\"\namplitude = 0.01\nfrequency = 1\nfile = \"sine.csv\"\n", at + "16:1: tank.motion.file: ",
       "unknown key"},
      // The run goes on past a table that ends moving, or starts before one that starts moving.
      {"kind = \"table\"\nfile = \"short.csv\"\n", at + "14:8: tank.motion.file: ",
       "the table ends at t = 0.03 s, before run.end_time = 0.1 s, with the tank moving"},
      {"kind = \"table\"\nfile = \"late.csv\"\n", at + "14:8: tank.motion.file: ",
       "the table starts at t = 0.05 s, after the run's start (t = 0), with the tank moving"},
  };
  for (const Bad& bad : cases) {
    const std::string text = motion_scene(bad.motion);
    CAPTURE(text);
    const std::vector<std::string> problems = problems_of(text, scene_file);
    CHECK_MESSAGE(mentions_in_order(problems, bad.start, bad.fragment), "expected ", bad.start, "... ", bad.fragment, "; got\n",
                  joined(problems));
  }
  // A run that ends before the table does is fine even though the table ends moving.
  CHECK_NOTHROW(parse_scene(motion_scene("kind = \"table\"\nfile = \"short.csv\"\n", 0.02), scene_file));
  std::filesystem::remove_all(dir);
}

TEST_CASE("a resumed run re-reads its table and refuses one changed at the checkpoint's time") {
  const auto dir = test::scratch_dir("motion_resume");
  const std::string scene_file = (dir / "scene.toml").string();
  write_file(dir / "sine.csv", sine_csv(0.01, 1.7, 0.001, 200));
  std::string text = test::small_scene_text();
  text.replace(text.find("kind = \"sinusoidal\""), text.find("[solids]") - text.find("kind = \"sinusoidal\""),
               "kind = \"table\"\nfile = \"sine.csv\"\n\n");
  write_file(scene_file, text);
  auto simulation = Simulation::from_scene_file(scene_file);
  for (int step = 0; step < 20; ++step) simulation->step();
  const CheckpointData data = simulation->checkpoint_data();
  const double time = simulation->world().time;
  CHECK(simulation->world().tank_motion->displacement[0] ==
        doctest::Approx(0.01 * std::sin(2.0 * std::numbers::pi * 1.7 * time)).epsilon(1e-6));
  CHECK_NOTHROW(Simulation::from_checkpoint_data(data, "run.ckpt"));
  write_file(dir / "sine.csv", sine_csv(0.012, 1.7, 0.001, 200));  // a different amplitude
  try {
    Simulation::from_checkpoint_data(data, "run.ckpt");
    FAIL("a changed table was accepted");
  } catch (const std::exception& error) {
    CHECK(std::string(error.what()).find("differs from the scene's motion at t = ") != std::string::npos);
  }
  std::filesystem::remove_all(dir);
}
