// The added-mass and history forces (systems/physics/coupling/added_mass.hpp) and the grains' implicit kick with added mass
// (systems/dem/solid_integrate.cpp), against closed forms.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include "components/world.hpp"
#include "systems/dem/solid_integrate.hpp"
#include "systems/physics/coupling/added_mass.hpp"
#include "systems/physics/coupling/drag_law.hpp"
#include "tests/support/test_support.hpp"

using namespace riffle;

namespace {
constexpr CouplingModel::FluidVelocity kPore = CouplingModel::FluidVelocity::kPore;
constexpr CouplingModel::FluidVelocity kMixture = CouplingModel::FluidVelocity::kMixture;

double kernel(const BassetModes& modes, double t) {
  double sum = 0.0;
  for (std::size_t k = 0; k < BassetModes::kCount; ++k) sum += modes.weight[k] * std::exp(-modes.rate[k] * t);
  return sum;
}
}  // namespace

TEST_CASE("Zuber's added-mass coefficient: 1/2 for a lone sphere, (1 + 2 phi) / (2 (1 - phi)) in a suspension") {
  CHECK(added_mass_coefficient(1.0) == 0.5);
  CHECK(added_mass_coefficient(1.2) == 0.5);  // a voidage above 1 is a lone grain
  CHECK(added_mass_coefficient(0.5) == doctest::Approx(2.0).epsilon(1e-15));
  CHECK(added_mass_coefficient(0.9) == doctest::Approx(0.5 * 1.2 / 0.9).epsilon(1e-15));
}

TEST_CASE("the added-mass coefficient the grains use: Zuber's, capped where the water's reaction would not be stable") {
  // A lone grain and a dilute suspension: Zuber's.
  CHECK(stable_added_mass_coefficient(1.0, kPore) == 0.5);
  CHECK(stable_added_mass_coefficient(1.0, kMixture) == 0.5);
  CHECK(stable_added_mass_coefficient(0.9, kMixture) == added_mass_coefficient(0.9));
  // A packed bed, phi = 0.6: Zuber's 2.75 would feed back C_a phi = 1.65 (pore) or 4.1 (mixture) times the water's
  // own acceleration; capped at half the water's inertia.
  CHECK(added_mass_coefficient(0.4) == doctest::Approx(2.75).epsilon(1e-14));
  CHECK(stable_added_mass_coefficient(0.4, kPore) == doctest::Approx(0.5 * 0.4 / 0.6).epsilon(1e-14));
  CHECK(stable_added_mass_coefficient(0.4, kMixture) == doctest::Approx(0.5 * 0.16 / 0.6).epsilon(1e-14));
  for (const double eps : {0.3, 0.5, 0.7, 0.9, 0.99})
    for (const bool mixture : {false, true}) {
      const CouplingModel::FluidVelocity reading = mixture ? kMixture : kPore;
      const double fed_back = stable_added_mass_coefficient(eps, reading) * (1.0 - eps) / (mixture ? eps : 1.0);
      CHECK(fed_back <= 0.5 + 1e-12);
      CHECK(stable_added_mass_coefficient(eps, reading) <= added_mass_coefficient(eps));
    }
}

TEST_CASE("the history kernel's exponential modes are t^(-1/2) up to the window and integrate it over a step") {
  for (const double window : {0.05, 0.1, 1.0}) {
    CAPTURE(window);
    const double dt = 1e-3;
    const BassetModes modes = BassetModes::make(window, dt);
    // From one update interval to window/30: within 1 % (the trapezoidal rule in ln s and its lumped ends).
    for (double t = dt; t <= window / 30.0; t *= 1.3) {
      CAPTURE(t);
      CHECK(kernel(modes, t) * std::sqrt(t) == doctest::Approx(1.0).epsilon(0.01));
    }
    // The window: 3 % low at window/10, down to about 0.58 at the window (the exponential tail).
    CHECK(kernel(modes, window / 10.0) * std::sqrt(window / 10.0) == doctest::Approx(0.97).epsilon(0.01));
    CHECK(kernel(modes, window) * std::sqrt(window) == doctest::Approx(0.585).epsilon(0.02));
    // A relative velocity growing at a constant rate a from t = 0: F_H / C = a int_0^t (t - tau)^(-1/2) dtau =
    // 2 a t^(1/2). The modes advanced step by step (exact for a linear w) give it within 1 % up to window/30.
    const Vec3 rate(0.3, -0.1, 0.0);
    std::array<Vec3, BassetModes::kCount> state;
    state.fill(Vec3::Zero());  // an Eigen vector is not zeroed by {}
    for (int step = 1; step * dt <= window / 30.0 + 1e-12; ++step) {
      Vec3 integral = Vec3::Zero();
      for (std::size_t k = 0; k < BassetModes::kCount; ++k) {
        advance_basset_mode(state[k], modes.rate[k], dt, dt * rate);
        integral += modes.weight[k] * state[k];
      }
      const double t = step * dt;
      CAPTURE(t);
      CHECK((integral - 2.0 * std::sqrt(t) * rate).norm() < 0.01 * 2.0 * std::sqrt(t) * rate.norm());
    }
  }
  // The prefactor 3/2 d^2 (pi rho mu)^(1/2): for d = 10 mm in water, 1.5e-4 (pi)^(1/2) kg/s^(1/2).
  CHECK(basset_prefactor(0.01, 1000.0, 1e-3) == doctest::Approx(1.5e-4 * std::sqrt(std::numbers::pi)).epsilon(1e-14));
}

TEST_CASE("Mei & Adrian's kernel: their two-term form, Basset's at short times and t^(-2) beyond t_H") {
  // Mei & Adrian (1992) as Loth & Dorgan (2009) write it, in Basset's normalisation (F_H = 3/2 d^2 (pi rho mu)^(1/2)
  // int K dw): K_MA(t) = d / (2 (pi nu)^(1/2)) {(4 pi nu t / d^2)^(1/4) + (pi |w|^3 t^2 / (d nu f_H^3))^(1/2)}^(-2),
  // f_H = 0.75 + 0.105 Re. Its factor on t^(-1/2) is basset_factor(t, t_H) for every t, Re and d.
  const double nu = 1e-6;
  for (const double diameter : {0.5e-3, 2e-3, 0.015})
    for (const double reynolds : {0.1, 1.5, 10.0, 100.0}) {
      const double w = reynolds * nu / diameter;
      const double f_h = 0.75 + 0.105 * reynolds;
      const double t_h = MeiAdrianKernel::time_scale(w, diameter, nu);
      for (const double t : {1e-4, 1e-3, 1e-2, 0.1, 1.0, 10.0}) {
        CAPTURE(diameter);
        CAPTURE(reynolds);
        CAPTURE(t);
        const double two_terms = std::pow(4.0 * std::numbers::pi * nu * t / (diameter * diameter), 0.25) +
                                 std::sqrt(std::numbers::pi * w * w * w * t * t / (diameter * nu * f_h * f_h * f_h));
        const double mei_adrian = 2.0 * std::sqrt(std::numbers::pi * nu) / diameter / (two_terms * two_terms);
        CHECK(mei_adrian * std::sqrt(t) == doctest::Approx(MeiAdrianKernel::basset_factor(t, t_h)).epsilon(1e-12));
      }
    }
  // t_H = (4/pi)^(1/3) nu f_H^2 / w^2: ten Cate's E1 (Re 1.5, 15 mm, 0.038 m/s in an oil of 3.85e-4 m^2/s), 0.24 s.
  CHECK(MeiAdrianKernel::time_scale(0.038, 0.015, 3.85e-4) == doctest::Approx(0.2425).epsilon(0.005));
  CHECK(std::isinf(MeiAdrianKernel::time_scale(0.0, 0.015, 3.85e-4)));
  CHECK(MeiAdrianKernel::basset_factor(0.5, std::numeric_limits<double>::infinity()) == 1.0);
  // Basset's below t_H (within 1 % at t_H / 1000), (t / t_H)^(-3/2) far beyond it.
  CHECK(MeiAdrianKernel::basset_factor(1e-3, 1.0) == doctest::Approx(1.0).epsilon(0.012));
  CHECK(MeiAdrianKernel::basset_factor(1e4, 1.0) == doctest::Approx(1e-6).epsilon(0.02));
}

TEST_CASE("Mei & Adrian's kernel on the history modes: within 3 % of Basset's magnitude, step by step") {
  for (const auto& window_and_step : {std::pair{1.0, 1e-3}, std::pair{1.0, 1e-4}, std::pair{0.3, 2e-3}}) {
    const double window = window_and_step.first, dt = window_and_step.second;  // named: doctest's CAPTURE takes them
    const BassetModes modes = BassetModes::make(window, dt);
    const MeiAdrianModeWeights mei_adrian(modes);
    const double shortest = 20.0 / modes.rate[BassetModes::kCount - 1];
    for (const double t_h : {shortest / 3.0, 3.0 * shortest, 0.01, 0.03, 0.1, 0.3, 1.0, 3.0, 10.0, 1e3}) {
      CAPTURE(window);
      CAPTURE(dt);
      CAPTURE(t_h);
      const auto weights = mei_adrian.weights(t_h);
      // The kernel itself, against the windowed Basset kernel times Mei & Adrian's factor, over the fit's span and
      // between its table's entries (t_H a third of the way to the next).
      const auto between = mei_adrian.weights(t_h * std::exp(0.25 / 3.0));
      for (double t = shortest; t <= window; t *= 1.1) {
        CAPTURE(t);
        double fitted = 0.0, fitted_between = 0.0;
        for (std::size_t k = 0; k < BassetModes::kCount; ++k) {
          fitted += weights[k] * std::exp(-modes.rate[k] * t);
          fitted_between += between[k] * std::exp(-modes.rate[k] * t);
        }
        const double basset = kernel(modes, t);
        CHECK(std::abs(fitted - basset * MeiAdrianKernel::basset_factor(t, t_h)) < 0.03 * basset);
        CHECK(std::abs(fitted_between - basset * MeiAdrianKernel::basset_factor(t, t_h * std::exp(0.25 / 3.0))) <
              0.03 * basset);
      }
    }
    // A slip growing at a constant rate from rest, t_H held: F_H / C = a int_0^t K(tau) dtau, the integral by
    // quadrature of t^(-1/2) g(t / t_H) (tau = s^2), against the modes advanced step by step: within 2 % of
    // Basset's 2 a t^(1/2) from the shortest time the modes resolve (20 / the top rate) to window/30.
    const double t_h = 0.05;
    const auto weights = mei_adrian.weights(t_h);
    std::array<Vec3, BassetModes::kCount> state;
    state.fill(Vec3::Zero());
    const Vec3 rate(0.2, 0.0, -0.1);
    for (int step = 1; step * dt <= window / 30.0 + 1e-12; ++step) {
      Vec3 integral = Vec3::Zero();
      for (std::size_t k = 0; k < BassetModes::kCount; ++k) {
        advance_basset_mode(state[k], modes.rate[k], dt, dt * rate);
        integral += weights[k] * state[k];
      }
      const double t = step * dt;
      double quadrature = 0.0;  // int_0^t tau^(-1/2) g dtau = int_0^sqrt(t) 2 g(s^2) ds, midpoint rule
      const int n = 2000;
      for (int i = 0; i < n; ++i) {
        const double s = (i + 0.5) * std::sqrt(t) / n;
        quadrature += 2.0 * MeiAdrianKernel::basset_factor(s * s, t_h) * std::sqrt(t) / n;
      }
      CAPTURE(t);
      if (t >= shortest) CHECK((integral - quadrature * rate).norm() < 0.02 * 2.0 * std::sqrt(t) * rate.norm());
    }
  }
}

TEST_CASE("the implicit kick: a grain in a uniformly accelerating fluid reaches the analytic velocity") {
  // Water accelerating uniformly at a has grad p = rho (g - a): the grain feels rho V (a - g) from the pressure
  // gradient and, with added mass, (m + m_a) dv/dt = rho V (a - g) + m g + m_a a, a constant acceleration that
  // velocity Verlet integrates exactly. Without added mass, m dv/dt = rho V (a - g) + m g. A neutral grain
  // (m = rho V) follows the water, dv/dt = a, either way.
  const Vec3 gravity(0.0, 0.0, -9.81), fluid_acceleration(1.2, -0.4, 0.3);
  const double rho = 1000.0, radius = 0.005, dt = 2.5e-5;
  const int substeps = 400;
  for (const bool added_mass : {false, true})
    for (const double density : {1000.0, 1318.0, 2500.0}) {
      CAPTURE(added_mass);
      CAPTURE(density);
      Model model = test::small_model();
      model.gravity = gravity;
      model.fluid.density = rho;
      model.coupling.enabled = true;
      model.coupling.added_mass = added_mass;
      World world;
      world.solids.emplace();
      const Vec3 start(0.01, 0.02, -0.03);
      world.solids->add(Vec3(0.1, 0.1, 0.1), start, radius, density, 0, 0);
      Solids& grain = *world.solids;
      const double volume = grain_volume(radius), mass = grain.mass[0];
      grain.fluid_weight[0] = 1.0;
      grain.voidage[0] = 0.9;
      grain.fluid_acceleration[0] = fluid_acceleration;
      grain.pressure_force[0] = rho * volume * (fluid_acceleration - gravity);
      grain.force[0] = grain.pressure_force[0];  // solid_force_sum's, with no contact and no drag
      SolidKickDrift kick_drift(model);
      SolidKick kick(model);
      const Access drift_access = kick_drift.access(), kick_access = kick.access();
      for (int sub = 0; sub < substeps; ++sub) {
        SystemContext first(world, model, kick_drift, drift_access, sub * dt, dt);
        kick_drift.run(first);
        SystemContext second(world, model, kick, kick_access, sub * dt, dt);
        kick.run(second);
      }
      const double added = added_mass ? 0.5 * 1.2 / 0.9 * rho * volume : 0.0;  // Zuber at eps = 0.9
      const Vec3 acceleration =
          (rho * volume * (fluid_acceleration - gravity) + mass * gravity + added * fluid_acceleration) /
          (mass + added);
      const double time = substeps * dt;
      CHECK((grain.velocity[0] - (start + time * acceleration)).norm() < 1e-12);
      if (density == rho) CHECK((acceleration - fluid_acceleration).norm() < 1e-12);
      // The force applied is m_a (a_f - dv/dt); its impulse went to the drag impulse for the water to take back:
      // m_a (a_f T - (v_T - v_0)).
      CHECK((grain.added_mass_force[0] - added * (fluid_acceleration - acceleration)).norm() < 1e-15);
      const Vec3 impulse = added * (time * fluid_acceleration - (grain.velocity[0] - start));
      CHECK((grain.drag_impulse[0] - impulse).norm() < 1e-15 + 1e-12 * impulse.norm());
      if (!added_mass) CHECK(grain.drag_impulse[0] == Vec3::Zero());
    }
}

TEST_CASE("the implicit kick is stable for added mass far above the grain's mass") {
  // A light grain (density 100 kg/m^3, m_a / m = 5 in water) with a stiff linear drag: an explicit added-mass force
  // from the last acceleration diverges for m_a > m; the implicit kick relaxes to the fluid's velocity.
  Model model = test::small_model();
  model.gravity = Vec3::Zero();
  model.fluid.density = 1000.0;
  model.coupling.enabled = true;
  model.coupling.added_mass = true;
  World world;
  world.solids.emplace();
  world.solids->add(Vec3(0.1, 0.1, 0.1), Vec3(0.2, 0.0, 0.0), 0.005, 100.0, 0, 0);
  Solids& grain = *world.solids;
  grain.fluid_weight[0] = 1.0;
  SolidKickDrift kick_drift(model);
  SolidKick kick(model);
  const Access drift_access = kick_drift.access(), kick_access = kick.access();
  const double dt = 1e-3, k = 0.05;  // k dt / m = 0.95: near the explicit limit without added mass
  for (int sub = 0; sub < 2000; ++sub) {
    SystemContext first(world, model, kick_drift, drift_access, sub * dt, dt);
    kick_drift.run(first);
    grain.force[0] = -k * grain.velocity[0];
    SystemContext second(world, model, kick, kick_access, sub * dt, dt);
    kick.run(second);
  }
  CHECK(grain.velocity[0].norm() < 1e-6);
}

TEST_CASE("the scene's added-mass and history switches: added mass and Mei & Adrian's history on with the MPS water, "
          "and a window too short is refused") {
  const std::string scene = test::coupled_scene_text();
  // Without a [coupling] table the scene gets the defaults of an empty one: added mass, the grain's undisturbed
  // velocity (the MPS water, the isotropic kernel) and the history force with Mei & Adrian's kernel on.
  for (const std::string& text : {scene, scene + "[coupling]\n"}) {
    const Model defaults = parse_scene(text, "coupled.toml");
    CHECK(defaults.coupling.added_mass);
    CHECK(defaults.coupling.self_induced_velocity);
    CHECK(defaults.coupling.history_force);
    CHECK(defaults.coupling.history_kernel == CouplingModel::HistoryKernel::kMeiAdrian);
    CHECK(defaults.coupling.history_window == 1.0);
  }
  CHECK_FALSE(parse_scene(scene + "[coupling]\nadded_mass = false\n", "coupled.toml").coupling.added_mass);
  // The history force goes with added mass and the undisturbed slip: off where either is off, unless asked for.
  CHECK_FALSE(parse_scene(scene + "[coupling]\nadded_mass = false\n", "coupled.toml").coupling.history_force);
  CHECK_FALSE(
      parse_scene(scene + "[coupling]\nself_induced_velocity = false\n", "coupled.toml").coupling.history_force);
  CHECK(parse_scene(scene + "[coupling]\nadded_mass = false\nhistory_force = true\n", "coupled.toml")
            .coupling.history_force);
  CHECK(parse_scene(scene + "[coupling]\nhistory_kernel = \"basset\"\n", "coupled.toml").coupling.history_kernel ==
        CouplingModel::HistoryKernel::kBasset);
  CHECK_THROWS_WITH(parse_scene(scene + "[coupling]\nhistory_kernel = \"oseen\"\n", "coupled.toml"),
                    doctest::Contains("coupling.history_kernel"));
  // A Model built in code starts with all three off (the tests that build their models).
  CHECK_FALSE(Model{}.coupling.added_mass);
  CHECK_FALSE(Model{}.coupling.self_induced_velocity);
  CHECK_FALSE(Model{}.coupling.history_force);
  const Model on = parse_scene(scene + "[coupling]\nadded_mass = true\nhistory_force = true\nhistory_window = 0.2\n",
                               "coupled.toml");
  CHECK(on.coupling.added_mass);
  CHECK(on.coupling.history_force);
  CHECK(on.coupling.history_window == 0.2);
  // A window of a few steps would be no history at all: refused, naming the key; harmless while the force is off.
  CHECK_THROWS_WITH(parse_scene(scene + "[coupling]\nhistory_force = true\nhistory_window = 0.005\n", "coupled.toml"),
                    doctest::Contains("coupling.history_window: must be at least 10 run.dt"));
  CHECK_NOTHROW(parse_scene(scene + "[coupling]\nhistory_force = false\nhistory_window = 0.005\n", "coupled.toml"));
  CHECK_THROWS_WITH(parse_scene(scene + "[coupling]\nhistory_window = -1\n", "coupled.toml"),
                    doctest::Contains("coupling.history_window"));
  CHECK_THROWS_WITH(parse_scene(scene + "[coupling]\nadded_mass = 1\n", "coupled.toml"),
                    doctest::Contains("coupling.added_mass"));
}

TEST_CASE("the scene's voidage keys: volume and the radius across the bed, a narrow radius over the water refused") {
  const std::string scene = test::coupled_scene_text();
  const Model plain = parse_scene(scene, "coupled.toml");
  CHECK(plain.coupling.voidage_volume == CouplingModel::VoidageVolume::kFluidParticles);
  CHECK(plain.coupling.voidage_vertical_radius == 0.0);
  const Model thin =
      parse_scene(scene + "[coupling]\nvoidage_volume = \"tank\"\nvoidage_vertical_radius = 0.005\n", "coupled.toml");
  CHECK(thin.coupling.voidage_volume == CouplingModel::VoidageVolume::kTank);
  CHECK(thin.coupling.voidage_vertical_radius == 0.005);
  // Over the fluid particles' volume, a radius under 3 l0 aliases with the water's layers: refused, naming the key.
  CHECK_THROWS_WITH(parse_scene(scene + "[coupling]\nvoidage_vertical_radius = 0.02\n", "coupled.toml"),
                    doctest::Contains("coupling.voidage_vertical_radius: below 3 l0"));
  CHECK_NOTHROW(parse_scene(scene + "[coupling]\nvoidage_vertical_radius = 0.03\n", "coupled.toml"));
  CHECK_THROWS_WITH(parse_scene(scene + "[coupling]\nvoidage_volume = \"cells\"\n", "coupled.toml"),
                    doctest::Contains("coupling.voidage_volume"));
  CHECK_THROWS_WITH(parse_scene(scene + "[coupling]\nvoidage_vertical_radius = -0.01\n", "coupled.toml"),
                    doctest::Contains("coupling.voidage_vertical_radius"));
  // Over the tank's volume: between the tank's height / 2000 and its height (0.1 m here).
  CHECK_THROWS_WITH(
      parse_scene(scene + "[coupling]\nvoidage_volume = \"tank\"\nvoidage_vertical_radius = 1e-6\n", "coupled.toml"),
      doctest::Contains("coupling.voidage_vertical_radius: must lie between"));
  CHECK_THROWS_WITH(
      parse_scene(scene + "[coupling]\nvoidage_volume = \"tank\"\nvoidage_vertical_radius = 0.2\n", "coupled.toml"),
      doctest::Contains("coupling.voidage_vertical_radius: must lie between"));
}

TEST_CASE("the scene's sampling_vertical_radius: read in metres, at least l0, not with the self-induced correction") {
  const std::string scene = test::coupled_scene_text();
  CHECK(parse_scene(scene, "coupled.toml").coupling.sampling_vertical_radius == 0.0);
  const Model thin = parse_scene(scene + "[coupling]\nsampling_vertical_radius = 0.015\n", "coupled.toml");
  CHECK(thin.coupling.sampling_vertical_radius == 0.015);
  CHECK_NOTHROW(parse_scene(scene + "[coupling]\nsampling_vertical_radius = 0.01\n", "coupled.toml"));
  // Under l0 the kernel holds one or two layers of water: refused, naming the key and the reason.
  CHECK_THROWS_WITH(parse_scene(scene + "[coupling]\nsampling_vertical_radius = 0.005\n", "coupled.toml"),
                    doctest::Contains("coupling.sampling_vertical_radius: below l0"));
  CHECK_THROWS_WITH(parse_scene(scene + "[coupling]\nsampling_vertical_radius = -0.01\n", "coupled.toml"),
                    doctest::Contains("coupling.sampling_vertical_radius"));
  CHECK_THROWS_WITH(parse_scene(scene + "[coupling]\nsampling_vertical_radius = \"wide\"\n", "coupled.toml"),
                    doctest::Contains("coupling.sampling_vertical_radius"));
  // The self-induced correction's overlap integrals are the isotropic kernel's.
  CHECK_THROWS_WITH(parse_scene(scene + "[coupling]\nsampling_vertical_radius = 0.015\nself_induced_velocity = true\n",
                                "coupled.toml"),
                    doctest::Contains("self_induced_velocity assumes the isotropic sampling kernel"));
  CHECK_NOTHROW(parse_scene(scene + "[coupling]\nself_induced_velocity = true\n", "coupled.toml"));
}
