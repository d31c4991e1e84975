// Speed against error for the MPS fluid (docs/BENCHMARKS.md, "Fluid (MPS)"). Scenes are built in code
// (tests/support/fluid_support.hpp), not read from scene files.
//
//   riffle_fluid_accuracy accuracy OUT.csv [--threads N] [--fine] [--cap SECONDS] [--only hydro|dam|variants]
//                                  [--hydro-time SECONDS] [--rate DENSITY_RATE] [--reference MARTIN_MOYCE.csv]
//   riffle_fluid_accuracy sloshing OUT.csv [--threads 1,2] [--time 0.3] [--from 0] [--rate DENSITY_RATE]
//                                  [--sort STEPS (fluid.sort_every)] [--skin RATIO (fluid.neighbour_skin)]
//                                  [--narrow-skin RATIO (fluid.neighbour_skin_narrow)]
//   riffle_fluid_accuracy still L0 DT_CAP TIME EVERY [key=value ...]   (history of the still-water tank, for diagnosis)
//
// accuracy: (a) hydrostatic tank 0.06 x 0.03 m, H = 0.06 m of still water, open top, --hydro-time (1 s) simulated,
//   at l0 = 10, 7.5, 5 mm (and 2.5 mm with --fine): RMS over particles at least 2 l0 below the surface of
//   p - rho g (H - z) and of p - rho g (H - l0/2 - z) (the exact discrete answer, numerics amendment 4), both over
//   rho g H and averaged over the last 0.1 s; the largest displacement of a fluid particle over l0;
//   (b) dam break (Martin & Moyce 1952, n^2 = 2): column a x 2a, a = 0.1 m, in a tank 5a long, a slab 4 l0 thick
//   in y between walls, open top, to T = t sqrt(2g/a) = 3.4 (the table ends at 3.33), at l0 = a/10, a/15, a/20
//   (and a/25, a/30 with --fine):
//   RMS of the surge front Z(T) against the table, raw and after the best constant time shift dT (positive: the
//   simulation leads); front = the rightmost fluid particle below 0.5 a with another fluid particle within 1.5 l0,
//   Z = (x + l0/2)/a;
//   (c) both cases at the middle and the finest of the three resolutions (7.5 and 5 mm, a/15 and a/20) with each
//   enhanced scheme off in turn (HS, ECS, HL, GC, DS) and the PPE tolerance 1e-6 and 1e-4 instead of 1e-8.
//   One CSV row per run (rewritten after every run, so a partial sweep keeps its rows). A run whose step status is
//   not ok, or that passes the wall-clock cap, is reported unstable with the simulated time it reached; a still-water
//   run in which a particle moved more than l0/2 is reported unstable ("drift") with its error metrics kept.
// sloshing: the seed's tank 0.24 x 0.16 m (0.12 m high), 6 cm of water at l0 = 5 mm, x = -A sin(2 pi f t),
//   A = 1 cm, f = 1.7 Hz, one period of ramp, for --time seconds from --from (an untimed lead-in) at each thread
//   count: the timing table per system (items per second from the timers) and the projected wall seconds per
//   simulated second.
#include <spdlog/spdlog.h>
#include <sys/resource.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "engine/core/timers.hpp"
#include "tests/support/fluid_support.hpp"

namespace {

using namespace riffle;

constexpr double kG = 9.81;
constexpr double kRho = 1000.0;

double cpu_seconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

const char* problem_name(StepProblem problem) {
  switch (problem) {
    case StepProblem::kNone: return "ok";
    case StepProblem::kNonFinite: return "non_finite";
    case StepProblem::kLeftDomain: return "left_domain";
    case StepProblem::kSolverFailed: return "solver_failed";
    case StepProblem::kTimeStepCollapse: return "dt_collapse";
    case StepProblem::kTooManyEscaped: return "too_many_escaped";
    case StepProblem::kSurfaceWithConservativeGradient: return "surface_with_conservative_gradient";
  }
  return "unknown";
}

std::size_t fluid_count(const World& world) {
  return static_cast<std::size_t>(
      std::count(world.fluid->kind.begin(), world.fluid->kind.end(), static_cast<std::int32_t>(FluidKind::kFluid)));
}

/// One run's results: a CSV row.
struct Row {
  std::string case_name, variant;
  double spacing = 0.0;
  std::size_t particles = 0, all_particles = 0;
  std::int64_t steps = 0;
  double end_time = 0.0, reached_time = 0.0, wall = 0.0, cpu = 0.0;
  double ppe_mean = 0.0;
  std::int64_t ppe_max = 0, ppe_unconverged = 0;
  double dt_mean = 0.0;
  // hydrostatic
  double rms_exact = NAN, rms_offset = NAN, drift = NAN;
  // dam break
  double front_raw = NAN, front_shifted = NAN, front_shift = NAN, front_z3 = NAN;
  double unstable_from = NAN;  ///< [s] the failed step's time, or when a still-water particle first moved > l0/2
  bool stable = true;
  std::string status = "ok";
  std::map<std::string, double> system_seconds;
};

/// Steps `run` to `end_time` or a failure or the wall-clock cap; `observe` is called after every good step.
template <class Observe>
void step_run(test::FluidRun& run, double end_time, double cap, Row& row, Observe&& observe) {
  const auto start = Clock::now();
  const double cpu_start = cpu_seconds();
  double iterations = 0.0;
  while (run.world.time < end_time - 1e-12) {
    run.stepper->step();
    if (!run.world.step_status.ok()) {
      row.stable = false;
      row.status = problem_name(run.world.step_status.problem);
      break;
    }
    ++row.steps;
    const FluidSummary& summary = *run.world.fluid_summary;
    iterations += static_cast<double>(summary.solver_iterations);
    row.ppe_max = std::max<std::int64_t>(row.ppe_max, summary.solver_iterations);
    if (!summary.solver_converged) ++row.ppe_unconverged;
    observe();
    if (seconds_since(start) > cap) {
      row.stable = false;
      row.status = "wall_cap";
      break;
    }
  }
  row.wall = seconds_since(start);
  row.cpu = cpu_seconds() - cpu_start;
  row.reached_time = run.world.time;
  if (!row.stable && std::isnan(row.unstable_from)) row.unstable_from = run.world.time;
  row.ppe_mean = row.steps > 0 ? iterations / static_cast<double>(row.steps) : 0.0;
  row.dt_mean = row.steps > 0 ? run.world.time / static_cast<double>(row.steps) : 0.0;
  row.particles = fluid_count(run.world);
  row.all_particles = run.world.fluid->size();
  for (const SystemTimer& timer : run.stepper->timers()) row.system_seconds[timer.name] += timer.total_seconds;
}

/// --rate: a density_relaxation_rate for every accuracy run instead of the model's default (0 = keep the default).
double g_density_rate = 0.0;
std::int64_t g_sort_every = -1;  // < 0: the model's default
double g_skin = -1.0;            // < 0: the model's default
double g_narrow_skin = -1.0;     // < 0: the model's default

void apply_overrides(FluidModel& fluid) {
  if (g_density_rate > 0.0) fluid.density_relaxation_rate = g_density_rate;
  if (g_sort_every >= 0) fluid.sort_every = g_sort_every;
  if (g_skin >= 0.0) fluid.neighbour_skin_ratio = g_skin;
  if (g_narrow_skin >= 0.0) fluid.narrow_neighbour_skin_ratio = g_narrow_skin;
}

struct Variant {
  std::string name;
  void (*apply)(FluidModel&);
};

const std::vector<Variant>& variants() {
  static const std::vector<Variant> all = {
      {"no_HS", [](FluidModel& f) { f.schemes.higher_order_source = false; }},
      {"no_ECS", [](FluidModel& f) { f.schemes.error_compensating_source = false; }},
      {"no_HL", [](FluidModel& f) { f.schemes.higher_order_laplacian = false; }},
      {"no_GC", [](FluidModel& f) { f.schemes.gradient_correction = false; }},
      {"no_DS", [](FluidModel& f) { f.schemes.dynamic_stabilisation = false; }},
      {"tol_1e-6", [](FluidModel& f) { f.solver_tolerance = 1e-6; }},
      {"tol_1e-4", [](FluidModel& f) { f.solver_tolerance = 1e-4; }},
  };
  return all;
}

// ---- (a) hydrostatic tank ------------------------------------------------------------------------------------

Row hydrostatic(double l0, const Variant* variant, double cap, double end_time) {
  const double depth = 0.06, average_from = end_time - 0.1;
  const double height = l0 * (std::round(depth / l0) + std::ceil(0.02 / l0 - 1e-9));  // >= 2 cm above the water
  Model model = test::fluid_model(Vec3(0.06, 0.03, height), l0,
                                  {ParticleBoxModel{Vec3::Zero(), Vec3(0.06, 0.03, depth)}});
  model.dt = 1.0e-3 * std::sqrt(l0 / 0.005);  // 1 ms at 5 mm (amendment 3), scaled with sqrt(l0 / g)
  apply_overrides(model.fluid);
  if (variant) variant->apply(model.fluid);
  auto run = std::make_unique<test::FluidRun>(std::move(model));
  Row row;
  row.case_name = "hydrostatic";
  row.variant = variant ? variant->name : "all";
  row.spacing = l0;
  row.end_time = end_time;
  const FluidParticles& fluid = *run->world.fluid;
  std::vector<Vec3> start(fluid.size());
  for (std::size_t i = 0; i < fluid.size(); ++i) start[fluid.id[i]] = fluid.position[i];
  double sum_exact = 0.0, sum_offset = 0.0;
  int samples = 0;
  const double scale = kRho * kG * depth;
  step_run(*run, end_time, cap, row, [&] {
    if (std::isnan(row.unstable_from)) {
      for (std::size_t i = 0; i < fluid.size(); ++i)
        if (fluid.kind[i] == static_cast<std::int32_t>(FluidKind::kFluid) &&
            (fluid.position[i] - start[fluid.id[i]]).squaredNorm() > 0.25 * l0 * l0) {
          row.unstable_from = run->world.time;
          break;
        }
    }
    if (run->world.time < average_from - 1e-12) return;
    double e2 = 0.0, o2 = 0.0;
    int n = 0;
    for (std::size_t i = 0; i < fluid.size(); ++i) {
      if (fluid.kind[i] != static_cast<std::int32_t>(FluidKind::kFluid)) continue;
      const double z = fluid.position[i].z();
      if (z > depth - 2.0 * l0) continue;
      e2 += std::pow(fluid.pressure[i] - kRho * kG * (depth - z), 2);
      o2 += std::pow(fluid.pressure[i] - kRho * kG * (depth - 0.5 * l0 - z), 2);
      ++n;
    }
    if (n == 0) return;
    sum_exact += std::sqrt(e2 / n) / scale;
    sum_offset += std::sqrt(o2 / n) / scale;
    ++samples;
  });
  if (samples > 0) {
    row.rms_exact = sum_exact / samples;
    row.rms_offset = sum_offset / samples;
  }
  double drift = 0.0;
  for (std::size_t i = 0; i < fluid.size(); ++i)
    if (fluid.kind[i] == static_cast<std::int32_t>(FluidKind::kFluid))
      drift = std::max(drift, (fluid.position[i] - start[fluid.id[i]]).norm());
  row.drift = drift / l0;
  // The prototype's criterion for still water (REPORT.md Sec. 1): a particle that moved more than l0/2 means the
  // column did not hold still, even if no step failed.
  if (row.stable && row.drift > 0.5) {
    row.stable = false;
    row.status = "drift";
  }
  if (row.stable) row.unstable_from = NAN;  // moved past l0/2 for a while but came back
  return row;
}

// ---- (b) dam break -------------------------------------------------------------------------------------------

struct Point {
  double t, z;
};

std::vector<Point> read_martin_moyce(const std::string& path) {
  std::ifstream in(path);
  std::vector<Point> table;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || !std::isdigit(static_cast<unsigned char>(line[0]))) continue;
    Point p{};
    if (std::sscanf(line.c_str(), "%lf,%lf", &p.t, &p.z) == 2) table.push_back(p);
  }
  return table;
}

/// Z of the simulated front at T (linear interpolation; the column at rest before T = 0).
double front_at(const std::vector<Point>& series, double t) {
  if (t <= series.front().t) return series.front().z;
  if (t >= series.back().t) return NAN;
  const auto it = std::lower_bound(series.begin(), series.end(), t, [](const Point& p, double v) { return p.t < v; });
  const Point& b = *it;
  const Point& a = *(it - 1);
  return a.z + (b.z - a.z) * (t - a.t) / (b.t - a.t);
}

/// RMS of Z_sim(T - shift) - Z_MM(T) over the table points the simulation covers (NaN if it covers none of them).
double front_rms(const std::vector<Point>& series, const std::vector<Point>& table, double shift, int* covered) {
  double sum = 0.0;
  int n = 0;
  for (const Point& p : table) {
    const double z = front_at(series, p.t - shift);
    if (std::isnan(z)) continue;
    sum += (z - p.z) * (z - p.z);
    ++n;
  }
  if (covered) *covered = n;
  return n > 0 ? std::sqrt(sum / n) : NAN;
}

Row dam_break(double a_over_l0, const Variant* variant, double cap, const std::vector<Point>& table) {
  const double a = 0.1, l0 = a / a_over_l0, width = 4.0 * l0;
  const double time_scale = std::sqrt(2.0 * kG / a);  // T = t sqrt(2 g / a)
  const double end_T = 3.4;
  Model model = test::fluid_model(Vec3(5.0 * a, width, 2.0 * a + 2.0 * l0), l0,
                                  {ParticleBoxModel{Vec3::Zero(), Vec3(a, width, 2.0 * a)}});
  model.dt = 1.0e-3;  // the largest step; the Courant limit (C_r = 0.2) takes over once the front runs
  model.tank.domain_margin = 0.3;
  apply_overrides(model.fluid);
  if (variant) variant->apply(model.fluid);
  auto run = std::make_unique<test::FluidRun>(std::move(model));
  Row row;
  row.case_name = "dam_break";
  row.variant = variant ? variant->name : "all";
  row.spacing = l0;
  row.end_time = end_T / time_scale;
  const FluidParticles& fluid = *run->world.fluid;
  std::vector<Point> series;
  std::vector<std::size_t> low;  // fluid slots below 0.5 a (+ 1.5 l0 for the partner search)
  auto front = [&]() -> double {
    low.clear();
    for (std::size_t i = 0; i < fluid.size(); ++i)
      if (fluid.kind[i] == static_cast<std::int32_t>(FluidKind::kFluid) && fluid.position[i].z() < 0.5 * a + 1.5 * l0)
        low.push_back(i);
    std::sort(low.begin(), low.end(), [&](std::size_t p, std::size_t q) { return fluid.position[p].x() > fluid.position[q].x(); });
    const double reach2 = 1.5 * l0 * 1.5 * l0;
    for (std::size_t k = 0; k < low.size(); ++k) {
      const Vec3& x = fluid.position[low[k]];
      if (x.z() >= 0.5 * a) continue;
      // Partners lie within 1.5 l0 in x: scan the sorted list both ways until the gap exceeds that.
      bool partner = false;
      for (std::size_t m = k + 1; m < low.size() && x.x() - fluid.position[low[m]].x() <= 1.5 * l0 && !partner; ++m)
        partner = (fluid.position[low[m]] - x).squaredNorm() <= reach2;
      for (std::size_t m = k; m-- > 0 && fluid.position[low[m]].x() - x.x() <= 1.5 * l0 && !partner;)
        partner = (fluid.position[low[m]] - x).squaredNorm() <= reach2;
      if (partner) return (x.x() + 0.5 * l0) / a;
    }
    return NAN;
  };
  series.push_back({0.0, front()});
  step_run(*run, row.end_time, cap, row, [&] { series.push_back({run->world.time * time_scale, front()}); });
  int covered = 0;
  row.front_raw = front_rms(series, table, 0.0, &covered);
  if (covered < static_cast<int>(table.size())) row.front_raw = NAN;  // a run that stopped early has no full RMS
  double best = INFINITY, best_shift = NAN;
  for (int k = -50; k <= 600; ++k) {
    const double shift = 1e-3 * k;
    int n = 0;
    const double rms = front_rms(series, table, shift, &n);
    if (n == static_cast<int>(table.size()) && rms < best) {
      best = rms;
      best_shift = shift;
    }
  }
  if (std::isfinite(best)) {
    row.front_shifted = best;
    row.front_shift = best_shift;
  }
  row.front_z3 = front_at(series, 3.0);
  return row;
}

// ---- CSV -----------------------------------------------------------------------------------------------------

std::string number(double v, const char* format = "%.6g") {
  if (std::isnan(v)) return "";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, v);
  return buffer;
}

void write_csv(const std::string& path, const std::vector<Row>& rows, int threads) {
  std::vector<std::string> systems;
  for (const Row& row : rows)
    for (const auto& [name, seconds] : row.system_seconds)
      if (std::find(systems.begin(), systems.end(), name) == systems.end()) systems.push_back(name);
  std::ofstream out(path);
  out << "case,variant,l0,particles,all_particles,threads,steps,end_time,reached_time,dt_mean,wall_s,cpu_s,"
         "ppe_iterations_mean,ppe_iterations_max,ppe_unconverged_steps,rms_vs_rho_g_H_minus_z,"
         "rms_vs_rho_g_H_minus_l0half_minus_z,drift_l0,front_rms_raw,front_rms_shifted,front_shift_T,front_Z_at_T3,"
         "stable,status,unstable_from_t";
  for (const std::string& name : systems) out << ",s_" << name;
  out << "\n";
  for (const Row& r : rows) {
    out << r.case_name << "," << r.variant << "," << number(r.spacing) << "," << r.particles << "," << r.all_particles
        << "," << threads << "," << r.steps << "," << number(r.end_time) << "," << number(r.reached_time) << ","
        << number(r.dt_mean) << "," << number(r.wall, "%.3f") << "," << number(r.cpu, "%.3f") << ","
        << number(r.ppe_mean, "%.2f") << "," << r.ppe_max << "," << r.ppe_unconverged << "," << number(r.rms_exact)
        << "," << number(r.rms_offset) << "," << number(r.drift) << "," << number(r.front_raw) << ","
        << number(r.front_shifted) << "," << number(r.front_shift, "%.3f") << "," << number(r.front_z3) << ","
        << (r.stable ? 1 : 0) << "," << r.status << "," << number(r.unstable_from);
    for (const std::string& name : systems) {
      const auto it = r.system_seconds.find(name);
      out << "," << (it == r.system_seconds.end() ? "" : number(it->second, "%.4f"));
    }
    out << "\n";
  }
}

void print_row(const Row& r) {
  const double time_scale = r.case_name == "dam_break" ? std::sqrt(2.0 * kG / 0.1) : 1.0;
  std::printf("%-12s %-9s l0 %6.4f  N %6zu  steps %6ld  wall %8.2f s  cpu %8.2f s  PPE %6.1f/%4ld  ", r.case_name.c_str(),
              r.variant.c_str(), r.spacing, r.particles, static_cast<long>(r.steps), r.wall, r.cpu, r.ppe_mean,
              static_cast<long>(r.ppe_max));
  if (r.case_name == "hydrostatic")
    std::printf("rms(H-z) %.4g  rms(H-l0/2-z) %.4g  drift %.3g l0", r.rms_exact, r.rms_offset, r.drift);
  else
    std::printf("front rms %.4g  shifted %.4g (dT %+.3f)  Z(3) %.3f", r.front_raw, r.front_shifted, r.front_shift,
                r.front_z3);
  if (!r.stable)
    std::printf("  UNSTABLE: %s at %s %.4g", r.status.c_str(), r.case_name == "dam_break" ? "T" : "t",
                r.unstable_from * time_scale);
  std::printf("\n");
  std::fflush(stdout);
}

int accuracy(const std::string& out, int threads, bool fine, double cap, const std::string& only,
             const std::string& reference, double hydro_time) {
  const std::vector<Point> table = read_martin_moyce(reference);
  if (table.empty()) {
    std::fprintf(stderr, "riffle_fluid_accuracy: cannot read the Martin & Moyce table %s\n", reference.c_str());
    return 1;
  }
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  std::vector<Row> rows;
  auto add = [&](Row row) {
    print_row(row);
    rows.push_back(std::move(row));
    write_csv(out, rows, threads);
  };
  std::vector<double> hydro_spacings = {0.01, 0.0075, 0.005};
  std::vector<double> dam_resolutions = {10.0, 15.0, 20.0};
  if (fine) {
    hydro_spacings.push_back(0.0025);
    dam_resolutions.insert(dam_resolutions.end(), {25.0, 30.0});
  }
  if (only.empty() || only == "hydro")
    for (double l0 : hydro_spacings) add(hydrostatic(l0, nullptr, cap, hydro_time));
  if (only.empty() || only == "dam")
    for (double n : dam_resolutions) add(dam_break(n, nullptr, cap, table));
  // The scheme and tolerance variants at the middle resolution of the required three, then at the finest of them.
  if (only.empty() || only == "variants") {
    for (double l0 : {0.0075, 0.005})
      for (const Variant& v : variants()) add(hydrostatic(l0, &v, cap, hydro_time));
    for (double n : {15.0, 20.0})
      for (const Variant& v : variants()) add(dam_break(n, &v, cap, table));
  }
  std::printf("wrote %s (%zu runs)\n", out.c_str(), rows.size());
  return 0;
}

// ---- still-water history (diagnosis) -------------------------------------------------------------------------

/// The hydrostatic tank at one spacing and step cap, with a history row every `every` simulated seconds: kinetic
/// energy, largest speed, largest displacement, surface count, mean n/n0, PPE iterations. Options (key=value):
/// threads, depth [m] (0.06), preconditioner (jacobi|two_level), tol, rate (density_relaxation_rate [1/s]), re
/// (r_e/l0), and hs, ecs, hl, gc, ds (0 or 1).
int still_history(double l0, double dt, double end_time, double every, const std::map<std::string, std::string>& options) {
  auto option = [&](const char* key, double fallback) {
    const auto it = options.find(key);
    return it == options.end() ? fallback : std::atof(it->second.c_str());
  };
  const int threads = static_cast<int>(option("threads", 1));
  const double depth = option("depth", 0.06);
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  const double height = l0 * (std::round(depth / l0) + std::ceil(0.02 / l0 - 1e-9));
  Model model = test::fluid_model(Vec3(0.06, 0.03, height), l0, {ParticleBoxModel{Vec3::Zero(), Vec3(0.06, 0.03, depth)}});
  model.dt = dt > 0.0 ? dt : 1.0e-3 * std::sqrt(l0 / 0.005);
  FluidModel& f = model.fluid;
  const auto preconditioner = options.find("preconditioner");
  if (preconditioner != options.end() && preconditioner->second == "jacobi")
    f.preconditioner = FluidModel::Preconditioner::kJacobi;
  f.solver_tolerance = option("tol", f.solver_tolerance);
  f.density_relaxation_rate = option("rate", f.density_relaxation_rate);
  f.effective_radius_ratio = option("re", f.effective_radius_ratio);
  f.schemes.higher_order_source = option("hs", 1) != 0;
  f.schemes.error_compensating_source = option("ecs", 1) != 0;
  f.schemes.higher_order_laplacian = option("hl", 1) != 0;
  f.schemes.gradient_correction = option("gc", 1) != 0;
  f.schemes.dynamic_stabilisation = option("ds", 1) != 0;
  auto run = std::make_unique<test::FluidRun>(std::move(model));
  const FluidParticles& fluid = *run->world.fluid;
  std::vector<Vec3> start(fluid.size());
  for (std::size_t i = 0; i < fluid.size(); ++i) start[fluid.id[i]] = fluid.position[i];
  {
    const FluidModel& m = run->model.fluid;
    std::printf("# %s preconditioner, tolerance %g, r_e %g l0, density term %g /s, HS %d ECS %d HL %d GC %d DS %d, %d thread(s)\n",
                m.preconditioner == FluidModel::Preconditioner::kJacobi ? "Jacobi" : "two-level", m.solver_tolerance,
                m.effective_radius_ratio, m.density_relaxation_rate, m.schemes.higher_order_source,
                m.schemes.error_compensating_source, m.schemes.higher_order_laplacian, m.schemes.gradient_correction,
                m.schemes.dynamic_stabilisation, threads);
  }
  std::printf("# still water l0 = %g m, H = %g m, dt cap %g s, %zu fluid particles\n", l0, depth, run->model.dt,
              fluid_count(run->world));
  std::printf("%8s %8s %12s %12s %10s %8s %10s %8s\n", "t", "steps", "KE [J]", "max|u| [m/s]", "drift/l0", "surface",
              "mean n/n0", "PPE it");
  double next = every;
  std::int64_t steps = 0;
  while (run->world.time < end_time - 1e-12) {
    run->stepper->step();
    if (!run->world.step_status.ok()) {
      std::printf("failed: %s at t = %.4f\n", problem_name(run->world.step_status.problem), run->world.time);
      return 3;
    }
    ++steps;
    if (run->world.time >= next - 1e-12) {
      next += every;
      double drift = 0.0;
      for (std::size_t i = 0; i < fluid.size(); ++i)
        if (fluid.kind[i] == static_cast<std::int32_t>(FluidKind::kFluid))
          drift = std::max(drift, (fluid.position[i] - start[fluid.id[i]]).norm());
      const FluidSummary& s = *run->world.fluid_summary;
      std::printf("%8.3f %8ld %12.3e %12.3e %10.4f %8zu %10.5f %8ld\n", run->world.time, static_cast<long>(steps),
                  s.kinetic_energy, s.max_speed, drift / l0, s.surface_count, s.mean_density_ratio,
                  static_cast<long>(s.solver_iterations));
      std::fflush(stdout);
    }
  }
  return 0;
}

// ---- sloshing-tank timing ------------------------------------------------------------------------------------

int sloshing(const std::string& out, const std::vector<int>& thread_counts, double time, double from) {
  std::ofstream csv(out);
  csv << "threads,system,calls,seconds,items,items_per_s,fluid_particle_steps_per_s\n";
  for (int threads : thread_counts) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    const double l0 = 0.005;
    Model model = test::fluid_model(Vec3(0.24, 0.16, 0.12), l0,
                                    {ParticleBoxModel{Vec3::Zero(), Vec3(0.24, 0.16, 0.06)}});
    model.dt = 1.0e-3;
    model.tank.motion.kind = TankMotionModel::Kind::kSinusoidal;
    model.tank.motion.direction = Vec3::UnitX();
    model.tank.motion.amplitude = 0.01;
    model.tank.motion.frequency = 1.7;
    model.tank.motion.ramp_time = 1.0 / 1.7;
    apply_overrides(model.fluid);
    auto run = std::make_unique<test::FluidRun>(std::move(model));
    const std::size_t fluid = fluid_count(run->world);
    // Untimed lead-in to `from` (e.g. past the ramp, into the full-amplitude motion); the timers are read as
    // differences from their values at `from`.
    while (run->world.time < from - 1e-12) {
      run->stepper->step();
      if (!run->world.step_status.ok()) {
        std::printf("sloshing: step failed (%s) at t = %.4f s\n", problem_name(run->world.step_status.problem),
                    run->world.time);
        return 3;
      }
    }
    std::map<std::string, SystemTimer> before;
    for (const SystemTimer& t : run->stepper->timers()) before[t.name] = t;
    std::int64_t steps = 0;
    double iterations = 0.0;
    const auto start = Clock::now();
    const double cpu_start = cpu_seconds();
    while (run->world.time < from + time - 1e-12) {
      run->stepper->step();
      if (!run->world.step_status.ok()) {
        std::printf("sloshing: step failed (%s) at t = %.4f s\n", problem_name(run->world.step_status.problem),
                    run->world.time);
        return 3;
      }
      ++steps;
      iterations += static_cast<double>(run->world.fluid_summary->solver_iterations);
    }
    const double wall = seconds_since(start), cpu = cpu_seconds() - cpu_start;
    std::vector<SystemTimer> timers = run->stepper->timers();
    for (SystemTimer& t : timers) {
      const SystemTimer& b = before[t.name];
      t.calls -= b.calls;
      t.total_seconds -= b.total_seconds;
      t.items -= b.items;
    }
    std::printf("\n## sloshing tank, l0 = 5 mm, %zu fluid particles (%zu with walls and dummies), %d thread(s) "
                "(TBB allows %zu of %d)\n",
                fluid, run->world.fluid->size(), threads,
                tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism),
                tbb::info::default_concurrency());
    const double simulated = run->world.time - from;
    std::printf("%ld steps from t = %.3f to %.3f s, wall %.2f s (cpu %.2f s), %.2f ms/step, PPE iterations mean %.1f\n",
                static_cast<long>(steps), from, run->world.time, wall, cpu, 1e3 * wall / steps, iterations / steps);
    std::printf("projected: %.1f wall s per simulated s; %.3g fluid particle-steps/s for the whole step\n",
                wall / simulated, static_cast<double>(fluid) * steps / wall);
    std::printf("%-28s %8s %10s %10s %14s %14s\n", "system", "calls", "seconds", "share", "items/s", "fluid p-steps/s");
    double total = 0.0;
    for (const SystemTimer& t : timers) total += t.total_seconds;
    for (const SystemTimer& t : timers) {
      if (t.calls == 0) continue;
      const double items_rate = t.total_seconds > 0 ? static_cast<double>(t.items) / t.total_seconds : 0.0;
      const double fluid_rate =
          t.total_seconds > 0 ? static_cast<double>(fluid) * static_cast<double>(t.calls) / t.total_seconds : 0.0;
      std::printf("%-28s %8lu %10.3f %9.1f%% %14.3g %14.3g\n", t.name.c_str(), static_cast<unsigned long>(t.calls),
                  t.total_seconds, 100.0 * t.total_seconds / wall, items_rate, fluid_rate);
      csv << threads << "," << t.name << "," << t.calls << "," << t.total_seconds << "," << t.items << ","
          << items_rate << "," << fluid_rate << "\n";
    }
    std::printf("%-28s %8ld %10.3f %9.1f%% %14s %14.3g\n", "whole step (wall clock)", static_cast<long>(steps), wall,
                100.0, "", static_cast<double>(fluid) * steps / wall);
    csv << threads << ",whole_step," << steps << "," << wall << ",," << "," << static_cast<double>(fluid) * steps / wall
        << "\n";
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  spdlog::set_level(spdlog::level::warn);
  if (argc >= 2 && !std::strcmp(argv[1], "still")) {  // still L0 DT|0 TIME EVERY [key=value ...]
    if (argc < 6) return 1;
    std::map<std::string, std::string> options;
    for (int k = 6; k < argc; ++k) {
      const std::string arg = argv[k];
      const std::size_t eq = arg.find('=');
      if (eq == std::string::npos) {
        std::fprintf(stderr, "riffle_fluid_accuracy still: options are key=value, not %s\n", arg.c_str());
        return 1;
      }
      options[arg.substr(0, eq)] = arg.substr(eq + 1);
    }
    return still_history(std::atof(argv[2]), std::atof(argv[3]), std::atof(argv[4]), std::atof(argv[5]), options);
  }
  if (argc < 3 || (std::strcmp(argv[1], "accuracy") && std::strcmp(argv[1], "sloshing"))) {
    std::fprintf(stderr,
                 "usage: riffle_fluid_accuracy accuracy OUT.csv [--threads N] [--fine] [--cap S] [--only hydro|dam|variants]\n"
                 "                             [--hydro-time S] [--rate R] [--reference martin_moyce.csv]\n"
                 "       riffle_fluid_accuracy sloshing OUT.csv [--threads 1,2] [--time 0.3] [--from 0] [--rate R] [--sort N] [--skin S]\n"
                 "                             [--narrow-skin S]\n"
                 "       riffle_fluid_accuracy still L0 DT_CAP(0 = 1 ms sqrt(l0/5 mm)) TIME EVERY [threads=N depth=H preconditioner=jacobi\n"
                 "                             tol=T rate=R re=R hs=0 ecs=0 hl=0 gc=0 ds=0]\n");
    return 1;
  }
  const std::string mode = argv[1], out = argv[2];
  int threads = 1;
  std::vector<int> thread_counts = {1, 2};
  bool fine = false;
  double cap = 300.0, time = 0.3, hydro_time = 1.0, from = 0.0;
  std::string only, reference = "../shared/refdata/martin_moyce_1952_surge_front_n2_2.csv";
  for (int k = 3; k < argc; ++k) {
    const std::string arg = argv[k];
    const bool has_value = k + 1 < argc;
    if (arg == "--threads" && has_value) {
      const std::string value = argv[++k];
      threads = std::atoi(value.c_str());
      thread_counts.clear();
      std::stringstream list(value);
      std::string item;
      while (std::getline(list, item, ',')) thread_counts.push_back(std::atoi(item.c_str()));
    } else if (arg == "--fine") {
      fine = true;
    } else if (arg == "--cap" && has_value) {
      cap = std::atof(argv[++k]);
    } else if (arg == "--only" && has_value) {
      only = argv[++k];
    } else if (arg == "--reference" && has_value) {
      reference = argv[++k];
    } else if (arg == "--from" && has_value) {
      from = std::atof(argv[++k]);
    } else if (arg == "--rate" && has_value) {
      g_density_rate = std::atof(argv[++k]);
    } else if (arg == "--sort" && has_value) {
      g_sort_every = std::atoll(argv[++k]);
    } else if (arg == "--skin" && has_value) {
      g_skin = std::atof(argv[++k]);
    } else if (arg == "--narrow-skin" && has_value) {
      g_narrow_skin = std::atof(argv[++k]);
    } else if (arg == "--hydro-time" && has_value) {
      hydro_time = std::atof(argv[++k]);
    } else if (arg == "--time" && has_value) {
      time = std::atof(argv[++k]);
    } else {
      std::fprintf(stderr, "riffle_fluid_accuracy: unknown argument %s\n", arg.c_str());
      return 1;
    }
  }
  if (mode == "accuracy") return accuracy(out, threads, fine, cap, only, reference, hydro_time);
  return sloshing(out, thread_counts, time, from);
}
