// The lubrication laws of systems/physics/coupling/lubrication.hpp against the published exact results: Brenner's (1961)
// series for a sphere moving towards a plane (his Table 1), its free-surface twin for two equal spheres, and the
// limits each approximation must reach.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "systems/physics/coupling/lubrication.hpp"
#include "tests/support/test_support.hpp"
#include "tests/support/scene_builder.hpp"

using namespace riffle;
using riffle::test::SceneBuilder;

namespace {
}

TEST_CASE("Brenner's series reproduces his Table 1 (sphere towards a plane, d/a = cosh alpha)") {
  // Brenner (1961) Table 1, lambda to the digits he prints.
  const double alpha[] = {0.5, 1.0, 1.5, 2.0, 2.5, 3.0};
  const double lambda[] = {9.2518, 3.0361, 1.8375, 1.4129, 1.2220, 1.1252};
  for (int k = 0; k < 6; ++k) {
    CAPTURE(alpha[k]);
    CHECK(brenner_wall_resistance(std::cosh(alpha[k]) - 1.0) == doctest::Approx(lambda[k]).epsilon(6e-5));
  }
}

TEST_CASE("riffle's wall resistance is within 0.15 % of Brenner's exact series from h/a = 1e-4 to 20") {
  // Cox & Brenner's inner expansion errs by O((h/a) ln(h/a)): 0.15 % at the switch h/a = 0.0756, less below; the
  // reflection form of Schaffer et al. (2007) is within 0.15 % above it (their fit). Where they meet they are equal.
  CHECK(cox_brenner_wall_resistance(kWallFormSwitch) == doctest::Approx(reflection_wall_resistance(kWallFormSwitch)).epsilon(1e-12));
  for (double x = 1e-4; x < 20.0; x *= 1.25) {
    CAPTURE(x);
    CHECK(std::abs(wall_resistance(x) / brenner_wall_resistance(x) - 1.0) < 1.5e-3);
  }
  // Far away the excess over Stokes drag decays as Lorentz's 9a/(8d).
  const double x = 200.0;
  CHECK(wall_resistance(x) - 1.0 == doctest::Approx(9.0 / 8.0 / (1.0 + x)).epsilon(0.01));
}

TEST_CASE("the wall coefficient is the excess over Stokes drag, held at the roughness, zero in contact and beyond the cut-off") {
  const double a = 0.005, mu = 0.1, roughness = 1e-6, cutoff = 0.005;
  const double stokes = 6.0 * std::numbers::pi * mu * a;
  CHECK(wall_lubrication_coefficient(a, 0.001, mu, roughness, cutoff) ==
        doctest::Approx(stokes * (wall_resistance(0.2) - 1.0)).epsilon(1e-12));
  const double at_roughness = wall_lubrication_coefficient(a, roughness, mu, roughness, cutoff);
  CHECK(wall_lubrication_coefficient(a, 1e-9, mu, roughness, cutoff) == at_roughness);
  CHECK(wall_lubrication_coefficient(a, -1e-5, mu, roughness, cutoff) == 0.0);  // in contact: the contact law's
  CHECK(wall_lubrication_coefficient(a, cutoff, mu, roughness, cutoff) == 0.0);
}

TEST_CASE("the pair law matches two equal spheres' exact squeeze to its omitted O(1) term, and the wall's limit") {
  // Two equal spheres closing at V, each at h/2 from their symmetry plane: each feels 6 pi mu a (V/2) lambda_fs,
  // of which 6 pi mu a V/2 is the Stokes drag the drag law gives it. The pair law keeps the terms singular as
  // h -> 0 (a*^2/h + (9/20) a* ln(a*/h), a* = a/2); the O(1) term it omits is 0.33-0.35 (units 6 pi mu a V) for
  // h/a up to 0.1, a fraction 1.4 h/a of the leading a/(4h): the tolerance below, 1.5 h/a.
  const double a = 0.003, mu = 0.01;
  for (double h_over_a : {1e-3, 3e-3, 1e-2, 3e-2, 0.1}) {
    CAPTURE(h_over_a);
    const double exact = 6.0 * std::numbers::pi * mu * a * 0.5 * (brenner_free_surface_resistance(0.5 * h_over_a) - 1.0);
    const double model = pair_lubrication_coefficient(a, a, h_over_a * a, mu, 1e-9 * a, a);
    CHECK(std::abs(model / exact - 1.0) < 1.5 * h_over_a);
  }
  // Symmetric in the two radii.
  CHECK(pair_lubrication_coefficient(0.002, 0.005, 1e-4, mu, 1e-7, 1e-3) ==
        doctest::Approx(pair_lubrication_coefficient(0.005, 0.002, 1e-4, mu, 1e-7, 1e-3)).epsilon(1e-14));
  // A grain against a much larger one: the sphere-plane singular terms 6 pi mu a (a/h + (1/5) ln(a/h)).
  const double h = 1e-5;
  const double plane = 6.0 * std::numbers::pi * mu * a * (a / h + 0.2 * std::log(a / h));
  CHECK(pair_lubrication_coefficient(a, 1e6 * a, h, mu, 1e-9, 1.0) == doctest::Approx(plane).epsilon(1e-5));
}

TEST_CASE("the swept coefficient takes the exact ln(h0/h1) of the film a sub-step crosses") {
  const double singular = 2.0, roughness = 1e-6, cutoff = 1e-3;
  const double gap = 2e-6, c = singular / gap;  // a pure 1/h law
  // No motion: the coefficient at the gap.
  CHECK(swept_coefficient(c, singular, gap, 0.0, 1e-5, roughness, cutoff) == doctest::Approx(c).epsilon(1e-12));
  // Sweeping 3 um at V = 0.3 m/s in 1e-5 s: from 3.5 um to 0.5 um, the last 0.5 um below the roughness.
  const double sweep = 3e-6;
  const double expected = singular * (std::log(3.5e-6 / roughness) + 0.5e-6 / roughness) / sweep;
  CHECK(swept_coefficient(c, singular, gap, 0.3, 1e-5, roughness, cutoff) == doctest::Approx(expected).epsilon(1e-12));
  CHECK(swept_coefficient(c, singular, gap, -0.3, 1e-5, roughness, cutoff) == doctest::Approx(expected).epsilon(1e-12));
  // A sweep into contact counts only the film: from 2 um down to 0 (-1 um is overlap).
  CHECK(swept_coefficient(0.0, singular, -0.0, 0.3, 1e-5, roughness, cutoff) > 0.0);
  CHECK(swept_coefficient(singular / roughness, singular, 0.5e-6, 0.3, 1e-5, roughness, cutoff) ==
        doctest::Approx(singular * (1.0 + std::log(2.0)) / sweep).epsilon(1e-12));
  // The implicit coefficient: c for a slow law, m*/dt at most for a stiff one.
  CHECK(implicit_coefficient(1e-3, 1e-5, 1.0) == doctest::Approx(1e-3).epsilon(1e-7));
  CHECK(implicit_coefficient(1e12, 1e-5, 1.0) == doctest::Approx(1e5).epsilon(1e-7));
}

namespace {
std::string coupled_scene(const std::string& coupling) {
  return SceneBuilder().run({.end_time = 0.01, .dt = 1.0e-3})
      .material("grain", {.density = 2500.0, .young_modulus = 1.0e8, .poisson_ratio = 0.3})
      .tank({.size = {0.04, 0.04, 0.04}, .wall_material = "grain"}).contact({.restitution = 0.9, .friction = 0.3})
      .sphere({.position = {0.02, 0.02, 0.01}, .radius = 0.0025, .material = "grain"}).fluid({.spacing = 0.005})
      .fluid_box({0.0, 0.0, 0.0}, {0.04, 0.04, 0.03}).coupling().toml() + coupling;
}

std::string problems(const std::string& coupling) {
  try {
    parse_scene(coupled_scene(coupling), "lube.toml");
  } catch (const SceneError& error) {
    return error.what();
  }
  return "";
}
}  // namespace

TEST_CASE("[coupling] lubrication keys: off by default, lengths in reduced radii or metres, clear errors") {
  const Model plain = parse_scene(coupled_scene(""), "lube.toml");
  CHECK_FALSE(plain.coupling.lubrication);
  CHECK(plain.coupling.lubrication_cutoff_gap(0.002) == doctest::Approx(0.002));
  CHECK(plain.coupling.roughness_gap(0.002) == doctest::Approx(2e-6));
  const Model metres =
      parse_scene(coupled_scene("lubrication = true\nlubrication_cutoff_m = 0.001\nroughness_m = 5e-7\n"), "lube.toml");
  CHECK(metres.coupling.lubrication);
  CHECK(metres.coupling.lubrication_cutoff_gap(0.002) == 0.001);
  CHECK(metres.coupling.roughness_gap(0.002) == 5e-7);
  CHECK(problems("roughness = 0.01\nroughness_m = 1e-6\n").find("roughness_m") != std::string::npos);
  CHECK(problems("roughness = -1.0\n").find("roughness") != std::string::npos);
  CHECK(problems("lubrication_cutoff = 0.5\nroughness = 0.6\n").find("below the lubrication cut-off") !=
        std::string::npos);
  CHECK(problems("lubrication = 1\n").find("lubrication") != std::string::npos);
}

TEST_CASE("Faxen's resistance along a plane tends to 1 + 9a/(16h), below the normal one, and is held near contact") {
  for (double x : {50.0, 200.0}) {  // h = a + gap: Faxen's leading reflection, half the normal one's 9/8
    CAPTURE(x);
    CHECK(faxen_wall_resistance_tangential(x) - 1.0 == doctest::Approx(9.0 / 16.0 / (1.0 + x)).epsilon(0.02));
  }
  double last = 1.0;
  for (double x = 20.0; x > kFaxenSmallestGap; x *= 0.8) {  // grows towards the plane, less than along the normal
    CAPTURE(x);
    const double tangential = faxen_wall_resistance_tangential(x);
    CHECK(tangential > last);
    CHECK(tangential < wall_resistance(x));
    last = tangential;
  }
  CHECK(faxen_wall_resistance_tangential(0.01) == faxen_wall_resistance_tangential(kFaxenSmallestGap));
}
