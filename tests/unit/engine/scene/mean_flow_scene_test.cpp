// What a grain reads from the mean-flow fluid, as the scene asks (engine/scene/mean_flow_scene.cpp, engine/scene/
// scene.cpp; docs/SCENES.md): by default the mean velocity with the shear lift; `[mean_flow] fluctuations =
// "langevin"` with its constant and seed, `[coupling] lift` off or with its coefficient; a lift without the mean-flow
// fluid, the
// fluctuations without drag and a constant out of range are refused naming the file, line and key.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "engine/scene/scene.hpp"
#include "tests/support/test_support.hpp"

namespace riffle {
namespace {

/// A periodic box of grains under the mean-flow fluid; `mean_flow_keys` end the [mean_flow] table (line 23 on),
/// `after` follows it.
std::string channel(const std::string& mean_flow_keys = "", const std::string& after = "") {
  return "[run]\nname = \"channel\"\nend_time = 0.01\ndt = 1.0e-3\n"
         "[materials.quartz]\ndensity = 2650.0\nyoung_modulus = 1.0e7\npoisson_ratio = 0.3\n"
         "[contact]\nrestitution = 0.5\nfriction = 0.5\n"
         "[tank]\nsize = [0.01, 0.01, 0.02]\nperiodic = [\"x\", \"y\"]\nwall_material = \"quartz\"\n"
         "[[solids.blocks]]\nmin = [0.001, 0.001, 0.001]\nmax = [0.009, 0.009, 0.004]\nspacing = 0.0025\n"
         "radius = 0.001\nmaterial = \"quartz\"\n"
         "[mean_flow]\ncells = 40\n" +
         mean_flow_keys + after;
}

}  // namespace

TEST_CASE("mean-flow grains: the mean velocity and the shear lift by default, the Langevin fluctuations on request") {
  // The lift is on with or without a [coupling] table (its default follows [mean_flow]), and off on request.
  const Model plain = parse_scene(channel(), "channel.toml");
  REQUIRE(plain.mean_flow.enabled);
  CHECK(plain.mean_flow.fluctuations == MeanFlowModel::Fluctuations::kNone);
  CHECK(plain.coupling.lift);
  CHECK(plain.coupling.lift_coefficient == 0.2);
  CHECK(parse_scene(channel("", "[coupling]\ndrag = true\n"), "channel.toml").coupling.lift);
  CHECK_FALSE(parse_scene(channel("", "[coupling]\nlift = false\n"), "channel.toml").coupling.lift);
  CHECK_FALSE(parse_scene(test::coupled_scene_text(), "coupled.toml").coupling.lift);  // the MPS water's grains
  const Model both = parse_scene(
      channel("fluctuations = \"langevin\"\nlangevin_c0 = 5.5\nfluctuation_seed = 42\n",
              "[coupling]\nlift = true\nlift_coefficient = 0.3\n"),
      "channel.toml");
  CHECK(both.mean_flow.fluctuations == MeanFlowModel::Fluctuations::kLangevin);
  CHECK(both.mean_flow.langevin_c0 == 5.5);
  CHECK(both.mean_flow.fluctuation_seed == 42);
  CHECK(both.coupling.lift);
  CHECK(both.coupling.lift_coefficient == 0.3);
  const Model defaults = parse_scene(channel("fluctuations = \"langevin\"\n", "[coupling]\nlift = true\n"), "c.toml");
  CHECK(defaults.mean_flow.langevin_c0 == 4.0);
  CHECK(defaults.mean_flow.fluctuation_seed == 1);
  CHECK(defaults.coupling.lift_coefficient == 0.2);
}

TEST_CASE("mean-flow grains: a lift without the mean-flow fluid, fluctuations without drag or turbulence, a bad constant are refused") {
  // The MPS water's grains: the lift is refused on its line.
  const std::vector<std::string> mps = test::problems_of(test::coupled_scene_text() + "[coupling]\nlift = true\n",
                                                         "coupled.toml");
  REQUIRE(mps.size() == 1);
  CHECK(mps[0].rfind("coupled.toml:20:8: coupling.lift: ", 0) == 0);
  CHECK(mps[0].find("needs [mean_flow]") != std::string::npos);
  const std::vector<std::string> no_drag =
      test::problems_of(channel("fluctuations = \"langevin\"\n", "[coupling]\ndrag = false\n"), "channel.toml");
  REQUIRE(no_drag.size() == 1);
  CHECK(no_drag[0].find("coupling.drag: [mean_flow] fluctuations act through the drag") != std::string::npos);
  const std::vector<std::string> bad = test::problems_of(channel("fluctuations = \"langevin\"\nlangevin_c0 = 0.5\n"),
                                                         "channel.toml");
  REQUIRE(bad.size() == 1);
  CHECK(bad[0].rfind("channel.toml:25:15: mean_flow.langevin_c0: ", 0) == 0);
  const std::vector<std::string> laminar =
      test::problems_of(channel("turbulence = \"laminar\"\nfluctuations = \"langevin\"\n"), "channel.toml");
  REQUIRE(laminar.size() == 1);
  CHECK(laminar[0].find("mean_flow.fluctuations: the Langevin fluctuations scale with the mixing-length") !=
        std::string::npos);
  const std::vector<std::string> kind = test::problems_of(channel("fluctuations = \"random\"\n"), "channel.toml");
  REQUIRE(kind.size() == 1);
  CHECK(kind[0].find("expected one of \"none\", \"langevin\", got \"random\"") != std::string::npos);
}

}  // namespace riffle

TEST_CASE("mean-flow drive: a profile forcing is read with its defaults, given twice, out of the column or at rest it is refused") {
  const std::string forcing = "[mean_flow.profile_forcing]\nvelocity = 0.6\nbase = 0.005\nstrength = 2.5\n";
  const Model plain = parse_scene(channel("initial = \"target_profile\"\n", forcing), "channel.toml");
  const MeanFlowModel::ProfileForcing& read = plain.mean_flow.profile_forcing;
  CHECK(read.enabled);
  CHECK(read.velocity == 0.6);
  CHECK(read.base == 0.005);
  CHECK(read.strength == 2.5);
  CHECK(read.exponent == doctest::Approx(1.0 / 7.0).epsilon(1e-15));
  CHECK(read.volume_fraction == 1.0);
  CHECK(plain.mean_flow.initial == MeanFlowModel::Initial::kTargetProfile);
  CHECK_FALSE(parse_scene(channel(), "channel.toml").mean_flow.profile_forcing.enabled);

  const auto only_problem = [](const std::string& text) {
    const std::vector<std::string> problems = test::problems_of(text, "channel.toml");
    REQUIRE(problems.size() == 1);
    return problems[0];
  };
  CHECK(only_problem(channel("shields_number = 0.1\nshields_diameter = 0.002\nshields_material = \"quartz\"\n", forcing))
            .find("mean_flow.profile_forcing: give the drive once: shields_number") != std::string::npos);
  CHECK(only_problem(channel("", "[mean_flow.body_force]\nkind = \"constant\"\nacceleration = 0.1\n" + forcing))
            .find("give the drive once: [mean_flow.body_force] or [mean_flow.profile_forcing]") != std::string::npos);
  const std::string below = only_problem(
      channel("", "[mean_flow.profile_forcing]\nvelocity = 0.6\nbase = 0.03\nstrength = 2.5\n"));
  CHECK(below.rfind("channel.toml:26:8: mean_flow.profile_forcing.base: ", 0) == 0);
  CHECK(below.find("between its floor (0 m) and its top (0.02 m)") != std::string::npos);
  CHECK(only_problem(channel("", "[mean_flow.profile_forcing]\nvelocity = 0.0\nbase = 0.005\nstrength = 2.5\n"))
            .find("profile_forcing.velocity: a target at rest pulls nothing") != std::string::npos);
  CHECK(only_problem(channel("", "[mean_flow.profile_forcing]\nvelocity = 0.6\nbase = 0.005\n"))
            .find("mean_flow.profile_forcing.strength") != std::string::npos);
  CHECK(only_problem(channel("", "[mean_flow.profile_forcing]\nbase = 0.005\nstrength = 2.5\n"))
            .find("mean_flow.profile_forcing.velocity: missing required key") != std::string::npos);
  CHECK(only_problem(channel("initial = \"target_profile\"\n"))
            .find("mean_flow.initial: \"target_profile\" starts the water on [mean_flow.profile_forcing]'s target") !=
        std::string::npos);
}
