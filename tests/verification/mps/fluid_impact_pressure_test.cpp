// Verification: the impact pressure of a dam break on a wall sensor (Lobovsky, Botia-Vera, Castellana, Mas-Soler &
// Souto-Iglesias 2014, J. Fluids Struct. 48, 407-434; their H = 300 mm series, tests/data/lobovsky_2014_h300_peaks.csv):
// a tank 1.61 m long, a column 0.6 m x 0.3 m, sensor 1 on the downstream wall 3 mm above the floor. The peak of the
// first impact's impulse (its mean over 15 ms) is checked against the experiment at two Courant numbers; the peak,
// a one-step spike of order rho u^2 / C_r in riffle's incompressible projection, is reported against the measured
// 2.5-97.5 % scatter of 100 runs (not met: docs/RESULTS.md, the impact pressure).
//
// Sizes (CTest time): l0 = 11.5 mm (H / 26; 1.61 m = 140 l0), a slab 4 l0 thick, up to 15 ms after the front reaches the
// wall (t ~ 0.45 s). The full study (l0 = 10 and 5 mm, post-impact noise) is tools/riffle-tools impact-study (docs/RESULTS.md).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "engine/output/probes.hpp"
#include "tests/support/fluid_support.hpp"

namespace riffle {
namespace {

constexpr double kH = 0.3;
using test::kG;
using test::kRho;

struct SensorRow {
  double median = 0.0, low = 0.0, high = 0.0;  ///< P = p / (rho g H): median, 2.5 % and 97.5 % of the peak
};

/// Sensor 1's row of the Lobovsky table (columns median_peak_P, p2_5_peak_P, p97_5_peak_P).
SensorRow lobovsky_sensor_1() {
  std::ifstream in(std::string(RIFFLE_SOURCE_DIR) + "/tests/data/lobovsky_2014_h300_peaks.csv");
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] != '1') continue;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream fields(line);
    double sensor = 0, z = 0, median_mbar = 0, low_mbar = 0, high_mbar = 0;
    SensorRow row;
    if (fields >> sensor >> z >> median_mbar >> low_mbar >> high_mbar >> row.median >> row.low >> row.high) return row;
  }
  return {};
}

struct Impact {
  double peak = 0.0;          ///< largest P at sensor 1 up to the end
  double peak_time = 0.0;     ///< T = t sqrt(g / H) of the peak
  double arrival_time = 0.0;  ///< T of the first reading above P = 0.1
  double mean_15ms = 0.0;     ///< mean P over the 15 ms after arrival (the impact's impulse / 15 ms)
  int steps = 0;
};

/// The Lobovsky dam break at l0 with Courant number `courant` and sound speed `sound_speed` (0 = incompressible),
/// sensor 1 read every step through the fluid_pressure probe's own function.
Impact run_lobovsky(double l0, double courant, double sound_speed) {
  const double width = 4.0 * l0;
  // The tank walls need whole spacings: 1.61 m long, and high enough (>= 0.6 m) for the run-up.
  const double height = std::ceil(0.6 / l0 - 1e-9) * l0;
  Model model =
      test::fluid_model(Vec3(1.61, width, height), l0, {ParticleBoxModel{Vec3::Zero(), Vec3(0.6, width, kH)}});
  model.tank.domain_margin = 0.6;
  model.fluid.courant = courant;
  model.fluid.sound_speed = sound_speed;
  test::FluidRun run(std::move(model));
  const FluidProbeSettings settings = fluid_probe_settings(run.model);
  const Vec3 sensor(1.61, 0.5 * width, 0.003);
  const double time_scale = std::sqrt(kG / kH);
  Impact impact;
  double arrival = -1.0, impulse = 0.0, last_time = 0.0, last_pressure = 0.0;
  while (arrival < 0.0 || run.world.time < arrival + 0.015 - 1e-12) {
    REQUIRE(run.world.time < 0.7);  // the front must have arrived by then
    REQUIRE_MESSAGE(run.step(), run.diagnosis());
    ++impact.steps;
    const TankMotion tank = run.world.tank_motion ? *run.world.tank_motion : TankMotion{};
    double pressure = fluid_pressure_at(*run.world.fluid, settings, tank, sensor) / (kRho * kG * kH);
    if (!std::isfinite(pressure)) pressure = 0.0;  // a dry sensor
    if (arrival < 0.0 && pressure > 0.1) arrival = run.world.time;
    if (arrival >= 0.0 && run.world.time > arrival) impulse += 0.5 * (pressure + last_pressure) * (run.world.time - last_time);
    if (pressure > impact.peak) {
      impact.peak = pressure;
      impact.peak_time = run.world.time * time_scale;
    }
    last_time = run.world.time;
    last_pressure = pressure;
  }
  impact.arrival_time = arrival * time_scale;
  impact.mean_15ms = impulse / (last_time - arrival);
  return impact;
}

}  // namespace

TEST_CASE("dam break impact on a wall sensor against Lobovsky et al. 2014") {
  const SensorRow measured = lobovsky_sensor_1();
  REQUIRE(measured.median > 0.0);
  const double l0 = 0.0115;  // 1.61 m = 140 l0; H = 26 l0 (0.299 m), the column 52 l0 (0.598 m)
  const Impact coarse = run_lobovsky(l0, 0.2, 0.0);
  const Impact fine_dt = run_lobovsky(l0, 0.1, 0.0);
  MESSAGE("sensor 1, l0 = 11.5 mm: arrival T = " << coarse.arrival_time << ", peak P = p/(rho g H) " << coarse.peak
                                               << " at T = " << coarse.peak_time << ", 15 ms mean " << coarse.mean_15ms
                                               << " (C_r 0.2, " << coarse.steps << " steps); C_r 0.1: peak "
                                               << fine_dt.peak << ", 15 ms mean " << fine_dt.mean_15ms
                                               << "; measured peak median " << measured.median << ", 2.5-97.5 % ["
                                               << measured.low << ", " << measured.high << "]");
  // Arrival: the record's T = 2.443 counts from the gate's first motion (it lifts over T ~ 0.4); ours opens at once
  // and its front reaches the wall at T ~ 2.5 (every l0 and C_r of tools/riffle-tools impact-study): within 0.3.
  CHECK(std::abs(coarse.arrival_time - 2.443) < 0.3);
  // The impulse of the first 15 ms: the record's mean P 2.24, with the relative 2.5-97.5 % scatter of the measured
  // peaks (-18 %, +43 %) as its band. The incompressible projection gets the impulse right, at any C_r.
  const double mean_low = 2.24 * measured.low / measured.median, mean_high = 2.24 * measured.high / measured.median;
  CHECK(coarse.mean_15ms > mean_low);
  CHECK(coarse.mean_15ms < mean_high);
  CHECK(fine_dt.mean_15ms > mean_low);
  CHECK(fine_dt.mean_15ms < mean_high);
  // NOT met (docs/RESULTS.md, the impact pressure): the peak is a one-step spike of order
  // rho u^2 / C_r, above the measured scatter, and it grows as dt is halved. Reported, not asserted, until a scheme
  // brings it inside; a fix turns these into CHECKs.
  WARN(coarse.peak <= measured.high);
  WARN(fine_dt.peak <= coarse.peak + 0.5 * (measured.high - measured.low));
}

}  // namespace riffle
