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
