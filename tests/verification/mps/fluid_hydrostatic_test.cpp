// Verification: still water in a box tank (numerics.md 6.2 item 2 and amendment 4). The exact answer of the
// continuum problem is p = rho g (H - z); the discrete scheme puts the Dirichlet condition p = 0 at the centres of
// the surface particles, half a spacing below the real surface, so its exact discrete answer is the offset line
// rho g (H - l0/2 - z): GC reproduces a linear field exactly and the HL Laplacian of a linear field vanishes on the
// lattice, so on the initial lattice the offset line solves the PPE. Anything else is scheme error.
//
// Sizes (CTest time): l0 = 10 mm and a 6 x 3 column of 10 layers (180 fluid particles) so that 10 s at the
// step cap dt = 2 ms are 5000 steps (amendment 6: at least 10 s, short runs hide the late zig-zag mode); the
// convergence study uses a 3 x 2 l0 column (the side walls are exact for hydrostatics: their pressure is
// extrapolated with rho g per pair) at H/l0 = 5, 10, 15.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "engine/run/simulation.hpp"
#include "systems/physics/mps/hypre_pressure_solver.hpp"
#include "tests/support/fluid_support.hpp"

namespace riffle {
namespace {

using test::kG;
using test::kRho;

struct PressureErrors {
  double rms_offset = 0.0;  ///< RMS(p - rho g (H - l0/2 - z)) / (rho g H)
  double rms_exact = 0.0;   ///< RMS(p - rho g (H - z)) / (rho g H)
  double mean_exact = 0.0;  ///< mean(p - rho g (H - z)) / (rho g l0)
  std::size_t samples = 0;
};

/// Over fluid particles at least 2 l0 below the surface (z <= H - 2 l0).
PressureErrors pressure_errors(const test::FluidRun& run, double depth) {
  const double l0 = run.model.fluid.spacing;
  const FluidParticles& fluid = *run.world.fluid;
  PressureErrors e;
  double sum_offset = 0.0, sum_exact = 0.0, sum_mean = 0.0;
  for (std::size_t i = 0; i < run.fluid_count(); ++i) {
    const double z = fluid.position[i].z();
    if (z > depth - 2.0 * l0) continue;
    const double exact = kRho * kG * (depth - z);
    const double offset = kRho * kG * (depth - 0.5 * l0 - z);
    sum_offset += std::pow(fluid.pressure[i] - offset, 2);
    sum_exact += std::pow(fluid.pressure[i] - exact, 2);
    sum_mean += fluid.pressure[i] - exact;
    ++e.samples;
  }
  const double n = static_cast<double>(e.samples);
  e.rms_offset = std::sqrt(sum_offset / n) / (kRho * kG * depth);
  e.rms_exact = std::sqrt(sum_exact / n) / (kRho * kG * depth);
  e.mean_exact = sum_mean / n / (kRho * kG * l0);
  return e;
}

/// Largest displacement of a fluid particle from its start (`start` indexed by id: slots are reordered by cell).
double max_drift(const test::FluidRun& run, const std::vector<Vec3>& start) {
  const std::vector<Vec3> now = run.fluid_positions_by_id();
  double drift = 0.0;
  for (std::size_t id = 0; id < start.size(); ++id) drift = std::max(drift, (now[id] - start[id]).norm());
  return drift;
}

/// Still water packed off the lattice at water's viscosity (l0 = 1 cm, dt = 2 ms, 6 s): a tank `size` filled up to
/// `depth`, open at the top if `open_top`, with `fluid_lines` added to [fluid].
std::string packed_still_water(const Vec3& size, double depth, bool open_top, const std::string& fluid_lines = "") {
  std::ostringstream text;
  text << "[run]\nend_time = 6.0\ndt = 2.0e-3\ngravity = [0.0, 0.0, -9.81]\n[materials.glass]\ndensity = 2500.0\n"
       << "[tank]\nsize = [" << size.x() << ", " << size.y() << ", " << size.z() << "]\n"
       << (open_top ? "open_faces = [\"z_max\"]\n" : "") << "wall_material = \"glass\"\n"
       << "[fluid]\nspacing = 0.01\nkinematic_viscosity = 1.0e-6\ninitial_arrangement = \"packed\"\n" << fluid_lines
       << "[[fluid.boxes]]\nlow = [0.0, 0.0, 0.0]\nhigh = [" << size.x() << ", " << size.y() << ", " << depth << "]\n";
  return text.str();
}

}  // namespace

TEST_CASE("hydrostatic column holds still for 5000 steps with the offset-line pressure") {
  const double l0 = 0.01, depth = 0.10;
  Model model = test::fluid_model(Vec3(0.06, 0.03, 0.14), l0, {ParticleBoxModel{Vec3::Zero(), Vec3(0.06, 0.03, depth)}});
  model.dt = 2.0e-3;  // the step cap; at rest the Courant limit never binds. gamma = 12/s * 2 ms = 0.024 (amendment 2)
  test::FluidRun run(std::move(model));
  const std::size_t count = run.fluid_count();
  REQUIRE(count == 180);
  const std::size_t top_layer = 6 * 3;
  const std::vector<Vec3> start = run.fluid_positions_by_id();

  std::int64_t steps = 0;
  std::size_t spurious_flags = 0, missed_top = 0;
  double ke_max = 0.0, density_error_max = 0.0;
  while (run.world.time < 10.0 - 1e-12) {
    REQUIRE_MESSAGE(run.step(), run.diagnosis());
    ++steps;
    const FluidSummary& summary = *run.world.fluid_summary;
    ke_max = std::max(ke_max, summary.kinetic_energy);
    density_error_max = std::max(density_error_max, std::abs(summary.mean_density_ratio - 1.0));
    if (steps % 50 == 0) {  // surface flags: exactly the top layer (initial z = H - l0/2)
      for (std::size_t i = 0; i < count; ++i) {
        const bool top = start[run.world.fluid->id[i]].z() > depth - l0;
        const bool flagged = run.world.fluid->free_surface[i] != 0;
        if (flagged && !top) ++spurious_flags;
        if (!flagged && top) ++missed_top;
      }
    }
  }
  const FluidSummary& summary = *run.world.fluid_summary;
  const PressureErrors e = pressure_errors(run, depth);
  const double drift = max_drift(run, start);
  const double mass = kRho * l0 * l0 * l0 * static_cast<double>(count);
  MESSAGE("steps " << steps << ", pressure RMS vs offset line " << e.rms_offset << " rho g H (" << e.samples
                   << " particles), vs rho g (H - z) " << e.rms_exact << ", final drift " << drift / l0 << " l0, KE max "
                   << ke_max << " J, final " << summary.kinetic_energy << " J, max |mean n/n0 - 1| "
                   << density_error_max << ", spurious flags " << spurious_flags << ", unflagged top " << missed_top
                   << ", surface count " << summary.surface_count);

  CHECK(steps >= 5000);
  // Drift: numerics 6.2 item 2 sets the target 0.1 l0 (limit 0.5 l0).
  CHECK(drift < 0.1 * l0);
  // Pressure: a particle displaced vertically by dz from the lattice sees rho g dz more or less than the line;
  // with the drift bound 0.1 l0 the RMS can be at most rho g 0.1 l0, i.e. 0.1 l0 / H of rho g H (1 %).
  CHECK(e.rms_offset < 0.1 * l0 / depth);
  // Kinetic energy decays: the final KE is below that of a uniform velocity that would carry the column 0.01 l0
  // over the run (0.5 M (0.01 l0 / 10 s)^2 = 9e-12 J), and below its own maximum.
  CHECK(summary.kinetic_energy < 0.5 * mass * std::pow(0.01 * l0 / 10.0, 2));
  CHECK(summary.kinetic_energy <= ke_max);
  // Only the top layer is flagged, all the time (numerics 6.2; beta = 0.93 flags exactly layer 1 in the prototype).
  CHECK(spurious_flags == 0);
  CHECK(missed_top == 0);
  CHECK(summary.surface_count == top_layer);
  // |n/n0 - 1| < 1 % (numerics 6.2).
  CHECK(density_error_max < 0.01);
}

TEST_CASE("hydrostatic pressure error against rho g (H - z) converges at first order") {
  // The offset of the Dirichlet condition makes the error against the continuum line rho g l0/2 at every depth:
  // e(l0) = l0 / (2H) + eps, with eps the deviation from the offset line. For a resolution ratio of 3 the observed
  // order ln(e1/e3)/ln 3 stays within 1 +- 0.15 as long as eps is below 8 % of the offset term at both ends
  // (ln(1.08/0.92)/ln 3 = 0.146), i.e. a vertical position error below 0.04 l0, inside the 0.1 l0 drift target.
  const double depth = 0.06;
  const std::vector<int> layers = {5, 10, 15};
  std::vector<double> spacing, error, offset_error;
  for (int n : layers) {
    const double l0 = depth / n;
    Model model = test::fluid_model(Vec3(3 * l0, 2 * l0, depth + 4 * l0), l0,
                                    {ParticleBoxModel{Vec3::Zero(), Vec3(3 * l0, 2 * l0, depth)}});
    model.dt = 1.0e-3 * std::sqrt(l0 / 0.005);  // 1 ms at 5 mm (amendment 3), scaled with the time sqrt(l0/g)
    test::FluidRun run(std::move(model));
    // 0.3 s of settling, then the error averaged over the last 0.1 s.
    REQUIRE_MESSAGE(run.run_until(0.2), run.diagnosis());
    double sum = 0.0, sum_offset = 0.0, sum_mean = 0.0;
    int samples = 0;
    while (run.world.time < 0.3 - 1e-12) {
      REQUIRE_MESSAGE(run.step(), run.diagnosis());
      const PressureErrors e = pressure_errors(run, depth);
      sum += e.rms_exact;
      sum_offset += e.rms_offset;
      sum_mean += e.mean_exact;
      ++samples;
    }
    spacing.push_back(l0);
    error.push_back(sum / samples);
    offset_error.push_back(sum_offset / samples);
    MESSAGE("H/l0 = " << n << ": RMS vs rho g (H - z) " << error.back() << " rho g H (l0/2H = " << l0 / (2 * depth)
                      << "), mean (p - rho g (H - z)) " << sum_mean / samples << " rho g l0, RMS vs offset line "
                      << offset_error.back());
    // The continuum error is the half-spacing offset: mean of p - rho g (H - z) = -rho g l0/2, to the 8 % allowed
    // above.
    CHECK(std::abs(sum_mean / samples + 0.5) < 0.5 * 0.08);
  }
  const double order = std::log(error.front() / error.back()) / std::log(spacing.front() / spacing.back());
  const double order_mid = std::log(error[0] / error[1]) / std::log(spacing[0] / spacing[1]);
  MESSAGE("observed order " << order << " (5 -> 15 layers), " << order_mid << " (5 -> 10)");
  CHECK(std::abs(order - 1.0) < 0.15);
}

}  // namespace riffle

namespace riffle {

// The conservative gradient ([fluid.schemes] conservative_gradient) in the only water it is for, a sealed box full
// of it: G is taken out before the sum form, so hydrostatics is exact for it on any arrangement (docs/FLUID.md, "A
// momentum-conserving gradient"), and still water must hold still to the bounds of the free-surface column above
// (drift 0.1 l0; final KE below that of a uniform velocity carrying the water that 0.1 l0 over the run). The
// pressure's level in a sealed box is set by the solve's compressibility, not by a surface, so its shape is checked:
// p + rho g z is the same at every particle to 0.1 l0 / H of rho g H (the bound a vertical displacement of 0.1 l0
// would give, as above); and the gradient each particle applies is rho g to 1e-6 (q constant: the sum vanishes up
// to the solve's tolerance). Measured: drift 0.053 l0, shape 5e-9, gradient 6e-8, KE 1e-11 J (bound 9e-10 J). GC in
// the same sealed box fails three of these (drift 0.23 l0, |grad p - rho g| up to 0.9 rho g, KE 3e-8 J; measured
// once with the two scheme lines flipped).
TEST_CASE("a sealed box full of still water holds still with the conservative gradient") {
  const double l0 = 0.01, height = 0.10;
  Model model = test::fluid_model(Vec3(0.06, 0.03, height), l0, {ParticleBoxModel{Vec3::Zero(), Vec3(0.06, 0.03, height)}});
  model.tank.open_faces.clear();
  model.dt = 2.0e-3;
  model.fluid.schemes.conservative_gradient = true;
  model.fluid.schemes.gradient_correction = false;
  test::FluidRun run(std::move(model));
  REQUIRE(run.fluid_count() == 6 * 3 * 10);
  const std::vector<Vec3> start = run.fluid_positions_by_id();
  REQUIRE_MESSAGE(run.run_until(10.0), run.diagnosis());
  const FluidParticles& fluid = *run.world.fluid;
  const std::size_t count = run.fluid_count();
  double mean = 0.0;
  for (std::size_t i = 0; i < count; ++i) mean += fluid.pressure[i] + kRho * kG * fluid.position[i].z();
  mean /= static_cast<double>(count);
  double squared = 0.0, worst_gradient = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    squared += std::pow(fluid.pressure[i] + kRho * kG * fluid.position[i].z() - mean, 2);
    worst_gradient = std::max(worst_gradient, (fluid.pressure_gradient[i] - Vec3(0.0, 0.0, -kRho * kG)).norm());
  }
  const double rms_shape = std::sqrt(squared / static_cast<double>(count)) / (kRho * kG * height);
  const double drift = max_drift(run, start);
  const double mass = kRho * l0 * l0 * l0 * static_cast<double>(count);
  MESSAGE("sealed box, conservative gradient: drift " << drift / l0 << " l0, RMS of p + rho g z about its mean "
                                                      << rms_shape << " rho g H, worst |grad p - rho g| "
                                                      << worst_gradient / (kRho * kG) << " rho g, final KE "
                                                      << run.world.fluid_summary->kinetic_energy << " J");
  CHECK(run.world.fluid_summary->surface_count == 0);
  CHECK(drift < 0.1 * l0);
  CHECK(rms_shape < 0.1 * l0 / height);
  CHECK(worst_gradient < 1e-6 * kRho * kG);
  CHECK(run.world.fluid_summary->kinetic_energy < 0.5 * mass * std::pow(0.1 * l0 / 10.0, 2));
}

// A sealed box full of water has no free-surface particle, so no p = 0 anywhere: its pressure's level is set only by
// the compressibility term, and clamping p < 0 at zero (the default, a free surface's condition) cut an arbitrary
// level. On the lattice that did no harm; off it (a packed start), the clamped water at water's viscosity left rest:
// in this box its kinetic energy fell to 7e-8 J and then grew to 5e-5 J between 3.5 and 6 s (max speed 6 cm/s). With
// no energy put in, still water's kinetic energy cannot grow: the solve does not clamp water without a free surface.
TEST_CASE("a sealed box full of packed still water at water's viscosity comes to rest with the default clamp") {
  const std::string text = packed_still_water(Vec3(0.1, 0.08, 0.08), 0.08, false);
  Model model = parse_scene(text, "sealed_packed.toml");
  REQUIRE(model.fluid.clamp_negative_pressure);  // the default the test is about
  test::FluidRun run(std::move(model));
  REQUIRE(run.fluid_count() == 10 * 8 * 8);
  REQUIRE_MESSAGE(run.run_until(1.0), run.diagnosis());
  const double early_energy = run.world.fluid_summary->kinetic_energy;
  const double early_speed = run.world.fluid_summary->max_speed;
  double largest_energy = 0.0;
  while (run.world.time < 6.0 - 1e-9) {
    REQUIRE_MESSAGE(run.step(), run.diagnosis());
    CHECK(run.world.fluid_summary->surface_count == 0);
    largest_energy = std::max(largest_energy, run.world.fluid_summary->kinetic_energy);
  }
  MESSAGE("packed sealed box: KE " << early_energy << " J at 1 s, largest after " << largest_energy << " J, "
                                   << run.world.fluid_summary->kinetic_energy << " J at 6 s; max speed "
                                   << early_speed << " m/s at 1 s, " << run.world.fluid_summary->max_speed
                                   << " m/s at 6 s");
  // Decaying (measured: 3.6e-9 J at 1 s, 1.8e-9 J at 6 s, never above the 1 s value); a quarter allowed for the
  // exchange with the energy the density term stores in the arrangement.
  CHECK(largest_energy <= 1.25 * early_energy);
  CHECK(run.world.fluid_summary->kinetic_energy < early_energy);
  CHECK(run.world.fluid_summary->max_speed <= early_speed);
}

// Under a free surface, packed water at water's viscosity leaves rest (the density term at the surface: docs/FLUID.md,
// "A packed start"): this column's kinetic energy fell to 2.4e-8 J by 2.5 s and grew to 5.8e-5 J at 6 s (largest
// speed 0.11 m/s). The particle-scale viscosity acts on the particles' scatter about their neighbours' linear field
// only; with it the column comes to rest (measured: 3.8e-8 J at 1 s, 3.5e-9 J at 6 s), its pressure hydrostatic.
TEST_CASE("packed still water under a free surface comes to rest with the particle-scale viscosity") {
  const std::string text = packed_still_water(Vec3(0.12, 0.06, 0.10), 0.06, true, "scatter_viscosity = 2.0\n");
  test::FluidRun run(parse_scene(text, "packed_column.toml"));
  REQUIRE_MESSAGE(run.run_until(1.0), run.diagnosis());
  const double early_energy = run.world.fluid_summary->kinetic_energy;
  double largest_energy = 0.0;
  while (run.world.time < 6.0 - 1e-9) {
    REQUIRE_MESSAGE(run.step(), run.diagnosis());
    largest_energy = std::max(largest_energy, run.world.fluid_summary->kinetic_energy);
  }
  const double depth = 0.06;
  const PressureErrors errors = pressure_errors(run, depth);
  MESSAGE("packed column with the particle-scale viscosity: KE " << early_energy << " J at 1 s, largest after "
                                                                 << largest_energy << " J, "
                                                                 << run.world.fluid_summary->kinetic_energy
                                                                 << " J at 6 s; pressure RMS about the offset line "
                                                                 << errors.rms_offset << " rho g H");
  CHECK(largest_energy <= 1.25 * early_energy);
  CHECK(run.world.fluid_summary->kinetic_energy < early_energy);
  CHECK(run.world.fluid_summary->max_speed < 0.01 * std::sqrt(kG * 0.01));
  CHECK(errors.rms_offset < 0.02);
}

// With a free surface the conservative gradient is unstable (a surface particle lifted by dz gains q = rho g dz and,
// its neighbourhood cut, a push up of order g dz / l0: the column above blows up within 0.2 s), so the run stops
// with that diagnosis at the first step that flags a surface particle instead of blowing up.
TEST_CASE("the conservative gradient stops a run at its first free-surface particle, naming it") {
  const double l0 = 0.01;
  Model model = test::fluid_model(Vec3(0.06, 0.03, 0.14), l0, {ParticleBoxModel{Vec3::Zero(), Vec3(0.06, 0.03, 0.10)}});
  model.fluid.schemes.conservative_gradient = true;
  model.fluid.schemes.gradient_correction = false;
  test::FluidRun run(std::move(model));
  CHECK_FALSE(run.step());
  CHECK(run.world.step == 1);
  CHECK(run.world.step_status.problem == StepProblem::kSurfaceWithConservativeGradient);
  CHECK(run.world.step_status.position.z() > 0.09);  // a particle of the top layer
  const std::string message = diagnosis(run.world, run.model);
  CAPTURE(message);
  CHECK(message.find("fluid particle id " + std::to_string(run.world.step_status.entity)) != std::string::npos);
  CHECK(message.find("is flagged as free surface") != std::string::npos);
  CHECK(message.find("conservative_gradient is for water without a free surface") != std::string::npos);
}

}  // namespace riffle

namespace riffle {

// hypre's BoomerAMG-PCG ([fluid] preconditioner = "boomeramg") solves the same system to the same criterion: still
// water holds still on it as on the in-house PCG, and the two pressure fields differ by no more than the solves'
// tolerance allows. With |r| <= tol |b| each solution is within cond(M) tol of the exact one in the relative norm;
// cond(M) of the column's PPE is of order (H / l0)^2 = 100, so 1e-8 leaves them within 1e-6 of each other: checked
// against 1e-5 rho g H after 500 steps, over which the particles, moved by the two fields, stay within that.
TEST_CASE("hydrostatic column on hypre's BoomerAMG-PCG: the in-house solve's pressure, and still") {
  if (!hypre_available()) return;  // the scene reader's refusal is a unit test
  const double l0 = 0.01, depth = 0.10;
  const auto column = [&](FluidModel::Preconditioner preconditioner) {
    Model model =
        test::fluid_model(Vec3(0.06, 0.03, 0.14), l0, {ParticleBoxModel{Vec3::Zero(), Vec3(0.06, 0.03, depth)}});
    model.dt = 2.0e-3;
    model.fluid.preconditioner = preconditioner;
    return model;
  };
  test::FluidRun in_house(column(FluidModel::Preconditioner::kTwoLevel));
  test::FluidRun amg(column(FluidModel::Preconditioner::kBoomerAmg));
  const std::vector<Vec3> start = amg.fluid_positions_by_id();
  std::int64_t largest_iterations = 0;
  for (int step = 0; step < 500; ++step) {
    REQUIRE_MESSAGE(in_house.step(), in_house.diagnosis());
    REQUIRE_MESSAGE(amg.step(), amg.diagnosis());
    REQUIRE(amg.world.fluid_summary->solver_converged);
    largest_iterations = std::max(largest_iterations, amg.world.fluid_summary->solver_iterations);
  }
  // The same particle by id in both runs.
  std::vector<double> pressure_by_id(in_house.fluid_count()), amg_pressure_by_id(amg.fluid_count());
  for (std::size_t i = 0; i < in_house.fluid_count(); ++i)
    pressure_by_id[in_house.world.fluid->id[i]] = in_house.world.fluid->pressure[i];
  for (std::size_t i = 0; i < amg.fluid_count(); ++i)
    amg_pressure_by_id[amg.world.fluid->id[i]] = amg.world.fluid->pressure[i];
  double largest_difference = 0.0;
  for (std::size_t id = 0; id < pressure_by_id.size(); ++id)
    largest_difference = std::max(largest_difference, std::abs(pressure_by_id[id] - amg_pressure_by_id[id]));
  const PressureErrors e = pressure_errors(amg, depth);
  const double drift = max_drift(amg, start);
  MESSAGE("BoomerAMG-PCG: largest |p - p_in-house| " << largest_difference / (kRho * kG * depth)
                                                    << " rho g H, RMS vs offset line " << e.rms_offset << ", drift "
                                                    << drift / l0 << " l0, at most " << largest_iterations
                                                    << " iterations a step");
  CHECK(largest_difference < 1e-5 * kRho * kG * depth);
  CHECK(e.rms_offset < 0.1 * l0 / depth);  // the bounds of the 5000-step column above
  CHECK(drift < 0.1 * l0);
}

// Deep still water (docs/FLUID.md, "Deep water's step limit"): a column 50 layers deep (40 x 40 x 250 mm at
// l0 = 5 mm, water's viscosity) at run.dt = 2 ms, where dt sqrt(g / l0) = 0.089 makes X = 4.4: with the step as
// asked a vertical motion grows from the surface down (0.2 m/s by 2 s); the default hydrostatic limit
// (dt <= 2 sqrt(l0 / g) l0 / H = 0.90 ms) keeps it still. The bound on the speed, 5e-4 m/s (2e-3 of the particle
// scale's sqrt(g l0)), is the top of the bounded noise the marginal limit 2.5 leaves (2-5e-4 m/s; 2 leaves below 1e-4)
// and a fiftieth of what the unlimited column reaches within 0.7 s.
TEST_CASE("deep still water: the hydrostatic step limit keeps a column 50 layers deep still, which dt = 2 ms blows up") {
  const double l0 = 0.005, depth = 0.25;
  const auto column = [&](double hydrostatic_number) {
    Model model =
        test::fluid_model(Vec3(0.04, 0.04, 0.255), l0, {ParticleBoxModel{Vec3::Zero(), Vec3(0.04, 0.04, depth)}});
    model.dt = 2.0e-3;
    model.end_time = 2.0;
    model.fluid.hydrostatic_number = hydrostatic_number;
    return model;
  };
  SUBCASE("with the default limit it stays still for 2 s") {
    test::FluidRun run(column(FluidModel{}.hydrostatic_number));
    REQUIRE(run.fluid_count() == 8 * 8 * 50);
    double late_speed = 0.0;
    while (run.world.time < 2.0 - 1e-12) {
      REQUIRE_MESSAGE(run.step(), run.diagnosis());
      if (run.world.time > 1.0) late_speed = std::max(late_speed, run.world.fluid_summary->max_speed);
    }
    // The step is the limit's: H = 49 l0 of centres plus l0.
    CHECK(run.world.last_step.limit == StepLimit::kHydrostatic);
    CHECK(run.world.last_step.dt == doctest::Approx(2.0 * std::sqrt(l0 / kG) * l0 / depth).epsilon(2e-3));
    MESSAGE("largest speed over 1-2 s with the limit: " << late_speed << " m/s, dt " << run.world.last_step.dt);
    CHECK(late_speed < 5e-4);
  }
  SUBCASE("without it (hydrostatic_number = 100) the same column runs away within 1.5 s") {
    test::FluidRun run(column(100.0));
    double largest = 0.0;
    bool failed = false;
    while (run.world.time < 1.5 - 1e-12 && largest < 1e-2) {
      if (!run.step()) {
        failed = true;
        break;
      }
      largest = std::max(largest, run.world.fluid_summary->max_speed);
    }
    MESSAGE("without the limit: largest speed " << largest << " m/s by t = " << run.world.time << " s");
    CHECK((failed || largest >= 1e-2));
  }
}

}  // namespace riffle
