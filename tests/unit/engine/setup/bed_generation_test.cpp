// Bed generation: the seed's three-layer bed (seed 000 Sec. 2 and 4.1: 135 large 15 mm, 537 medium 10 mm and
// 7,490 small 5 mm spheres in three 15 mm layers over a 0.24 m x 0.16 m tank floor) and box fills must have
// exactly the asked counts per class and layer, no overlapping spheres, every sphere inside its region and slab,
// and be reproducible from their seed. The scene tables must report every problem at its file:line:column and key:
// as they are read, or (a bed whose random grains jam) when the run generates them.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <numeric>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "engine/scene/bed_scene.hpp"
#include "engine/scene/scene.hpp"
#include "engine/setup/bed_generation.hpp"
#include "engine/toml/scene_reader.hpp"
#include "tests/support/test_support.hpp"

namespace {

using test::joined;

using riffle::BedArrangement;
using riffle::BedGenerationError;
using riffle::FillSpec;
using riffle::LayeredBedSpec;
using riffle::SphereSpec;
using riffle::Vec3;

constexpr std::int32_t kSmall = 0, kMedium = 1, kLarge = 2;  // size classes of the seed bed

/// The seed's bed over the whole floor of its 0.24 m x 0.16 m tank, loosened by the factor docs/SCENES.md gives.
LayeredBedSpec seed_bed(std::uint64_t seed = 1) {
  LayeredBedSpec spec;
  spec.x_min = 0.0;
  spec.x_max = 0.24;
  spec.y_min = 0.0;
  spec.y_max = 0.16;
  spec.base = 0.0;
  spec.layers = 3;
  spec.layer_thickness = 0.015;
  spec.loose_factor = 1.7;
  spec.seed = seed;
  // Small first on purpose: the generator must still lay out the regular classes first, largest first.
  spec.classes = {{{0.005, 7490, 0, kSmall}, BedArrangement::kRandom},
                  {{0.010, 537, 1, kMedium}, BedArrangement::kRegular},
                  {{0.015, 135, 2, kLarge}, BedArrangement::kRegular}};
  return spec;
}

/// The layer whose slab holds the whole sphere, or -1 if none does.
int layer_of(const LayeredBedSpec& spec, const SphereSpec& sphere) {
  constexpr double kTolerance = 1e-12;  // [m] rounding of bottom + radius
  for (std::int64_t layer = 0; layer < spec.layers; ++layer)
    if (sphere.position.z() - sphere.radius >= spec.slab_bottom(layer) - kTolerance &&
        sphere.position.z() + sphere.radius <= spec.slab_bottom(layer + 1) + kTolerance)
      return static_cast<int>(layer);
  return -1;
}

/// Pairs of spheres closer than the sum of their radii. Sweep along x (independent of the generator's grid): only
/// spheres whose x differ by less than the largest contact distance are compared.
std::size_t count_overlaps(const std::vector<SphereSpec>& spheres) {
  std::vector<std::size_t> order(spheres.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return spheres[a].position.x() < spheres[b].position.x(); });
  double largest_radius = 0.0;
  for (const SphereSpec& sphere : spheres) largest_radius = std::max(largest_radius, sphere.radius);
  std::size_t overlaps = 0;
  for (std::size_t a = 0; a < order.size(); ++a) {
    const SphereSpec& first = spheres[order[a]];
    for (std::size_t b = a + 1; b < order.size(); ++b) {
      const SphereSpec& second = spheres[order[b]];
      if (second.position.x() - first.position.x() >= first.radius + largest_radius) break;
      const double contact = first.radius + second.radius;
      if ((second.position - first.position).squaredNorm() < contact * contact) ++overlaps;
    }
  }
  return overlaps;
}

bool inside_box(const SphereSpec& sphere, const Vec3& low, const Vec3& high) {
  constexpr double kTolerance = 1e-12;  // [m]
  return (sphere.position.array() - sphere.radius >= low.array() - kTolerance).all() &&
         (sphere.position.array() + sphere.radius <= high.array() + kTolerance).all();
}

}  // namespace

TEST_CASE("count_in_layer gives the remainder to the first layers") {
  CHECK(riffle::count_in_layer(7490, 3, 0) == 2497);
  CHECK(riffle::count_in_layer(7490, 3, 1) == 2497);
  CHECK(riffle::count_in_layer(7490, 3, 2) == 2496);
  CHECK(riffle::count_in_layer(537, 3, 2) == 179);
  CHECK(riffle::count_in_layer(2, 3, 2) == 0);
  CHECK(riffle::count_in_layer(0, 3, 0) == 0);
}

TEST_CASE("the seed bed has the seed's counts per class and per layer, layer by layer, regular classes first") {
  const LayeredBedSpec spec = seed_bed();
  // The seed's bed at its nominal 4.5 cm: 58% solid.
  CHECK(riffle::nominal_solid_fraction(spec) == doctest::Approx(0.5845).epsilon(1e-3));
  const std::vector<SphereSpec> spheres = riffle::generate_layered_bed(spec);
  REQUIRE(spheres.size() == 135 + 537 + 7490);

  std::map<std::pair<int, std::int32_t>, int> per_layer_and_class;
  int previous_layer = 0;
  bool random_seen = false;  // in the current layer
  std::size_t out_of_order = 0, outside = 0;
  for (const SphereSpec& sphere : spheres) {
    const int layer = layer_of(spec, sphere);
    if (layer < 0) {
      ++outside;
      continue;
    }
    if (layer != previous_layer) random_seen = false;
    const bool random = sphere.size_class == kSmall;
    // Layers ascend; in a layer large, then medium, then small.
    if (layer < previous_layer || (random_seen && !random)) ++out_of_order;
    random_seen = random_seen || random;
    previous_layer = layer;
    ++per_layer_and_class[{layer, sphere.size_class}];
  }
  CHECK(outside == 0);
  CHECK(out_of_order == 0);
  for (int layer = 0; layer < 3; ++layer) {
    CAPTURE(layer);
    CHECK(per_layer_and_class[{layer, kLarge}] == 45);
    CHECK(per_layer_and_class[{layer, kMedium}] == 179);
    CHECK(per_layer_and_class[{layer, kSmall}] == (layer < 2 ? 2497 : 2496));
  }
  // The first layer starts with its 45 large spheres, then its 179 medium ones.
  for (std::size_t k = 0; k < 45 + 179; ++k) {
    CAPTURE(k);
    REQUIRE(spheres[k].size_class == (k < 45 ? kLarge : kMedium));
  }

  // Each class keeps its diameter and material; the bed starts at rest.
  std::size_t wrong = 0;
  for (const SphereSpec& sphere : spheres) {
    const double diameter = sphere.size_class == kSmall ? 0.005 : sphere.size_class == kMedium ? 0.010 : 0.015;
    if (sphere.radius != 0.5 * diameter || sphere.material != sphere.size_class ||
        sphere.velocity != Vec3::Zero() || sphere.angular_velocity != Vec3::Zero())
      ++wrong;
  }
  CHECK(wrong == 0);
}

TEST_CASE("the seed bed's regular classes form one interleaved lattice, the same in every layer") {
  const LayeredBedSpec spec = seed_bed();
  const std::vector<SphereSpec> spheres = riffle::generate_layered_bed(spec);
  std::map<int, std::vector<Vec3>> regular_by_layer;
  std::set<double> large_x, large_y, regular_x, regular_y;
  for (const SphereSpec& sphere : spheres) {
    if (sphere.size_class == kSmall) continue;
    const int layer = layer_of(spec, sphere);
    // Regular spheres rest on the bottom of their slab.
    CHECK(sphere.position.z() == doctest::Approx(spec.slab_bottom(layer) + sphere.radius).epsilon(1e-12));
    regular_by_layer[layer].push_back(
        Vec3(sphere.position.x(), sphere.position.y(), static_cast<double>(sphere.size_class)));
    if (layer != 0) continue;
    regular_x.insert(sphere.position.x());
    regular_y.insert(sphere.position.y());
    if (sphere.size_class == kLarge) {
      large_x.insert(sphere.position.x());
      large_y.insert(sphere.position.y());
    }
  }
  // 224 regular spheres per layer on a 19 x 12 lattice (12.6 mm x 13.3 mm apart, just over the 12.5 mm a large
  // and a medium sphere need), the large ones on a 9 x 5 sub-lattice so that no two are neighbours.
  CHECK(regular_x.size() == 19);
  CHECK(regular_y.size() == 12);
  CHECK(large_x.size() == 9);
  CHECK(large_y.size() == 5);
  REQUIRE(regular_by_layer.size() == 3);
  CHECK(regular_by_layer[1] == regular_by_layer[0]);
  CHECK(regular_by_layer[2] == regular_by_layer[0]);
}

TEST_CASE("no two spheres of the seed bed overlap, and all lie inside the region") {
  const LayeredBedSpec spec = seed_bed();
  const std::vector<SphereSpec> spheres = riffle::generate_layered_bed(spec);
  REQUIRE(spheres.size() == 8162);
  CHECK(count_overlaps(spheres) == 0);
  const Vec3 low(spec.x_min, spec.y_min, spec.base);
  const Vec3 high(spec.x_max, spec.y_max, spec.slab_bottom(spec.layers));
  CHECK(std::count_if(spheres.begin(), spheres.end(),
                      [&](const SphereSpec& sphere) { return !inside_box(sphere, low, high); }) == 0);
  // The bed is loose: its top is loose_factor x 4.5 cm up.
  CHECK(high.z() == doctest::Approx(0.045 * 1.7));
  double top = 0.0;
  for (const SphereSpec& sphere : spheres) top = std::max(top, sphere.position.z() + sphere.radius);
  CHECK(top > 0.9 * high.z());
}

TEST_CASE("the same seed gives a bit-identical bed, another seed another arrangement of the random class") {
  const std::vector<SphereSpec> first = riffle::generate_layered_bed(seed_bed(1));
  const std::vector<SphereSpec> again = riffle::generate_layered_bed(seed_bed(1));
  const std::vector<SphereSpec> other = riffle::generate_layered_bed(seed_bed(2));
  REQUIRE(first.size() == again.size());
  REQUIRE(first.size() == other.size());
  std::size_t differ_again = 0, differ_other_random = 0, differ_other_regular = 0;
  for (std::size_t k = 0; k < first.size(); ++k) {
    // Exact comparison: the generator uses no library-defined distribution, so this holds on any platform.
    if (first[k].position != again[k].position || first[k].radius != again[k].radius ||
        first[k].size_class != again[k].size_class)
      ++differ_again;
    if (first[k].position != other[k].position) ++(first[k].size_class == kSmall ? differ_other_random
                                                                                 : differ_other_regular);
  }
  CHECK(differ_again == 0);
  CHECK(differ_other_random > 7400);  // practically every small sphere moves
  CHECK(differ_other_regular == 0);   // the lattice does not depend on the seed
}

TEST_CASE("a bed too dense for random sequential addition is refused with a larger loose_factor suggested") {
  // One layer, 0.06 m x 0.04 m x 15 mm, two regular 15 mm spheres and 250 random 5 mm ones: solid fraction 0.55.
  LayeredBedSpec spec;
  spec.x_max = 0.06;
  spec.y_max = 0.04;
  spec.layers = 1;
  spec.layer_thickness = 0.015;
  spec.loose_factor = 1.0;
  spec.classes = {{{0.015, 2, 0, kLarge}, BedArrangement::kRegular},
                  {{0.005, 250, 0, kSmall}, BedArrangement::kRandom}};
  SUBCASE("jammed: the problem names the class's count, how many were placed and a loose_factor to try") {
    try {
      riffle::generate_layered_bed(spec);
      FAIL("a jammed bed was generated");
    } catch (const BedGenerationError& error) {
      const std::string message = error.what();
      CAPTURE(message);
      CHECK(error.class_index() == std::optional<std::size_t>(1));
      CHECK(error.key() == "count");
      CHECK(message.find("placed only ") != std::string::npos);
      CHECK(message.find(" of the 250 spheres of this class in layer 1") != std::string::npos);
      const std::string suggestion = "raise loose_factor (now 1), e.g. to ";
      const std::size_t at = message.find(suggestion);
      REQUIRE(at != std::string::npos);
      spec.loose_factor = std::stod(message.substr(at + suggestion.size()));
    }
    CAPTURE(spec.loose_factor);
    CHECK(spec.loose_factor > 1.0);
    CHECK(riffle::generate_layered_bed(spec).size() == 252);  // the suggestion works
  }
  SUBCASE("hopeless (denser than random close packing): refused at once at loose_factor") {
    spec.classes[1].count = 400;
    try {
      riffle::generate_layered_bed(spec);
      FAIL("a hopeless bed was generated");
    } catch (const BedGenerationError& error) {
      CHECK(!error.class_index());
      CHECK(error.key() == "loose_factor");
      CHECK(std::string(error.what()).find("solid fraction of 0.") != std::string::npos);
    }
  }
  SUBCASE("regular classes that do not fit their lattice") {
    spec.classes[0].count = 12;  // 12 x 15 mm spheres need 4 x 3 x 15 mm: 0.06 x 0.045 > 0.04
    try {
      riffle::generate_layered_bed(spec);
      FAIL("overlapping regular spheres were generated");
    } catch (const BedGenerationError& error) {
      CHECK(error.class_index() == std::optional<std::size_t>(0));
      CHECK(error.key() == "count");
      CHECK(std::string(error.what()).find("cannot lay out the regular spheres of layer 1") != std::string::npos);
    }
  }
}

TEST_CASE("a fill has its counts, no overlaps, every sphere in the box, largest first, reproducibly") {
  FillSpec spec;
  spec.min = Vec3(0.01, 0.02, 0.03);
  spec.max = Vec3(0.11, 0.07, 0.09);
  spec.seed = 42;
  spec.classes = {{0.004, 900, 0, 0}, {0.012, 30, 1, 2}, {0.008, 0, 0, 1}, {0.006, 150, 1, 1}};
  const std::vector<SphereSpec> spheres = riffle::generate_fill(spec);
  REQUIRE(spheres.size() == 1080);
  std::map<std::int32_t, int> per_class;
  for (const SphereSpec& sphere : spheres) ++per_class[sphere.size_class];
  CHECK(per_class[0] == 900);
  CHECK(per_class[1] == 150);
  CHECK(per_class[2] == 30);
  CHECK(spheres.front().radius == 0.006);
  CHECK(spheres[30].radius == 0.003);
  CHECK(spheres.back().radius == 0.002);
  CHECK(count_overlaps(spheres) == 0);
  CHECK(std::count_if(spheres.begin(), spheres.end(), [&](const SphereSpec& sphere) {
          return !inside_box(sphere, spec.min, spec.max) || sphere.velocity != Vec3::Zero();
        }) == 0);

  const std::vector<SphereSpec> again = riffle::generate_fill(spec);
  REQUIRE(again.size() == spheres.size());
  CHECK(std::equal(spheres.begin(), spheres.end(), again.begin(),
                   [](const SphereSpec& a, const SphereSpec& b) { return a.position == b.position; }));
  spec.seed = 43;
  const std::vector<SphereSpec> other = riffle::generate_fill(spec);
  CHECK(!std::equal(spheres.begin(), spheres.end(), other.begin(),
                    [](const SphereSpec& a, const SphereSpec& b) { return a.position == b.position; }));

  SUBCASE("too full: refused, naming the class and the count placed") {
    spec.classes = {{0.004, 8000, 0, 0}};  // solid fraction 0.89: beyond any packing
    CHECK_THROWS_WITH_AS(riffle::generate_fill(spec), doctest::Contains("enlarge the box"), BedGenerationError);
    spec.classes = {{0.004, 4000, 0, 0}};  // 0.45: random sequential addition jams first
    try {
      riffle::generate_fill(spec);
      FAIL("a jammed fill was generated");
    } catch (const BedGenerationError& error) {
      CHECK(error.class_index() == std::optional<std::size_t>(0));
      CHECK(error.key() == "count");
      CHECK(std::string(error.what()).find("of the 4000 spheres of this class") != std::string::npos);
    }
  }
}

// ---------------------------------------------------------------------------------------------------------------
// The scene tables, read directly (as read_solids calls read_bed_generators) with a hand-made Model, then generated
// as set-up generates them (scene_spheres).

namespace {

// The seed bed and a fill above it. Every line a test case changes occurs once.
constexpr std::string_view kBedScene = R"(# Bed generator tables.
[solids]

[[solids.spheres]]
position = [0.1, 0.1, 0.15]

[[solids.layered_beds]]
x_min = 0.0
x_max = 0.24
y_min = 0.0
y_max = 0.16
base = 0.0
layers = 3
layer_thickness = 0.015
loose_factor = 1.7
seed = 1

[[solids.layered_beds.classes]]
diameter = 0.005
count = 7490
material = "grain"
size_class = 0
arrangement = "random"

[[solids.layered_beds.classes]]
diameter = 0.010
count = 537
material = "grain"
size_class = 1
arrangement = "regular"

[[solids.layered_beds.classes]]
diameter = 0.015
count = 135
material = "grain"
size_class = 2
arrangement = "regular"

[[solids.fills]]
min = [0.0, 0.0, 0.12]
max = [0.24, 0.16, 0.3]
seed = 7

[[solids.fills.classes]]
diameter = 0.008
count = 200
material = "glass"
size_class = 3
)";

struct ReadResult {
  riffle::Model model;
  std::vector<std::string> problems;  ///< found while reading
};

/// Reads the bed tables of `text` as read_solids does: [[solids.spheres]] is skipped (asked for, so not unknown),
/// then read_bed_generators, then finish() on [solids].
ReadResult read_beds(const std::string& text) {
  ReadResult result;
  result.model.materials = {{"glass", 2500.0}, {"grain", 1318.0}};
  result.model.tank.size = Vec3(0.24, 0.16, 0.20);
  riffle::SceneProblems problems{"beds.toml", {}};
  std::optional<toml::table> root = riffle::parse_toml(text, problems);
  REQUIRE(root);
  riffle::TableReader scene(*root, "", problems);
  if (auto solids = scene.table("solids", true)) {
    for (riffle::TableReader& sphere : solids->tables("spheres")) {
      SphereSpec spec;
      spec.position = sphere.vec3("position", std::nullopt, "m", riffle::Bounds::any());
      result.model.solids.spheres.push_back(spec);
    }
    riffle::read_bed_generators(*solids, result.model);
    solids->finish();
  }
  scene.finish();
  result.problems = problems.lines;
  return result;
}

using riffle::test::count_of, riffle::test::replace_once;

/// "beds.toml:LINE:COLUMN: " for `needle` in `text` (which must occur once); a '^' in the needle marks the column.
std::string location_of(std::string_view text, const std::string& needle) {
  return riffle::test::location("beds.toml", text, needle);
}


/// The problems set-up finds generating the beds and fills of a model read without problems (none if it generates).
std::vector<std::string> setup_problems(const riffle::Model& model) {
  try {
    riffle::scene_spheres(model);
  } catch (const riffle::SceneError& error) {
    return error.problems();
  }
  return {};
}

}  // namespace

TEST_CASE("read_bed_generators keeps the seed bed and the fill, which set-up generates after the spheres") {
  const ReadResult result = read_beds(std::string(kBedScene));
  CHECK_MESSAGE(result.problems.empty(), joined(result.problems));
  // The model holds the tables as read, not their spheres.
  REQUIRE(result.model.solids.spheres.size() == 1);
  REQUIRE(result.model.solids.layered_beds.size() == 1);
  REQUIRE(result.model.solids.fills.size() == 1);
  CHECK(result.model.solids.layered_beds[0].classes.size() == 3);
  CHECK(riffle::scene_sphere_count(result.model.solids) == 1 + 8162 + 200);
  const std::vector<SphereSpec> spheres = riffle::scene_spheres(result.model);
  REQUIRE(spheres.size() == 1 + 8162 + 200);
  CHECK(spheres[0].position == Vec3(0.1, 0.1, 0.15));
  // Same spheres, same order as the generator gives for the same spec (materials by name: grain is index 1).
  LayeredBedSpec spec = seed_bed();
  for (auto& grains : spec.classes) grains.material = 1;
  const std::vector<SphereSpec> bed = riffle::generate_layered_bed(spec);
  CHECK(std::equal(bed.begin(), bed.end(), spheres.begin() + 1, [](const SphereSpec& a, const SphereSpec& b) {
    return a.position == b.position && a.radius == b.radius && a.material == b.material &&
           a.size_class == b.size_class;
  }));
  // The fill's box reaches above the tank (0.20 m): only its part inside the tank is filled.
  const auto fill_begin = spheres.begin() + 1 + 8162;
  CHECK(std::all_of(fill_begin, spheres.end(), [](const SphereSpec& sphere) {
    return sphere.material == 0 && sphere.size_class == 3 && sphere.radius == 0.004 &&
           inside_box(sphere, Vec3(0.0, 0.0, 0.12), Vec3(0.24, 0.16, 0.20));
  }));
}

TEST_CASE("bad bed and fill tables are reported with file, line, column, key and a useful message") {
  struct BadTable {
    const char* find;      // text of kBedScene to change (must occur once)
    const char* replace;   // what it becomes
    const char* at;        // where the problem must be reported: unique text of the mutated scene, '^' = column
    const char* key;       // full key
    const char* message;   // fragment of the message
    std::size_t problems;  // how many problems in all
    bool at_setup = false; // found only when the run generates the table (random grains that jam), not as it is read
  };
  const std::vector<BadTable> cases = {
      // Keys, types and ranges.
      {"layer_thickness = 0.015", "layer_thicknes = 0.015", "^layer_thicknes", "solids.layered_beds[0].layer_thicknes",
       "unknown key (known keys here: base, classes, layer_thickness, layers, loose_factor, seed, x_max, x_min, "
       "y_max, y_min)", 2},
      {"layer_thickness = 0.015", "layer_thicknes = 0.015", "^[[solids.layered_beds]]",
       "solids.layered_beds[0].layer_thickness", "missing required key; expected a number > 0 [m]", 2},
      {"size_class = 1\n", "size_class = 1\ncolour = \"red\"\n", "^colour", "solids.layered_beds[0].classes[1].colour",
       "unknown key", 1},
      {"size_class = 3\n", "size_class = 3\narrangement = \"regular\"\n", "size_class = 3\n^arrangement",
       "solids.fills[0].classes[0].arrangement", "unknown key", 1},
      {"diameter = 0.010", "diameter = 0.0", "diameter = ^0.0\n", "solids.layered_beds[0].classes[1].diameter",
       "expected a number > 0 [m], got 0", 1},
      {"diameter = 0.008", "diameter = -0.008", "diameter = ^-0.008", "solids.fills[0].classes[0].diameter",
       "expected a number > 0 [m], got -0.008", 1},
      {"count = 537", "count = -1", "count = ^-1", "solids.layered_beds[0].classes[1].count",
       "expected an integer in [0, 50000000], got -1", 1},
      {"count = 200", "count = 2.5", "count = ^2.5", "solids.fills[0].classes[0].count", "got a number", 1},
      {"count = 537\nmaterial = \"grain\"", "count = 537\nmaterial = \"gravel\"", "material = ^\"gravel\"",
       "solids.layered_beds[0].classes[1].material", "unknown material \"gravel\" (materials defined: glass, grain)",
       1},
      {"arrangement = \"regular\"\n\n[[solids.layered_beds.classes]]\ndiameter = 0.015",
       "arrangement = \"grid\"\n\n[[solids.layered_beds.classes]]\ndiameter = 0.015", "arrangement = ^\"grid\"",
       "solids.layered_beds[0].classes[1].arrangement", "expected one of \"regular\", \"random\", got \"grid\"", 1},
      {"loose_factor = 1.7", "loose_factor = 0.9", "loose_factor = ^0.9", "solids.layered_beds[0].loose_factor",
       "expected a number in [1, 1000] [1], got 0.9", 1},
      {"layers = 3", "layers = 0", "layers = ^0", "solids.layered_beds[0].layers", "expected an integer in [1, 1000]",
       1},
      {"seed = 7", "seed = -7", "seed = ^-7", "solids.fills[0].seed", "got -7", 1},
      {"\n[[solids.fills.classes]]\ndiameter = 0.008\ncount = 200\nmaterial = \"glass\"\nsize_class = 3\n", "",
       "^[[solids.fills]]", "solids.fills[0].classes", "expected at least one [[solids.fills[0].classes]] table", 1},
      // Geometry.
      {"x_max = 0.24", "x_max = 0.3", "x_max = ^0.3", "solids.layered_beds[0].x_max",
       "the region must lie inside the tank (the tank spans x from 0 to 0.24)", 1},
      {"y_min = 0.0", "y_min = 0.2", "y_max = ^0.16", "solids.layered_beds[0].y_max",
       "y_max must be greater than y_min", 1},
      {"loose_factor = 1.7", "loose_factor = 5", "loose_factor = ^5", "solids.layered_beds[0].loose_factor",
       "the loosened bed (layers x layer_thickness x loose_factor = 0.225 m above the base) rises above the tank", 1},
      {"diameter = 0.015", "diameter = 0.03", "diameter = ^0.03", "solids.layered_beds[0].classes[2].diameter",
       "a 0.03 m sphere does not fit in a layer 0.0255 m thick", 1},
      {"count = 135", "count = 300", "count = ^300", "solids.layered_beds[0].classes[2].count",
       "cannot lay out the regular spheres of layer 1 without overlap", 1},
      {"loose_factor = 1.7", "loose_factor = 1.2", "count = ^7490", "solids.layered_beds[0].classes[0].count",
       "placed only", 1, true},
      {"count = 7490", "count = 30000", "loose_factor = ^1.7", "solids.layered_beds[0].loose_factor",
       "layer 1 would have a solid fraction of 0.8", 1},
      {"min = [0.0, 0.0, 0.12]", "min = [0.0, 0.0, 0.25]", "min = ^[0.0, 0.0, 0.25]", "solids.fills[0].min",
       "the box does not overlap the tank", 1},
      {"min = [0.0, 0.0, 0.12]", "min = [0.0, 0.2, 0.12]", "max = ^[0.24", "solids.fills[0].max",
       "every component of max must be > the one of min", 1},
      {"count = 200", "count = 20000", "^[[solids.fills.classes]]", "solids.fills[0].classes",
       "would fill the box to a solid fraction of", 1},
  };
  for (const BadTable& bad : cases) {
    const std::string text = replace_once(kBedScene, bad.find, bad.replace);
    const std::string prefix = location_of(text, bad.at) + bad.key + ": ";
    CAPTURE(text);
    const ReadResult read = read_beds(text);
    CHECK_MESSAGE(read.problems.empty() == bad.at_setup, "read: ", joined(read.problems));
    const std::vector<std::string> problems = bad.at_setup ? setup_problems(read.model) : read.problems;
    const bool found = std::any_of(problems.begin(), problems.end(), [&](const std::string& line) {
      return line.rfind(prefix, 0) == 0 && line.find(bad.message, prefix.size()) != std::string::npos;
    });
    CHECK_MESSAGE(found, "no problem starts with \"", prefix, "\" and mentions \"", std::string(bad.message),
                  "\"; got:\n", joined(problems));
    CHECK_MESSAGE(problems.size() == bad.problems, "expected ", bad.problems, " problem(s), got:\n", joined(problems));
  }
}

TEST_CASE("with no valid tank size the bed tables are checked, but no region is judged and nothing kept") {
  riffle::Model model;
  model.materials = {{"glass", 2500.0}, {"grain", 1318.0}};  // tank size left zero, as after a bad [tank]
  riffle::SceneProblems problems{"beds.toml", {}};
  std::optional<toml::table> root = riffle::parse_toml(std::string(kBedScene), problems);
  REQUIRE(root);
  riffle::TableReader scene(*root, "", problems);
  auto solids = scene.table("solids", true);
  REQUIRE(solids);
  solids->tables("spheres");
  riffle::read_bed_generators(*solids, model);
  CHECK_MESSAGE(problems.lines.empty(), joined(problems.lines));
  CHECK(model.solids.layered_beds.empty());
  CHECK(model.solids.fills.empty());
}

TEST_CASE("bed and fill lists that are not arrays of tables are reported") {
  const std::vector<std::string> problems = read_beds("[solids]\nlayered_beds = 5\nfills = [1, 2]\n").problems;
  CAPTURE(joined(problems));
  REQUIRE(problems.size() == 2);
  CHECK(problems[0] == "beds.toml:2:16: solids.layered_beds: expected an array of tables ([[solids.layered_beds]]), "
                       "got an integer");
  CHECK(problems[1].rfind("beds.toml:3:9: solids.fills: expected an array of tables ([[solids.fills]])", 0) == 0);
}

TEST_CASE("a hexagonal close-packed block: every sphere touches its neighbours at the spacing, none nearer, 12 inside") {
  // 6 x 6 rows x 4 layers of 2 mm spheres touching, in a closed 2 cm box: the scene's counts come from the lattice's
  // pitches (spacing, spacing sqrt(3)/2, spacing sqrt(2/3)).
  const std::string scene =
      "[run]\nname = \"hexagonal\"\nend_time = 0.01\ndt = 1.0e-3\n"
      "[materials.grain]\ndensity = 2650.0\nyoung_modulus = 1.0e7\npoisson_ratio = 0.3\n"
      "[tank]\nsize = [0.02, 0.02, 0.02]\nwall_material = \"grain\"\n"
      "[[solids.blocks]]\nmin = [0.001, 0.001, 0.001]\nmax = [0.0115, 0.0095, 0.0060]\n"
      "spacing = 0.002\nradius = 0.001\nmaterial = \"grain\"\nlattice = \"hexagonal\"\n";
  const riffle::Model model = riffle::parse_scene(scene, "hexagonal.toml");
  REQUIRE(model.solids.blocks.size() == 1);
  const riffle::SphereBlockSpec& block = model.solids.blocks[0];
  CHECK(block.counts == std::array<std::int64_t, 3>{6, 5, 4});
  const std::vector<SphereSpec> spheres = riffle::generate_block(block, model.tank);
  CHECK(static_cast<std::int64_t>(spheres.size()) == block.count);
  // Odd rows, shifted half a spacing, lose their last sphere only where it would leave the box (it does not here).
  CHECK(spheres.size() == 6u * 5u * 4u);
  double nearest = 1.0;
  std::size_t full = 0;
  for (std::size_t a = 0; a < spheres.size(); ++a) {
    std::size_t touching = 0;
    for (std::size_t b = 0; b < spheres.size(); ++b) {
      if (a == b) continue;
      const double distance = (spheres[a].position - spheres[b].position).norm();
      nearest = std::min(nearest, distance);
      if (std::abs(distance - 0.002) < 1e-12) ++touching;
    }
    CHECK(touching <= 12u);
    if (touching == 12) ++full;  // an interior sphere of close packing
  }
  CHECK(nearest == doctest::Approx(0.002).epsilon(1e-12));
  CHECK(full > 0u);
  // Each sphere of the second layer sits over three of the first, touching them.
  const Vec3 upper = spheres[6 * 5].position;  // the first of layer 1
  int below = 0;
  for (std::size_t b = 0; b < 6u * 5u; ++b)
    if (std::abs((upper - spheres[b].position).norm() - 0.002) < 1e-12) ++below;
  CHECK(below == 3);
}
