// Bed statistics (engine/bed_statistics.*): class centroids, and per sub-layer the coordination number Z = 2 Nc / Np
// and the mean dimensionless overlap delta* (seed 000 Eqs. 27-28), on hand-built grains and contact lists whose
// answers are known exactly; and the scene keys that switch the bed profile on.
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "systems/physics/measures/bed_statistics.hpp"
#include "engine/scene/scene.hpp"
#include "tests/support/test_support.hpp"
#include "tests/support/scene_builder.hpp"

using namespace riffle;
using riffle::test::SceneBuilder;

namespace {

Solids grains(const std::vector<Vec3>& positions, const std::vector<double>& radii,
              const std::vector<std::int32_t>& classes = {}) {
  Solids solids;
  for (std::size_t k = 0; k < positions.size(); ++k)
    solids.add(positions[k], Vec3::Zero(), radii[k], 1000.0, 0, classes.empty() ? 0 : classes[k]);
  return solids;
}

struct Pair {
  std::uint32_t first, second;
};

/// A contact list holding `pairs` (first < second, grouped by first in ascending order), with the overlaps the
/// geometry gives (the contact force system stores exactly these).
Contacts contact_list(const Solids& solids, const std::vector<Pair>& pairs) {
  Contacts contacts;
  contacts.pair_offsets.assign(solids.size() + 1, 0);
  for (const Pair& pair : pairs) {
    REQUIRE(pair.first < pair.second);
    ++contacts.pair_offsets[pair.first + 1];
    contacts.pair_second.push_back(pair.second);
    const double distance = (solids.position[pair.second] - solids.position[pair.first]).norm();
    contacts.pair_overlap.push_back(solids.radius[pair.first] + solids.radius[pair.second] - distance);
  }
  for (std::size_t k = 0; k < solids.size(); ++k) contacts.pair_offsets[k + 1] += contacts.pair_offsets[k];
  contacts.wall_pair_offsets.assign(solids.size() + 1, 0);
  contacts.valid = true;
  return contacts;
}

}  // namespace

TEST_CASE("class centroids are the volume-weighted mean centre heights above the floor, per class") {
  // Class 0: three equal grains at heights 2, 3 and 5.5 above the floor (z = -1): mean 3.5, exactly.
  // Class 2: a grain of radius 1 at height 1 and one of radius 0.5 at height 10: (1 * 1 + 1/8 * 10) / (9/8) = 2.
  // Class 7 is not asked for; class 5 is asked for but has no grain.
  const Solids solids = grains({{0, 0, 1.0}, {1, 0, 9.0}, {0, 1, 2.0}, {3, 3, 0.0}, {0, 0, 4.5}, {5, 5, 5.0}},
                               {0.5, 0.5, 0.5, 1.0, 0.5, 0.25}, {0, 2, 0, 2, 0, 7});
  const std::vector<ClassCentroid> centroids = class_centroids(solids, {0, 2, 5}, -1.0);
  REQUIRE(centroids.size() == 3);
  CHECK(centroids[0].size_class == 0);
  CHECK(centroids[0].grains == 3);
  CHECK(centroids[0].height == 3.5);
  CHECK(centroids[1].size_class == 2);
  CHECK(centroids[1].grains == 2);
  CHECK(centroids[1].height == 2.0);
  CHECK(centroids[2].size_class == 5);
  CHECK(centroids[2].grains == 0);
  CHECK(std::isnan(centroids[2].height));
}

TEST_CASE("a vertical column of three touching grains: Z and delta* per layer, exactly") {
  // Grain 0: r = 0.5 at z = 0.5 (on the floor); grain 1: r = 0.5 at z = 1.25, overlap 0.25 with grain 0;
  // grain 2: r = 0.25 at z = 1.75, overlap 0.25 with grain 1; grains 0 and 2 are candidates but apart (-0.5).
  // Contact points (middle of the overlap): 0.5 + (0.5 - 0.125) = 0.875 and 1.25 + (0.5 - 0.125) = 1.625.
  // Layers of thickness 1: layer 0 holds grain 0 and the first contact, layer 1 grains 1 and 2 and the second
  // contact, layer 2 nothing.
  const Solids solids = grains({{0, 0, 0.5}, {0, 0, 1.25}, {0, 0, 1.75}}, {0.5, 0.5, 0.25});
  const Contacts contacts = contact_list(solids, {{0, 1}, {0, 2}, {1, 2}});
  CHECK(contacts.pair_overlap == std::vector<double>{0.25, -0.5, 0.25});
  const BedProfile profile = bed_profile(solids, &contacts, 0.0, 1.0, 3);
  REQUIRE(profile.contacts_known);
  REQUIRE(profile.layers.size() == 3);
  const BedLayer& bottom = profile.layers[0];
  CHECK(bottom.z_low == 0.0);
  CHECK(bottom.z_high == 1.0);
  CHECK(bottom.grains == 1);
  CHECK(bottom.contacts == 1);
  CHECK(bottom.coordination_number() == 2.0);            // 2 * 1 / 1
  CHECK(bottom.mean_dimensionless_overlap() == 0.25);    // 0.25 / ((1 + 1) / 2)
  const BedLayer& middle = profile.layers[1];
  CHECK(middle.z_low == 1.0);
  CHECK(middle.z_high == 2.0);
  CHECK(middle.grains == 2);
  CHECK(middle.contacts == 1);
  CHECK(middle.coordination_number() == 1.0);            // 2 * 1 / 2
  CHECK(middle.mean_dimensionless_overlap() == 0.25 / 0.75);  // d_12 = (1 + 0.5) / 2
  const BedLayer& top = profile.layers[2];
  CHECK(top.grains == 0);
  CHECK(top.contacts == 0);
  CHECK(std::isnan(top.coordination_number()));
  CHECK(std::isnan(top.mean_dimensionless_overlap()));

  SUBCASE("heights are measured from the floor: the same column on a floor at z = -2 gives the same layers") {
    const Solids lowered = grains({{0, 0, -1.5}, {0, 0, -0.75}, {0, 0, -0.25}}, {0.5, 0.5, 0.25});
    const BedProfile shifted = bed_profile(lowered, &contacts, -2.0, 1.0, 3);
    for (std::size_t k = 0; k < 3; ++k) {
      CAPTURE(k);
      CHECK(shifted.layers[k].grains == profile.layers[k].grains);
      CHECK(shifted.layers[k].contacts == profile.layers[k].contacts);
      CHECK(shifted.layers[k].overlap_ratio_sum == profile.layers[k].overlap_ratio_sum);
    }
  }
}

TEST_CASE("a horizontal row: Z = 2 Nc / Np = 4/3 and delta* is the mean of the overlap ratios") {
  // Three grains of radius 0.5 at height 0.5 along x, centres 0.75 and 0.875 apart: overlaps 0.25 and 0.125.
  const Solids solids = grains({{0, 0, 0.5}, {0.75, 0, 0.5}, {1.625, 0, 0.5}}, {0.5, 0.5, 0.5});
  const Contacts contacts = contact_list(solids, {{0, 1}, {1, 2}});
  const BedProfile profile = bed_profile(solids, &contacts, 0.0, 1.0, 1);
  REQUIRE(profile.layers.size() == 1);
  CHECK(profile.layers[0].grains == 3);
  CHECK(profile.layers[0].contacts == 2);
  CHECK(profile.layers[0].coordination_number() == 4.0 / 3.0);
  CHECK(profile.layers[0].mean_dimensionless_overlap() == (0.25 + 0.125) / 2.0);
}

TEST_CASE("a contact is counted at its contact point, not at the mid-point of the centres") {
  // Grain A: r = 0.5 at (0, 0, 0.5); grain B: r = 0.4 at (0.48, 0, 1.14): distance 0.8, overlap 0.1, n_z = 0.8.
  // Contact point z = 0.5 + (0.5 - 0.05) 0.8 = 0.86 (layer 17 of 0.05); the centres' mid-point is at 0.82 (layer 16).
  for (const bool a_first : {true, false}) {
    CAPTURE(a_first);
    const Vec3 a(0, 0, 0.5), b(0.48, 0, 1.14);
    const Solids solids = a_first ? grains({a, b}, {0.5, 0.4}) : grains({b, a}, {0.4, 0.5});
    const Contacts contacts = contact_list(solids, {{0, 1}});
    CHECK(contacts.pair_overlap[0] == doctest::Approx(0.1).epsilon(1e-12));
    const BedProfile profile = bed_profile(solids, &contacts, 0.0, 0.05, 40);
    for (std::size_t k = 0; k < profile.layers.size(); ++k) {
      CAPTURE(k);
      CHECK(profile.layers[k].contacts == (k == 17 ? 1u : 0u));
    }
    CHECK(profile.layers[17].overlap_ratio_sum == doctest::Approx(0.1 / 0.9).epsilon(1e-12));
  }
}

TEST_CASE("grains and contacts outside the layers are left out, and unknown contact lists are reported") {
  // One grain below the floor, one above the top layer, one inside.
  const Solids solids = grains({{0, 0, -0.5}, {0, 0, 5.5}, {0, 0, 0.5}}, {0.5, 0.5, 0.5});
  SUBCASE("without a contact model every layer has zero contacts, known") {
    const BedProfile profile = bed_profile(solids, nullptr, 0.0, 1.0, 3);
    CHECK(profile.contacts_known);
    CHECK(profile.layers[0].grains == 1);
    CHECK(profile.layers[1].grains + profile.layers[2].grains == 0);
    CHECK(profile.layers[0].coordination_number() == 0.0);
  }
  SUBCASE("a contact list not built yet (before the first step) leaves the contacts unknown") {
    Contacts unbuilt;
    const BedProfile profile = bed_profile(solids, &unbuilt, 0.0, 1.0, 3);
    CHECK_FALSE(profile.contacts_known);
    CHECK(profile.layers[0].grains == 1);
    CHECK(profile.layers[0].contacts == 0);
  }
}

TEST_CASE("[output] bed_profile_interval and bed_layer_thickness") {
  SUBCASE("off by default; the layer thickness defaults to the smallest grain diameter") {
    const Model model = test::small_model();
    CHECK(model.output.bed_profile_interval == 0.0);
    CHECK(model.output.bed_layer_thickness == 0.0);
    Solids solids = grains({{0.1, 0.1, 0.1}, {0.1, 0.1, 0.12}, {0.1, 0.1, 0.14}}, {0.0075, 0.0025, 0.005}, {2, 0, 1});
    CHECK(bed_layer_thickness(model, solids) == 0.005);  // the smallest diameter
    CHECK(bed_layer_count(model, 0.005) == 40);          // 0.20 m / 5 mm
    CHECK(size_classes(solids) == std::vector<std::int32_t>{0, 1, 2});
    CHECK(bed_layer_thickness(model, Solids{}) == 0.0);
    CHECK(oscillation_periods(model, 2.0) == doctest::Approx(3.4));  // f = 1.7 Hz
  }
  SUBCASE("set explicitly") {
    const Model model =
        parse_scene(test::small_scene_text("\n[output]\nbed_profile_interval = 0.01\nbed_layer_thickness = 0.03\n"),
                    "small.toml");
    CHECK(model.output.bed_profile_interval == 0.01);
    CHECK(bed_layer_thickness(model, Solids{}) == 0.03);
    CHECK(bed_layer_count(model, 0.03) == 7);  // ceil(0.20 / 0.03)
  }
  SUBCASE("negative values are refused with file:line:column: key") {
    const std::string text =
        test::small_scene_text("\n[output]\nbed_profile_interval = -1.0\nbed_layer_thickness = 0\n");
    try {
      parse_scene(text, "small.toml");
      FAIL("accepted");
    } catch (const SceneError& error) {
      REQUIRE(error.problems().size() == 2);
      CHECK(error.problems()[0].find("output.bed_profile_interval: expected a number >= 0 [s], got -1") !=
            std::string::npos);
      CHECK(error.problems()[1].find("output.bed_layer_thickness: expected a number > 0 [m], got 0") !=
            std::string::npos);
      CHECK(error.problems()[0].rfind("small.toml:", 0) == 0);
    }
  }
  SUBCASE("a bed profile without grains is refused") {
    const std::string text = SceneBuilder().run({.end_time = 0.1, .dt = 1.0e-3})
        .material("grain", {.density = 1000.0}).tank({.size = {0.1, 0.1, 0.1}, .wall_material = "grain"})
        .output().set("bed_profile_interval", 0.01).toml();
    CHECK_THROWS_WITH_AS(parse_scene(text, "empty.toml"), doctest::Contains("the bed profile needs grains"),
                         SceneError);
  }
}
