// Lubrication between a grain and a wall and between two grains (systems/coupling/solid_lubrication, docs/COUPLING.md
// "Lubrication"), run as the engine runs it: the systems of one DEM sub-step on a World, the water's samples set by
// hand (still water around a wet grain), so that nothing but the grain-side physics is tested.
//   * a sphere moving towards a wall: drag law + lubrication against Brenner's (1961) exact series;
//   * two grains closing: equal and opposite, and the pair law;
//   * a heavy grain thrown at a wall in a very viscous fluid: no blow-up, no tunnelling, no energy gained;
//   * wet restitution against Legendre, Zenit, Daniel & Guiraud (2006): e/e_dry = exp(-35/St).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "components/world.hpp"
#include "engine/scene/scene.hpp"
#include "systems/coupling/solid_drag.hpp"
#include "systems/coupling/solid_lubrication.hpp"
#include "systems/dem/solid_contacts.hpp"
#include "systems/dem/solid_force_sum.hpp"
#include "systems/dem/solid_integrate.hpp"
#include "systems/dem/solid_neighbours.hpp"
#include "systems/physics/coupling/drag_law.hpp"
#include "systems/physics/coupling/lubrication.hpp"
#include "tests/support/scene_builder.hpp"

using namespace riffle;
using riffle::test::SceneBuilder;

namespace {


struct LubeScene {
  double density = 7800.0;        ///< [kg/m^3] the grain (steel, as in Joseph et al. 2001 and Gondret et al. 2002)
  double young = 1.0e8;           ///< [Pa] softened, as the seed scenes: the contact lasts longer, the sub-step too
  double restitution = 0.9;       ///< [1] e_dry
  double viscosity = 0.1;         ///< [Pa s] mu
  double fluid_density = 1000.0;  ///< [kg/m^3]
  double max_impact_speed = 1.0;  ///< [m/s]
  std::string coupling = "lubrication = true\n";
};

std::string lubrication_scene_text(const LubeScene& spec) {
  return SceneBuilder().run({.end_time = 1.0, .dt = 1.0e-4, .gravity = {0.0, 0.0, 0.0}})
      .material("grain", {.density = spec.density, .young_modulus = spec.young, .poisson_ratio = 0.3})
      .tank({.size = {0.1, 0.1, 0.1}, .wall_material = "grain"})
      .contact({.restitution = spec.restitution, .friction = 0.3, .max_impact_speed = spec.max_impact_speed})
      .sphere({.position = {0.05, 0.05, 0.05}, .radius = 0.0025, .material = "grain"})
      .fluid({.spacing = 0.01, .kinematic_viscosity = spec.viscosity / spec.fluid_density})
      .set("density", spec.fluid_density).fluid_box({0.0, 0.0, 0.0}, {0.1, 0.1, 0.1})
      .coupling().verbatim(spec.coupling).toml();
}

/// A World with the grains given (wet, in still water, voidage 1) and the tank's floor, and one DEM sub-step as the
/// engine runs it with lubrication on: kick-drift, neighbours, contacts, drag, lubrication, force sum, kick.
struct Bench {
  Model model;
  World world;
  std::vector<std::unique_ptr<System>> systems;
  double time = 0.0;

  Bench(const LubeScene& spec, const std::vector<std::pair<Vec3, double>>& grains) {
    model = parse_scene(lubrication_scene_text(spec), "lubrication.toml");
    world.solids.emplace();
    for (const auto& [position, radius] : grains) {
      const std::size_t slot = world.solids->add(position, Vec3::Zero(), radius, spec.density, 0, 0);
      world.solids->fluid_weight[slot] = 1.0;
      world.solids->voidage[slot] = 1.0;
    }
    world.walls.emplace();
    world.walls->add("floor", Vec3(0.05, 0.05, 0.0), Vec3::UnitZ(), Vec3(0.05, 0.0, 0.0), Vec3(0.0, 0.05, 0.0),
                     false, 0);
    world.tank_motion.emplace();
    world.contacts.emplace();
    systems.push_back(std::make_unique<SolidKickDrift>(model));
    systems.push_back(std::make_unique<SolidNeighbours>());
    systems.push_back(std::make_unique<SolidContactForces>());
    systems.push_back(std::make_unique<SolidDrag>(model));
    systems.push_back(std::make_unique<SolidLubrication>(model));
    systems.push_back(std::make_unique<SolidForceSum>(true));
    systems.push_back(std::make_unique<SolidKick>(model));
  }

  /// Runs the systems from `first` to `last` (indices above) once with sub-step dt.
  void run(std::size_t first, std::size_t last, double dt) {
    for (std::size_t k = first; k <= last; ++k) {
      const Access access = systems[k]->access();
      SystemContext context(world, model, *systems[k], access, time, dt);
      systems[k]->run(context);
    }
  }
  /// The forces at the present state without moving: neighbours to the force sum.
  void forces(double dt) { run(1, 5, dt); }
  void substep(double dt) {
    run(0, 6, dt);
    time += dt;
  }
};

double stokes(double viscosity, double radius, double speed) { return 6.0 * std::numbers::pi * viscosity * radius * speed; }

}  // namespace

TEST_CASE("a sphere moving towards a wall: drag law + lubrication give Brenner's exact force, h/a = 0.05 to 2") {
  // A grain of a = 2.5 mm at speed V = 10 um/s in a fluid of mu = 1 Pa s (Re = rho d V / mu = 5e-5: Stokes flow),
  // cut-off at 3 radii. riffle's wall resistance is within 0.15 % of Brenner's series (unit test), the drag law is
  // Stokes' within 0.15 Re^0.687 = 2e-4 here, and the sub-step (1e-9 s) leaves the swept and implicit forms at their
  // point values to 1e-6: 0.2 % in all.
  LubeScene spec;
  spec.viscosity = 1.0;
  spec.coupling = "lubrication = true\nlubrication_cutoff = 3.0\nroughness = 1e-4\n";
  const double a = 0.0025, speed = 1e-5;
  for (double h_over_a : {0.05, 0.1, 0.2, 0.5, 1.0, 1.5, 2.0}) {
    CAPTURE(h_over_a);
    Bench bench(spec, {{Vec3(0.05, 0.05, a * (1.0 + h_over_a)), a}});
    bench.world.solids->velocity[0] = Vec3(0.0, 0.0, -speed);
    bench.forces(1e-9);
    const Solids& solids = *bench.world.solids;
    const double written = solids.force[0].z();  // drag + lubrication (no contact, no pressure force)
    const double exact = stokes(spec.viscosity, a, speed) * brenner_wall_resistance(h_over_a);
    std::printf("wall approach: h/a %.2f  force / Brenner %.5f\n", h_over_a, written / exact);
    CHECK(std::abs(written / exact - 1.0) < 2e-3);
    CHECK(solids.lubrication_force[0].z() > 0.0);
    CHECK(std::abs(solids.lubrication_force[0].x()) + std::abs(solids.lubrication_force[0].y()) == 0.0);
  }
  // Beyond the cut-off only the drag law acts.
  Bench far(spec, {{Vec3(0.05, 0.05, a * 4.5), a}});
  far.world.solids->velocity[0] = Vec3(0.0, 0.0, -speed);
  far.forces(1e-9);
  CHECK(far.world.solids->lubrication_force[0].isZero(0.0));
}

TEST_CASE("two grains closing: equal and opposite lubrication, the pair law, and none for a dry grain") {
  LubeScene spec;
  spec.viscosity = 0.5;
  spec.coupling = "lubrication = true\nlubrication_cutoff = 0.5\nroughness = 1e-4\n";
  const double a1 = 0.0025, a2 = 0.004, gap = 1e-4;
  Bench bench(spec, {{Vec3(0.05, 0.05, 0.05), a1}, {Vec3(0.05 + a1 + a2 + gap, 0.05, 0.05), a2}});
  bench.world.solids->velocity[0] = Vec3(2e-3, 0.0, 0.0);
  bench.world.solids->velocity[1] = Vec3(-1e-3, 0.0, 0.0);
  bench.forces(1e-9);
  const Solids& solids = *bench.world.solids;
  CHECK((solids.lubrication_force[0] + solids.lubrication_force[1]).isZero(0.0));
  const double expected =
      pair_lubrication_coefficient(a1, a2, gap, spec.viscosity, 1e-4 * reduced_radius(a1, a2), 0.5 * reduced_radius(a1, a2)) * 3e-3;
  CHECK(-solids.lubrication_force[0].x() == doctest::Approx(expected).epsilon(1e-5));
  // One grain out of the water: no lubrication on either.
  bench.world.solids->fluid_weight[1] = 0.0;
  bench.forces(1e-9);
  CHECK(solids.lubrication_force[0].isZero(0.0));
  CHECK(solids.lubrication_force[1].isZero(0.0));
  // The neighbour list reaches the cut-off: a pair at 0.9 of it (beyond the skin of a1/2 ... here a1/2 = 1.25 mm
  // is more than the cut-off, so take a cut-off of 2 a* = 3.1 mm > skin) is a candidate.
  spec.coupling = "lubrication = true\nlubrication_cutoff = 2.0\nroughness = 1e-4\n";
  const double wide_gap = 0.9 * 2.0 * reduced_radius(a1, a2);
  Bench wide(spec, {{Vec3(0.05, 0.05, 0.05), a1}, {Vec3(0.05 + a1 + a2 + wide_gap, 0.05, 0.05), a2}});
  wide.world.solids->velocity[0] = Vec3(2e-3, 0.0, 0.0);
  wide.forces(1e-9);
  CHECK(wide.world.contacts->pair_count() == 1);
  CHECK(wide.world.solids->lubrication_force[0].x() < 0.0);
}

TEST_CASE("a lubricated pair across the periodic seam feels the same force as the same pair half a period away") {
  // The pair of the test above, closing along x: once in the middle of the box, once straddling the x seam (the
  // box made periodic along x and y after parsing: the scene refuses [fluid] with periodic until the periodic water
  // lands, and the lubrication needs only the fluid's viscosity). Across the seam the second grain of the pair is a
  // ghost; its force must be the same and its reaction must reach the owner.
  LubeScene spec;
  spec.viscosity = 0.5;
  spec.coupling = "lubrication = true\nlubrication_cutoff = 0.5\nroughness = 1e-4\n";
  const double a1 = 0.0025, a2 = 0.004, gap = 1e-4, period = 0.1;
  const double at_x = 0.05 - 0.5 * (a1 + a2 + gap);
  Bench inside(spec, {{Vec3(at_x, 0.05, 0.05), a1}, {Vec3(at_x + a1 + a2 + gap, 0.05, 0.05), a2}});
  Bench across(spec, {{Vec3(at_x + 0.5 * period, 0.05, 0.05), a1},
                      {Vec3(at_x + a1 + a2 + gap - 0.5 * period, 0.05, 0.05), a2}});
  across.model.tank.periodic = {true, true, false};
  for (Bench* bench : {&inside, &across}) {
    bench->world.solids->velocity[0] = Vec3(2e-3, 0.0, 0.0);
    bench->world.solids->velocity[1] = Vec3(-1e-3, 0.0, 0.0);
    bench->forces(1e-9);
  }
  REQUIRE(across.world.contacts->halo.valid);
  REQUIRE(across.world.contacts->pair_count() == 1);
  CHECK(across.world.contacts->pair_second[0] >= 2);  // the second grain is a ghost
  // The list may reorder the grains: compare them by id.
  const Solids& expected = *inside.world.solids;
  const Solids& seam = *across.world.solids;
  const auto slot = [](const Solids& solids, std::size_t id) {
    return static_cast<std::size_t>(std::find(solids.id.begin(), solids.id.end(), id) - solids.id.begin());
  };
  REQUIRE(expected.lubrication_force[slot(expected, 0)].x() < 0.0);
  for (std::size_t id = 0; id < 2; ++id)
    for (int axis = 0; axis < 3; ++axis)
      CHECK(seam.lubrication_force[slot(seam, id)][axis] ==
            doctest::Approx(expected.lubrication_force[slot(expected, id)][axis]).epsilon(1e-9).scale(1e-12));
  CHECK((seam.lubrication_force[0] + seam.lubrication_force[1]).isZero(0.0));
  // A sub-step on: both pairs slow alike.
  inside.substep(1e-6);
  across.substep(1e-6);
  for (std::size_t id = 0; id < 2; ++id)
    CHECK(seam.velocity[slot(seam, id)].x() ==
          doctest::Approx(expected.velocity[slot(expected, id)].x()).epsilon(1e-9));
}

namespace {

struct Bounce {
  double impact = 0.0;   ///< [m/s] approach speed when the gap first falls below the cut-off
  double rebound = 0.0;  ///< [m/s] separation speed when it next rises above it (0: it never did)
  double lowest = 1.0;   ///< [m] smallest gap reached (negative: overlap)
  double fastest = 0.0;  ///< [m/s] largest speed after the start
  bool finite = true;
};

/// A grain of radius 2.5 mm thrown at the floor at `speed` from just beyond the cut-off, no gravity; `wet` false
/// takes it out of the water (dry impact: no drag, no lubrication).
Bounce bounce(const LubeScene& spec, double speed, bool wet, double until) {
  const double a = 0.0025;
  Bench bench(spec, {{Vec3(0.05, 0.05, 0.0), a}});
  const double cutoff = bench.model.coupling.lubrication_cutoff_gap(a);
  Solids& solids = *bench.world.solids;
  solids.position[0].z() = a + cutoff + 0.05 * a;
  solids.velocity[0] = Vec3(0.0, 0.0, -speed);
  solids.fluid_weight[0] = wet ? 1.0 : 0.0;
  const double dt = bench.model.solid_dt();
  bench.forces(dt);
  Bounce result;
  bool inside = false;
  while (bench.time < until) {
    bench.substep(dt);
    const double gap = solids.position[0].z() - a;
    const double vz = solids.velocity[0].z();
    result.finite = result.finite && std::isfinite(gap) && std::isfinite(vz);
    if (!result.finite) break;
    result.lowest = std::min(result.lowest, gap);
    result.fastest = std::max(result.fastest, std::abs(vz));
    if (!inside && gap < cutoff && result.impact == 0.0) {
      inside = true;
      result.impact = -vz;
    }
    if (inside && gap > cutoff) {
      result.rebound = vz;
      break;
    }
  }
  return result;
}

}  // namespace

TEST_CASE("a heavy grain thrown at a wall in a very viscous fluid neither blows up nor tunnels") {
  // Steel at 3 m/s into mu = 1 and 10 Pa s with a roughness of 1e-6 a (2.5 nm): c dt/m reaches 5e2-5e3 at the
  // film, where an explicit force would reverse and amplify the velocity every sub-step. Expected: the speed
  // never exceeds the initial one (lubrication and drag only take energy), the grain never sinks into the wall
  // further than a dry impact at the same speed would (Hertz: 15 m v^2 / (16 E* sqrt(a)) to the 2/5), and at
  // St = rho d v / (9 mu) = 13 and 1.3 it does not come back (Gondret et al. 2002: no rebound below St ~ 10;
  // the fit gives e/e_dry = exp(-35/13) = 0.07 at most).
  for (double viscosity : {1.0, 10.0}) {
    CAPTURE(viscosity);
    LubeScene spec;
    spec.viscosity = viscosity;
    spec.max_impact_speed = 3.0;
    spec.coupling = "lubrication = true\nroughness = 1e-6\n";
    const Bounce wet = bounce(spec, 3.0, true, 0.02);
    const Bounce dry = bounce(spec, 3.0, false, 0.02);
    CHECK(wet.finite);
    CHECK(wet.fastest <= 3.0 * (1.0 + 1e-12));
    CHECK(wet.lowest >= dry.lowest);
    CHECK(wet.lowest > -0.1 * 0.0025);
    CHECK(wet.rebound < 0.1 * dry.rebound);
  }
}

TEST_CASE("wet restitution against Stokes number follows Legendre et al. (2006): e/e_dry = exp(-35/St)") {
  // St = (rho_p + C_a rho_f) d V / (9 mu), C_a = 0.5, V the speed where the grain enters the cut-off; e the
  // separation speed where it leaves it over V. The data the fit summarises (Joseph et al. 2001, JFM 433; Gondret
  // et al. 2002, Phys. Fluids 14; Legendre et al. 2006 Fig. 3) scatter about it by about +-0.1 to 0.15 in e/e_dry
  // between St = 20 and 500 (different materials, roughnesses and fluids at one St): the tolerance, 0.15. At
  // St = 8 both data and fit are below 0.02: the check there is e/e_dry < 0.1. The full sweep and the table:
  // tools/riffle-tools wet-restitution, docs/COUPLING.md.
  const double speed = 0.5, d = 0.005;
  LubeScene spec;
  spec.restitution = 0.9;
  const double e_dry = [&] {
    const Bounce dry = bounce(spec, speed, false, 0.1);
    return dry.rebound / dry.impact;
  }();
  CHECK(e_dry == doctest::Approx(0.9).epsilon(0.03));
  for (double stokes_number : {8.0, 30.0, 100.0, 400.0}) {
    CAPTURE(stokes_number);
    spec.viscosity = (spec.density + 0.5 * spec.fluid_density) * d * speed / (9.0 * stokes_number);
    const Bounce wet = bounce(spec, speed, true, 0.1);
    const double st = (spec.density + 0.5 * spec.fluid_density) * d * wet.impact / (9.0 * spec.viscosity);
    const double ratio = wet.rebound / wet.impact / e_dry;
    const double fit = std::exp(-35.0 / st);
    std::printf("wet restitution: St %.1f  e/e_dry %.3f  fit %.3f\n", st, ratio, fit);
    if (stokes_number < 10.0)
      CHECK(ratio < 0.1);
    else
      CHECK(std::abs(ratio - fit) < 0.15);
  }
}
