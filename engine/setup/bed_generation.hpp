#pragma once
// Generated initial beds for the solid phase. Seed 000 (Sec. 2 and 4.1) builds its movable bed from three layers,
// each of regularly arranged large (15 mm) and medium (10 mm) grains with small (5 mm) grains set randomly among
// them; generate_layered_bed builds that bed (and others like it), generate_fill fills a box with a size
// distribution. Both are pure functions of their spec: the same spec and seed give bit-identical spheres, in a
// fixed order, so grain ids are reproducible. The beds are loose (no two spheres overlap, none touch a slab or box
// face from outside); a scene settles them under gravity with DEM.
//
// engine/scene/bed_scene.hpp reads the scene tables [[solids.layered_beds]] and [[solids.fills]] (docs/SCENES.md).
#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "components/vec.hpp"
#include "components/model.hpp"
#include "engine/toml/scene_reader.hpp"

namespace riffle {

/// One grain size class of a generated bed.
struct GrainClassSpec {
  double diameter = 0.0;        ///< [m]
  std::int64_t count = 0;       ///< spheres in the whole bed (all layers together)
  std::int32_t material = 0;    ///< index into Model::materials
  std::int32_t size_class = 0;  ///< copied to SphereSpec::size_class
};

enum class BedArrangement {
  kRegular,  ///< on a rectangular lattice shared by all regular classes of the layer
  kRandom,   ///< random sequential addition into the space the regular grains leave free
};

struct BedClassSpec : GrainClassSpec {
  BedArrangement arrangement = BedArrangement::kRandom;
};

/// A bed of `layers` equal layers stacked from z = base over the rectangle [x_min, x_max] x [y_min, y_max].
/// Each layer is generated in a slab of height layer_thickness * loose_factor (the nominal layer stretched so that
/// random sequential addition, which jams near a solid fraction of 0.38, can place the random classes); the
/// scene then settles the bed to about its nominal thickness. The seed bed (3 layers of 15 mm, 135 large, 537
/// medium, 7490 small over 0.24 m x 0.16 m) has a solid fraction of 0.585 at its nominal 4.5 cm: 0.585 / 0.38
/// suggests 1.54. Measured with seeds 1-5: 1.45 jams for four of them, 1.48 passes all in about 0.6 s (near the
/// jam every sphere costs many attempts), 1.6 in 80 ms, 1.7 in 40 ms; 1.7 is the value to use (docs/SCENES.md).
struct LayeredBedSpec {
  double x_min = 0.0;            ///< [m] region
  double x_max = 0.0;            ///< [m]
  double y_min = 0.0;            ///< [m]
  double y_max = 0.0;            ///< [m]
  double base = 0.0;             ///< [m] bottom of the lowest layer
  std::int64_t layers = 1;
  double layer_thickness = 0.0;  ///< [m] nominal (settled) thickness of one layer
  double loose_factor = 1.0;     ///< [1] >= 1: vertical stretch of each layer at generation time
  std::uint64_t seed = 1;        ///< std::mt19937_64 seed for the random classes
  std::vector<BedClassSpec> classes;

  double slab_thickness() const { return layer_thickness * loose_factor; }
  /// [m] z of the bottom of layer `layer` (0 = lowest); slab_bottom(layers) is the top of the bed.
  double slab_bottom(std::int64_t layer) const { return base + static_cast<double>(layer) * slab_thickness(); }
};

/// Random sequential addition of every class into the box [min, max] (each sphere entirely inside).
struct FillSpec {
  Vec3 min = Vec3::Zero();  ///< [m]
  Vec3 max = Vec3::Zero();  ///< [m]
  std::uint64_t seed = 1;   ///< std::mt19937_64 seed
  std::vector<GrainClassSpec> classes;
};

/// A spec the generators cannot build. key() is the scene key to blame, relative to the bed or fill table (e.g.
/// "loose_factor") or, when class_index() is set, to that entry of its classes (e.g. "count").
class BedGenerationError : public std::runtime_error {
 public:
  BedGenerationError(std::optional<std::size_t> class_index, std::string key, const std::string& message)
      : std::runtime_error(message), class_index_(class_index), key_(std::move(key)) {}
  std::optional<std::size_t> class_index() const { return class_index_; }
  const std::string& key() const { return key_; }

 private:
  std::optional<std::size_t> class_index_;
  std::string key_;
};

/// Random sequential addition gives up on a class after this many attempts per sphere of the class on average
/// (the budget is shared, so the cheap early spheres leave room for the hard last ones) ...
inline constexpr std::int64_t kBedAttemptsPerSphere = 1000;
/// ... or after this many misses in a row (the free space is then practically gone; do not spend the rest).
inline constexpr std::int64_t kBedMaxConsecutiveMisses = 100000;
/// Upper limit on the spheres of one generator (as for [[solids.blocks]]).
inline constexpr std::int64_t kBedMaxSpheres = 50000000;

/// Spheres of a class in layer `layer` (0-based) when `total` are spread over `layers`: the first total % layers
/// layers get one more.
std::int64_t count_in_layer(std::int64_t total, std::int64_t layers, std::int64_t layer);

/// Solid volume of all classes over the volume of the bed at its nominal thickness.
double nominal_solid_fraction(const LayeredBedSpec& spec);

/// The spheres of a layered bed, layer by layer from the bottom; in each layer the regular classes first, then the
/// random ones, each group largest diameter first (ties in the order listed). Regular spheres rest on the bottom
/// of their slab. Velocities are zero. Throws BedGenerationError.
std::vector<SphereSpec> generate_layered_bed(const LayeredBedSpec& spec);

/// The spheres of a fill, largest diameter first (ties in the order listed). Velocities are zero. Throws
/// BedGenerationError.
std::vector<SphereSpec> generate_fill(const FillSpec& spec);

}  // namespace riffle
