#pragma once
// Generated initial beds for the solid phase. Seed 000 (Sec. 2 and 4.1) builds its movable bed from three layers,
// each of regularly arranged large (15 mm) and medium (10 mm) grains with small (5 mm) grains set randomly among
// them; generate_layered_bed builds that bed (and others like it), generate_fill fills a box with a size
// distribution, generate_block sets spheres on a cubic lattice. All are pure functions of their spec: the same spec
// and seed give bit-identical spheres, in a fixed order, so grain ids are reproducible. The beds are loose (no two
// spheres overlap, none touch a slab or box face from outside); a scene settles them under gravity with DEM.
//
// The specs (components/grain_specs.hpp) are what the model keeps; engine/scene/bed_scene.hpp reads the scene tables
// [[solids.layered_beds]] and [[solids.fills]] (docs/SCENES.md) and checks them with check_layered_bed and check_fill,
// which raise every problem a spec can be seen to have without random placement. The spheres are made once, when a
// run lays out its initial world (scene_spheres, initial_state.hpp).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "components/grain_specs.hpp"
#include "components/model.hpp"
#include "components/vec.hpp"
#include "engine/toml/scene_reader.hpp"

namespace riffle {

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

/// Throws the BedGenerationError generate_layered_bed would throw before its first random draw: a bad region,
/// layer count, thickness or loose_factor; a class that does not fit in a layer or the region; a layer beyond any
/// random sequential addition (solid fraction above 0.64); regular classes that do not fit on their layer's lattice
/// (laid out once for each distinct set of per-layer counts: the bed's own lattices). What it cannot see is a layer
/// whose random classes jam: that shows only when the bed is generated.
void check_layered_bed(const LayeredBedSpec& spec);

/// The spheres of a layered bed, layer by layer from the bottom; in each layer the regular classes first, then the
/// random ones, each group largest diameter first (ties in the order listed). Regular spheres rest on the bottom
/// of their slab. Velocities are zero. Exactly the classes' counts, or throws BedGenerationError.
std::vector<SphereSpec> generate_layered_bed(const LayeredBedSpec& spec);

/// Throws the BedGenerationError generate_fill would throw before its first random draw (a bad box, a class that
/// does not fit, a solid fraction above 0.64); a fill whose classes jam shows only when it is generated.
void check_fill(const FillSpec& spec);

/// The spheres of a fill, largest diameter first (ties in the order listed). Velocities are zero. Exactly the
/// classes' counts, or throws BedGenerationError.
std::vector<SphereSpec> generate_fill(const FillSpec& spec);

/// Whether a sphere of `radius` at `centre` lies inside the tank at rest (touching a wall counts as inside). Along a
/// periodic axis the centre must lie in the period [origin, origin + size) and the sphere may reach across the
/// seam, unless `across_seam` is false (a block's lattice that does not divide the period would overlap its own
/// first row across the seam).
bool inside_tank(const TankModel& tank, const Vec3& centre, double radius, bool across_seam = true);

/// The spheres generate_block makes: the lattice sites whose sphere lies inside the tank, counted axis by axis (a
/// site is inside when its coordinate along each axis is), so without visiting the block's sites.
std::int64_t block_sphere_count(const SphereBlockSpec& block, const TankModel& tank);

/// The spheres of a block, sites z-major then y then x, those inside the tank at rest only.
std::vector<SphereSpec> generate_block(const SphereBlockSpec& block, const TankModel& tank);

/// The spheres the scene lists and generates, in the order a run adds them after initial_state's grains:
/// [[solids.spheres]], [[solids.blocks]], [[solids.layered_beds]], [[solids.fills]], each in scene order. Hands them
/// to `add` one table at a time, so only one generator's spheres are held at once. A bed or fill that cannot be
/// generated (its random classes jam) throws SceneError naming the table's key (its SceneTableSource), as the scene
/// reader names its own problems.
void for_each_scene_sphere(const Model& model, const std::function<void(const SphereSpec&)>& add);

/// for_each_scene_sphere's spheres in one list (tests and tools; a run adds them to its grains as they come).
std::vector<SphereSpec> scene_spheres(const Model& model);

}  // namespace riffle
