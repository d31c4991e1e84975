#pragma once
// The grains a scene starts with, as the scene gives them: explicit spheres, lattice blocks, layered beds and fills.
// The model keeps these descriptions, not the spheres they make: a bed of millions of grains is a few numbers until a
// run starts, when engine/setup lays it out once (bed_generation.hpp, initial_state.hpp). Whatever must be known before
// that (the grain count, the sizes that bound the DEM sub-step, the neighbour skin and cells, the memory budget) is
// taken from these descriptions alone (scene_grain_sizes), so `riffle check` and a run agree without placing a grain.
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "components/vec.hpp"

namespace riffle {

struct Solids;

/// One sphere as the scene gives it, or as a generator makes it.
struct SphereSpec {
  Vec3 position = Vec3::Zero();          ///< [m]
  Vec3 velocity = Vec3::Zero();          ///< [m/s]
  Vec3 angular_velocity = Vec3::Zero();  ///< [rad/s]
  double radius = 0.0;                   ///< [m]
  std::int32_t material = 0;
  std::int32_t size_class = 0;
  bool fixed = false;  ///< held with the tank for the whole run (GrainProperties::fixed)
};

/// Where the keys of one scene table were given, so that a problem found only when the run lays the table out (a bed
/// whose random grains jam) is reported as the scene reader reports its own: "file:line:column: full.key: message".
struct SceneTableSource {
  /// What a problem at a key begins with ("beds.toml:12:9: solids.layered_beds[0].loose_factor: "), by the key
  /// relative to the table ("loose_factor", "classes[1].count"), for every key the table's reader asked for.
  std::map<std::string, std::string> key_prefix;
  std::string table_prefix;  ///< the table's own ("beds.toml:3:1: solids.layered_beds[0]: "), for any other key

  std::string problem(const std::string& key, const std::string& message) const {
    const auto found = key_prefix.find(key);
    return (found != key_prefix.end() ? found->second : table_prefix) + message;
  }
};

/// [[solids.blocks]]: spheres alike on a cubic or a hexagonal close-packed lattice from `low`, `counts` sites along
/// x, y, z; the sites whose sphere lies wholly inside the tank at rest are kept (engine/setup/bed_generation.hpp
/// generate_block).
struct SphereBlockSpec {
  /// kCubic: sites `spacing` apart along x, y and z. kHexagonal: hexagonal close packing (ABAB): in each layer rows
  /// `spacing` apart along x, every other row shifted by spacing / 2, rows spacing sqrt(3)/2 apart along y; every
  /// other layer shifted by (spacing / 2, spacing sqrt(3)/6) over the hollows of the one below, layers spacing
  /// sqrt(2/3) apart along z: every sphere touches its 12 neighbours when spacing is the diameter.
  enum class Lattice { kCubic, kHexagonal };
  Lattice lattice = Lattice::kCubic;
  Vec3 low = Vec3::Zero();                 ///< [m] the first site
  double spacing = 0.0;                    ///< [m] between neighbouring sites, at least the diameter
  /// [m] the distance between sites along x, y and z (rows and layers of the hexagonal lattice)
  Vec3 pitch() const {
    if (lattice == Lattice::kCubic) return Vec3::Constant(spacing);
    return Vec3(spacing, spacing * 0.86602540378443865, spacing * 0.81649658092772604);  // sqrt(3)/2, sqrt(2/3)
  }
  std::array<std::int64_t, 3> counts{};    ///< sites along x, y, z (their product at most 5e7)
  SphereSpec sphere;                       ///< radius, velocity, material and size class of every sphere
  std::int64_t count = 0;                  ///< spheres inside the tank: exactly what the block generates
};

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

/// [[solids.layered_beds]]: a bed of `layers` equal layers stacked from z = base over the rectangle
/// [x_min, x_max] x [y_min, y_max]. Each layer is generated in a slab of height layer_thickness * loose_factor (the
/// nominal layer stretched so that random sequential addition, which jams near a solid fraction of 0.38, can place
/// the random classes); the scene then settles the bed to about its nominal thickness. The seed bed (3 layers of
/// 15 mm, 135 large, 537 medium, 7490 small over 0.24 m x 0.16 m) has a solid fraction of 0.585 at its nominal 4.5 cm:
/// 0.585 / 0.38 suggests 1.54. Measured with seeds 1-5: 1.45 jams for four of them, 1.48 passes all in about 0.6 s
/// (near the jam every sphere costs many attempts), 1.6 in 80 ms, 1.7 in 40 ms; 1.7 is the value to use
/// (docs/SCENES.md). A bed that generates at all has exactly the classes' counts of spheres.
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
  SceneTableSource source;       ///< where the scene gave it, for a problem found at set-up

  double slab_thickness() const { return layer_thickness * loose_factor; }
  /// [m] z of the bottom of layer `layer` (0 = lowest); slab_bottom(layers) is the top of the bed.
  double slab_bottom(std::int64_t layer) const { return base + static_cast<double>(layer) * slab_thickness(); }
};

/// [[solids.fills]]: random sequential addition of every class into the box [min, max] (each sphere entirely inside;
/// the scene reader clips the box to the tank). A fill that generates at all has exactly the classes' counts.
struct FillSpec {
  Vec3 min = Vec3::Zero();  ///< [m]
  Vec3 max = Vec3::Zero();  ///< [m]
  std::uint64_t seed = 1;   ///< std::mt19937_64 seed
  std::vector<GrainClassSpec> classes;
  SceneTableSource source;  ///< where the scene gave it, for a problem found at set-up
};

/// The grains a run starts with, summed from the scene's descriptions without placing one: the grains of
/// initial_state, explicit spheres, blocks, beds and fills (classes with a zero count make no grain and are left out).
struct GrainSizes {
  std::int64_t count = 0;
  double smallest_radius = 0.0;   ///< [m] 0 without grains
  double largest_radius = 0.0;    ///< [m] 0 without grains
  double radius_cubed_sum = 0.0;  ///< [m^3] sum of r^3 over every grain
  /// [m] the smallest radius of each material in use (material index -> radius): what the DEM sub-step is set by
  std::map<std::int32_t, double> smallest_radius_by_material;
};

}  // namespace riffle
