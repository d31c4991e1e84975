#include "engine/setup/bed_generation.hpp"

#include "engine/toml/scene_reader.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <set>
#include <sstream>

namespace riffle {

namespace {

/// Random sequential addition of equal spheres jams at a solid fraction of 0.384 (mixtures a little higher); used
/// only to word messages and to suggest a loose_factor.
constexpr double kJammingFraction = 0.38;
/// A layer or box asked to hold more than this solid fraction is beyond any random sequential addition (it is
/// random close packing): refuse at once instead of spending the whole attempt budget to find out.
constexpr double kHopelessFraction = 0.64;

double sphere_volume(double diameter) { return std::numbers::pi / 6.0 * diameter * diameter * diameter; }

std::string format_mm(double metres) { return format_number(std::round(metres * 1e4) / 10.0) + " mm"; }

/// A uniform number in [0, 1) from the top 53 bits of one draw. std::uniform_real_distribution's algorithm is left
/// to the standard library; this keeps a seed's bed bit-identical with any library.
double unit_uniform(std::mt19937_64& random) { return static_cast<double>(random() >> 11) * 0x1.0p-53; }

/// Class indices with a positive count, largest diameter first, ties in the order listed.
template <class Class>
std::vector<std::size_t> largest_first(const std::vector<Class>& classes, bool (*wanted)(const Class&)) {
  std::vector<std::size_t> order;
  for (std::size_t k = 0; k < classes.size(); ++k)
    if (classes[k].count > 0 && wanted(classes[k])) order.push_back(k);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return classes[a].diameter > classes[b].diameter; });
  return order;
}

/// The spheres placed so far, binned in a uniform grid of cubic cells at least as wide as the largest diameter,
/// so that an overlap test looks only at the few cells within reach and placing N spheres costs O(N).
class OverlapGrid {
 public:
  OverlapGrid(const Vec3& low, const Vec3& high, double largest_diameter, std::int64_t expected_spheres)
      : low_(low) {
    const Vec3 extent = (high - low).cwiseMax(0.0);
    // Cells no smaller than needed for about one sphere each, so tiny grains in a big box cannot ask for more
    // cells than spheres; then grow until the count is bounded whatever the box's shape.
    const double volume = extent.prod();
    const double spheres = static_cast<double>(std::max<std::int64_t>(expected_spheres, 1));
    cell_ = std::max(largest_diameter, std::cbrt(volume / spheres));
    const double cell_limit = 8.0 * static_cast<double>(expected_spheres) + 64.0;
    for (;;) {
      for (int axis = 0; axis < 3; ++axis)
        // Clamped before the cast: a long thin region can ask for more cells along one axis than int64 holds.
        cells_[axis] = static_cast<std::int64_t>(std::clamp(std::ceil(extent[axis] / cell_), 1.0, 1e15));
      if (static_cast<double>(cells_[0]) * static_cast<double>(cells_[1]) * static_cast<double>(cells_[2]) <=
          cell_limit)
        break;
      cell_ *= 1.25;
    }
    head_.assign(static_cast<std::size_t>(cells_[0] * cells_[1] * cells_[2]), -1);
  }

  /// Whether a sphere at `centre` of `radius` would overlap (not merely touch) a sphere already placed.
  bool overlaps(const Vec3& centre, double radius) const {
    const double reach = radius + largest_radius_;
    std::int64_t from[3], to[3];
    for (int axis = 0; axis < 3; ++axis) {
      from[axis] = cell_of(centre[axis] - reach, axis);
      to[axis] = cell_of(centre[axis] + reach, axis);
    }
    for (std::int64_t k = from[2]; k <= to[2]; ++k)
      for (std::int64_t j = from[1]; j <= to[1]; ++j)
        for (std::int64_t i = from[0]; i <= to[0]; ++i)
          for (std::int64_t at = head_[flat(i, j, k)]; at >= 0; at = next_[static_cast<std::size_t>(at)]) {
            const std::size_t other = static_cast<std::size_t>(at);
            const double contact = radius + radii_[other];
            if ((centres_[other] - centre).squaredNorm() < contact * contact) return true;
          }
    return false;
  }

  void insert(const Vec3& centre, double radius) {
    const std::size_t cell = flat(cell_of(centre.x(), 0), cell_of(centre.y(), 1), cell_of(centre.z(), 2));
    centres_.push_back(centre);
    radii_.push_back(radius);
    next_.push_back(head_[cell]);
    head_[cell] = static_cast<std::int64_t>(centres_.size() - 1);
    largest_radius_ = std::max(largest_radius_, radius);
  }

 private:
  std::int64_t cell_of(double coordinate, int axis) const {
    const double cell = std::floor((coordinate - low_[axis]) / cell_);
    return static_cast<std::int64_t>(std::clamp(cell, 0.0, static_cast<double>(cells_[axis] - 1)));
  }
  std::size_t flat(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return static_cast<std::size_t>((k * cells_[1] + j) * cells_[0] + i);
  }

  Vec3 low_;
  double cell_ = 1.0;
  std::int64_t cells_[3] = {1, 1, 1};
  double largest_radius_ = 0.0;
  std::vector<std::int64_t> head_;  ///< per cell: the last sphere inserted there, -1 if none
  std::vector<std::int64_t> next_;  ///< per sphere: the previous sphere of its cell, -1 if none
  std::vector<Vec3> centres_;
  std::vector<double> radii_;
};

SphereSpec make_sphere(const Vec3& centre, const GrainClassSpec& grains) {
  SphereSpec sphere;  // velocities stay zero: the bed starts at rest
  sphere.position = centre;
  sphere.radius = 0.5 * grains.diameter;
  sphere.material = grains.material;
  sphere.size_class = grains.size_class;
  return sphere;
}

struct RandomPlacement {
  std::int64_t placed = 0;
  std::int64_t attempts = 0;
};

/// Random sequential addition: up to `count` spheres of `grains`, each at a uniformly random centre that keeps it
/// inside [low, high] and off every sphere in `grid`; stops at the attempt budget or a long run of misses.
RandomPlacement place_randomly(const GrainClassSpec& grains, std::int64_t count, const Vec3& low, const Vec3& high,
                               std::mt19937_64& random, OverlapGrid& grid, std::vector<SphereSpec>& spheres) {
  const double radius = 0.5 * grains.diameter;
  // Computed as inside_tank does (low + r, high - r), so a sphere in a box equal to the tank passes that test
  // exactly.
  const Vec3 centre_low = low.array() + radius;
  const Vec3 centre_high = high.array() - radius;
  const Vec3 centre_span = centre_high - centre_low;
  const std::int64_t budget = kBedAttemptsPerSphere * count;
  RandomPlacement result;
  std::int64_t misses = 0;
  while (result.placed < count && result.attempts < budget && misses < kBedMaxConsecutiveMisses) {
    ++result.attempts;
    Vec3 centre;
    for (int axis = 0; axis < 3; ++axis)  // min(): rounding must not carry a centre past centre_high
      centre[axis] = std::min(centre_low[axis] + unit_uniform(random) * centre_span[axis], centre_high[axis]);
    if (grid.overlaps(centre, radius)) {
      ++misses;
      continue;
    }
    misses = 0;
    grid.insert(centre, radius);
    spheres.push_back(make_sphere(centre, grains));
    ++result.placed;
  }
  return result;
}

std::string jam_summary(const RandomPlacement& result, std::int64_t wanted, const std::string& where) {
  return "random sequential addition placed only " + std::to_string(result.placed) + " of the " +
         std::to_string(wanted) +
         " spheres of this class" + where + " (gave up after " + std::to_string(result.attempts) +
         " attempts); it jams near a solid fraction of " + format_number(kJammingFraction);
}

/// Rounds a suggested loose_factor up to a tenth.
double round_up_to_tenth(double value) { return std::ceil(value * 10.0 - 1e-9) / 10.0; }

/// A loose_factor for a layer that is refused before trying: enough to bring the bed to the jamming fraction.
double suggested_loose_factor(const LayeredBedSpec& spec) {
  return round_up_to_tenth(std::max(nominal_solid_fraction(spec) / kJammingFraction, spec.loose_factor * 1.1));
}

/// A loose_factor for a layer that jammed with `random_placed` of `random_wanted` random solid volume [m^3] placed
/// beside `regular` [m^3] of regular spheres: the fraction of the free space the random classes reached is taken as
/// what they can reach, the slab grown until the wanted volume fits at that fraction, plus 10%. The fraction grows a
/// little with the slab (fewer spheres lose room at its faces), so the estimate errs on the safe side.
double suggested_loose_factor(const LayeredBedSpec& spec, double regular, double random_placed,
                              double random_wanted) {
  const double layer_area = (spec.x_max - spec.x_min) * (spec.y_max - spec.y_min);
  const double slab_volume = layer_area * spec.slab_thickness();
  const double reached = random_placed / std::max(slab_volume - regular, 1e-300);
  if (!(reached > 0.0)) return round_up_to_tenth(2.0 * spec.loose_factor);
  const double needed_slab = regular + random_wanted / reached;
  const double needed = needed_slab / (layer_area * spec.layer_thickness);
  return round_up_to_tenth(1.1 * std::max(needed, spec.loose_factor));
}

void check_class(const GrainClassSpec& grains, std::size_t index) {
  if (!(grains.diameter > 0.0) || !std::isfinite(grains.diameter))
    throw BedGenerationError(index, "diameter", "expected a diameter > 0, got " + format_number(grains.diameter));
  if (grains.count < 0 || grains.count > kBedMaxSpheres)
    throw BedGenerationError(index, "count", "expected a count in [0, " + std::to_string(kBedMaxSpheres) +
                                                 "], got " + std::to_string(grains.count));
}

template <class Class>
void check_total(const std::vector<Class>& classes) {
  std::int64_t total = 0;
  for (const Class& grains : classes) total += grains.count;  // each <= kBedMaxSpheres: no overflow
  if (total > kBedMaxSpheres)
    throw BedGenerationError(std::nullopt, "classes", "the classes ask for " + std::to_string(total) +
                                                          " spheres, more than " + std::to_string(kBedMaxSpheres));
}

/// The rectangular lattice that the regular classes of one layer share: `columns` x `rows` sites at the cell
/// centres of the region, as many as needed at least, chosen for the largest spacing in its closer direction (which
/// makes its aspect ratio nearly the region's).
struct SiteLattice {
  std::int64_t columns = 1;
  std::int64_t rows = 1;
  double spacing_x = 0.0;  ///< [m]
  double spacing_y = 0.0;  ///< [m]
};

SiteLattice choose_lattice(std::int64_t sites, double width, double length) {
  SiteLattice best;
  double best_spacing = -1.0;
  for (std::int64_t columns = 1; columns <= sites; ++columns) {
    const std::int64_t rows = (sites + columns - 1) / columns;
    const double spacing = std::min(width / static_cast<double>(columns), length / static_cast<double>(rows));
    // Ties: the lattice with fewer empty sites.
    if (spacing > best_spacing || (spacing == best_spacing && columns * rows < best.columns * best.rows)) {
      best_spacing = spacing;
      best = {columns, rows, width / static_cast<double>(columns), length / static_cast<double>(rows)};
    }
  }
  return best;
}

/// `count` indices spread evenly over [0, available): k * available / count.
std::vector<std::int64_t> spread_indices(std::int64_t count, std::int64_t available) {
  std::vector<std::int64_t> picks;
  for (std::int64_t k = 0; k < count && k < available; ++k) picks.push_back(k * available / count);
  return picks;
}

/// `count` positions spread evenly over [first, last], rounded half up: first + round(k (last - first) / (count-1)).
std::int64_t spread_position(std::int64_t k, std::int64_t count, std::int64_t first, std::int64_t last) {
  if (count <= 1) return first;
  return first + (2 * k * (last - first) + (count - 1)) / (2 * (count - 1));
}

/// Lays the regular classes of one layer on one shared lattice. The largest class takes an evenly spread
/// sub-lattice of the sites where it fits (for the seed: large grains on every other site in both directions, 9 x
/// 5 of a 19 x 12 lattice); each further class, largest first, takes the free sites where it fits and touches
/// nothing, evenly spread over them. So large and medium grains interleave like a checkerboard, and the lattice
/// spacing only has to clear the mean of two neighbouring diameters (12.5 mm for the seed, which gets 12.6 mm).
/// Sites the spread picks that would overlap are skipped and made up in row-major order.
void place_regular_layer(const LayeredBedSpec& spec, std::int64_t layer, OverlapGrid& grid,
                         std::vector<SphereSpec>& spheres) {
  const std::vector<std::size_t> order = largest_first<BedClassSpec>(
      spec.classes, [](const BedClassSpec& c) { return c.arrangement == BedArrangement::kRegular; });
  std::int64_t sites_needed = 0;
  for (std::size_t index : order) sites_needed += count_in_layer(spec.classes[index].count, spec.layers, layer);
  if (sites_needed == 0) return;
  const double width = spec.x_max - spec.x_min;
  const double length = spec.y_max - spec.y_min;
  const SiteLattice lattice = choose_lattice(sites_needed, width, length);
  std::vector<char> taken(static_cast<std::size_t>(lattice.columns * lattice.rows), 0);
  auto site_x = [&](std::int64_t i) { return spec.x_min + (static_cast<double>(i) + 0.5) * lattice.spacing_x; };
  auto site_y = [&](std::int64_t j) { return spec.y_min + (static_cast<double>(j) + 0.5) * lattice.spacing_y; };
  const double bottom = spec.slab_bottom(layer);

  bool first_class = true;
  for (std::size_t index : order) {
    const BedClassSpec& grains = spec.classes[index];
    const std::int64_t wanted = count_in_layer(grains.count, spec.layers, layer);
    if (wanted == 0) continue;
    const double radius = 0.5 * grains.diameter;
    const double z = bottom + radius;  // resting on the bottom of the slab
    // The sites where the sphere stays inside the region form a sub-rectangle of columns [i_first, i_last] and
    // rows [j_first, j_last].
    std::int64_t i_first = lattice.columns, i_last = -1, j_first = lattice.rows, j_last = -1;
    for (std::int64_t i = 0; i < lattice.columns; ++i)
      if (site_x(i) >= spec.x_min + radius && site_x(i) <= spec.x_max - radius) {
        i_first = std::min(i_first, i);
        i_last = i;
      }
    for (std::int64_t j = 0; j < lattice.rows; ++j)
      if (site_y(j) >= spec.y_min + radius && site_y(j) <= spec.y_max - radius) {
        j_first = std::min(j_first, j);
        j_last = j;
      }
    std::vector<std::int64_t> candidates;  // free sites where the sphere fits, row-major
    for (std::int64_t j = std::max<std::int64_t>(j_first, 0); j <= j_last; ++j)
      for (std::int64_t i = std::max<std::int64_t>(i_first, 0); i <= i_last; ++i)
        if (!taken[static_cast<std::size_t>(j * lattice.columns + i)]) candidates.push_back(j * lattice.columns + i);

    std::vector<std::int64_t> preferred;
    if (first_class && i_last >= i_first && j_last >= j_first) {
      // a x b sub-lattice over the usable rectangle with the widest gap between picked sites.
      const std::int64_t usable_columns = i_last - i_first + 1, usable_rows = j_last - j_first + 1;
      std::int64_t best_a = 0, best_b = 0;
      double best_gap = -1.0;
      for (std::int64_t a = 1; a <= std::min(wanted, usable_columns); ++a) {
        const std::int64_t b = (wanted + a - 1) / a;
        if (b > usable_rows) continue;
        const double inf = std::numeric_limits<double>::infinity();
        // [m] mean distance between neighbouring picks along x and along y
        const double gap_x = a > 1 ? static_cast<double>(usable_columns - 1) / static_cast<double>(a - 1) *
                                         lattice.spacing_x
                                   : inf;
        const double gap_y =
            b > 1 ? static_cast<double>(usable_rows - 1) / static_cast<double>(b - 1) * lattice.spacing_y : inf;
        const double gap = std::min(gap_x, gap_y);
        if (gap > best_gap || (gap == best_gap && a * b < best_a * best_b)) {
          best_gap = gap;
          best_a = a;
          best_b = b;
        }
      }
      std::vector<std::int64_t> sub_lattice;
      for (std::int64_t q = 0; q < best_b; ++q)
        for (std::int64_t p = 0; p < best_a; ++p)
          sub_lattice.push_back(spread_position(q, best_b, j_first, j_last) * lattice.columns +
                                spread_position(p, best_a, i_first, i_last));
      for (std::int64_t pick : spread_indices(wanted, static_cast<std::int64_t>(sub_lattice.size())))
        preferred.push_back(sub_lattice[static_cast<std::size_t>(pick)]);
    } else {
      for (std::int64_t pick : spread_indices(wanted, static_cast<std::int64_t>(candidates.size())))
        preferred.push_back(candidates[static_cast<std::size_t>(pick)]);
    }
    first_class = false;

    std::int64_t placed = 0;
    auto try_site = [&](std::int64_t site) {
      if (placed == wanted || taken[static_cast<std::size_t>(site)]) return;
      const Vec3 centre(site_x(site % lattice.columns), site_y(site / lattice.columns), z);
      if (grid.overlaps(centre, radius)) return;
      taken[static_cast<std::size_t>(site)] = 1;
      grid.insert(centre, radius);
      spheres.push_back(make_sphere(centre, grains));
      ++placed;
    };
    for (std::int64_t site : preferred) try_site(site);
    for (std::int64_t site : candidates) try_site(site);
    if (placed < wanted)
      throw BedGenerationError(
          index, "count",
          "cannot lay out the regular spheres of layer " + std::to_string(layer + 1) + " without overlap: placed " +
              std::to_string(placed) + " of the " + std::to_string(wanted) + " of this class on the lattice of " +
              std::to_string(lattice.columns) + " x " + std::to_string(lattice.rows) + " sites (" +
              format_mm(lattice.spacing_x) + " x " + format_mm(lattice.spacing_y) +
              " apart) that all regular classes of the layer share; lower the count, enlarge the region or make "
              "the class random");
  }
}

}  // namespace

std::int64_t count_in_layer(std::int64_t total, std::int64_t layers, std::int64_t layer) {
  if (layers <= 0) return 0;
  return total / layers + (layer < total % layers ? 1 : 0);
}

double nominal_solid_fraction(const LayeredBedSpec& spec) {
  double solid = 0.0;
  for (const BedClassSpec& grains : spec.classes)
    solid += static_cast<double>(grains.count) * sphere_volume(grains.diameter);
  const double bed = (spec.x_max - spec.x_min) * (spec.y_max - spec.y_min) * static_cast<double>(spec.layers) *
                     spec.layer_thickness;
  return bed > 0.0 ? solid / bed : std::numeric_limits<double>::infinity();
}

namespace {

/// What generate_layered_bed checks before it places anything; returns the largest diameter of a class with spheres
/// (0 if the bed has none).
double check_bed_spec(const LayeredBedSpec& spec) {
  const auto finite = [](double value) { return std::isfinite(value); };
  if (!finite(spec.x_min) || !finite(spec.x_max) || !(spec.x_max > spec.x_min))
    throw BedGenerationError(std::nullopt, "x_max", "x_max must be greater than x_min");
  if (!finite(spec.y_min) || !finite(spec.y_max) || !(spec.y_max > spec.y_min))
    throw BedGenerationError(std::nullopt, "y_max", "y_max must be greater than y_min");
  if (!finite(spec.base)) throw BedGenerationError(std::nullopt, "base", "base must be finite");
  if (spec.layers < 1 || spec.layers > 1000)
    throw BedGenerationError(std::nullopt, "layers", "expected 1 to 1000 layers, got " + std::to_string(spec.layers));
  if (!(spec.layer_thickness > 0.0) || !finite(spec.layer_thickness))
    throw BedGenerationError(std::nullopt, "layer_thickness", "expected a layer thickness > 0");
  if (!(spec.loose_factor >= 1.0) || !finite(spec.loose_factor) || !finite(spec.slab_bottom(spec.layers)))
    throw BedGenerationError(std::nullopt, "loose_factor", "expected a finite loose_factor >= 1");
  for (std::size_t k = 0; k < spec.classes.size(); ++k) check_class(spec.classes[k], k);
  check_total(spec.classes);

  const double width = spec.x_max - spec.x_min;
  const double length = spec.y_max - spec.y_min;
  const double slab = spec.slab_thickness();
  double largest_diameter = 0.0;
  for (std::size_t k = 0; k < spec.classes.size(); ++k) {
    const BedClassSpec& grains = spec.classes[k];
    if (grains.count == 0) continue;
    largest_diameter = std::max(largest_diameter, grains.diameter);
    if (grains.diameter > slab)
      throw BedGenerationError(k, "diameter",
                               "a " + format_number(grains.diameter) + " m sphere does not fit in a layer " +
                                   format_number(slab) + " m thick (layer_thickness x loose_factor)");
    if (grains.diameter > width || grains.diameter > length)
      throw BedGenerationError(k, "diameter",
                               "a " + format_number(grains.diameter) + " m sphere does not fit in the region (" +
                                   format_number(width) + " m x " + format_number(length) + " m)");
  }
  return largest_diameter;
}

/// [m^3] solid volume of one layer's regular and random classes.
struct LayerVolumes {
  double regular = 0.0;
  double random = 0.0;
};

LayerVolumes layer_volumes(const LayeredBedSpec& spec, std::int64_t layer) {
  LayerVolumes volumes;
  for (const BedClassSpec& grains : spec.classes)
    (grains.arrangement == BedArrangement::kRegular ? volumes.regular : volumes.random) +=
        static_cast<double>(count_in_layer(grains.count, spec.layers, layer)) * sphere_volume(grains.diameter);
  return volumes;
}

/// Refuses a layer no random sequential addition can fill, before the attempt budget is spent on it.
void refuse_hopeless_layer(const LayeredBedSpec& spec, std::int64_t layer, const LayerVolumes& volumes) {
  const double slab_volume = (spec.x_max - spec.x_min) * (spec.y_max - spec.y_min) * spec.slab_thickness();
  if (volumes.random > 0.0 && volumes.regular + volumes.random > kHopelessFraction * slab_volume)
    throw BedGenerationError(
        std::nullopt, "loose_factor",
        "layer " + std::to_string(layer + 1) + " would have a solid fraction of " +
            format_number((volumes.regular + volumes.random) / slab_volume) + " at loose_factor " +
            format_number(spec.loose_factor) + ", beyond random sequential addition (it jams near " +
            format_number(kJammingFraction) + "); raise loose_factor, e.g. to " +
            format_number(suggested_loose_factor(spec)));
}

}  // namespace

void check_layered_bed(const LayeredBedSpec& spec) {
  const double largest_diameter = check_bed_spec(spec);
  if (!(largest_diameter > 0.0)) return;  // no spheres
  // Regular spheres of one layer meet only each other (each sphere lies inside its own slab), so a layer's lattice
  // is laid out alone; layers with the same counts per class lay out alike, so each set of counts is tried once, at
  // the first layer that has it, as the bed would lay it out.
  std::set<std::vector<std::int64_t>> tried;
  for (std::int64_t layer = 0; layer < spec.layers; ++layer) {
    std::vector<std::int64_t> counts;
    std::int64_t regular = 0;
    for (const BedClassSpec& grains : spec.classes) {
      counts.push_back(count_in_layer(grains.count, spec.layers, layer));
      if (grains.arrangement == BedArrangement::kRegular) regular += counts.back();
    }
    if (!tried.insert(counts).second) continue;
    if (regular > 0) {
      OverlapGrid grid(Vec3(spec.x_min, spec.y_min, spec.slab_bottom(layer)),
                       Vec3(spec.x_max, spec.y_max, spec.slab_bottom(layer + 1)), largest_diameter, regular);
      std::vector<SphereSpec> spheres;
      spheres.reserve(static_cast<std::size_t>(regular));
      place_regular_layer(spec, layer, grid, spheres);
    }
    refuse_hopeless_layer(spec, layer, layer_volumes(spec, layer));
  }
}

std::vector<SphereSpec> generate_layered_bed(const LayeredBedSpec& spec) {
  const double largest_diameter = check_bed_spec(spec);
  std::int64_t total = 0;
  for (const BedClassSpec& grains : spec.classes) total += grains.count;
  std::vector<SphereSpec> spheres;
  if (total == 0) return spheres;

  const std::vector<std::size_t> random_order = largest_first<BedClassSpec>(
      spec.classes, [](const BedClassSpec& c) { return c.arrangement == BedArrangement::kRandom; });
  spheres.reserve(static_cast<std::size_t>(total));
  OverlapGrid grid(Vec3(spec.x_min, spec.y_min, spec.base), Vec3(spec.x_max, spec.y_max, spec.slab_bottom(spec.layers)),
                   largest_diameter, total);
  std::mt19937_64 random(spec.seed);
  for (std::int64_t layer = 0; layer < spec.layers; ++layer) {
    place_regular_layer(spec, layer, grid, spheres);
    const LayerVolumes volumes = layer_volumes(spec, layer);
    refuse_hopeless_layer(spec, layer, volumes);

    // The slab's faces are computed like the neighbouring slabs' (slab_bottom), so adjacent layers share them
    // exactly and no sphere crosses into the next layer by rounding.
    const Vec3 low(spec.x_min, spec.y_min, spec.slab_bottom(layer));
    const Vec3 high(spec.x_max, spec.y_max, spec.slab_bottom(layer + 1));
    double random_placed = 0.0;  // [m^3] in this layer
    for (std::size_t index : random_order) {
      const BedClassSpec& grains = spec.classes[index];
      const std::int64_t wanted = count_in_layer(grains.count, spec.layers, layer);
      const RandomPlacement result = place_randomly(grains, wanted, low, high, random, grid, spheres);
      random_placed += static_cast<double>(result.placed) * sphere_volume(grains.diameter);
      if (result.placed < wanted)
        throw BedGenerationError(
            index, "count",
            jam_summary(result, wanted, " in layer " + std::to_string(layer + 1)) +
                "; the bed's solid fraction at its nominal thickness is " +
                format_number(nominal_solid_fraction(spec)) + ", so raise loose_factor (now " +
                format_number(spec.loose_factor) + "), e.g. to " +
                format_number(suggested_loose_factor(spec, volumes.regular, random_placed, volumes.random)));
    }
  }
  return spheres;
}

void check_fill(const FillSpec& spec) {
  for (int axis = 0; axis < 3; ++axis) {
    if (!std::isfinite(spec.min[axis]) || !std::isfinite(spec.max[axis]))
      throw BedGenerationError(std::nullopt, "max", "the box corners must be finite");
    if (!(spec.max[axis] > spec.min[axis]))
      throw BedGenerationError(std::nullopt, "max", "every component of max must be > the one of min");
  }
  for (std::size_t k = 0; k < spec.classes.size(); ++k) check_class(spec.classes[k], k);
  check_total(spec.classes);
  const Vec3 extent = spec.max - spec.min;
  double solid = 0.0;
  for (std::size_t k = 0; k < spec.classes.size(); ++k) {
    const GrainClassSpec& grains = spec.classes[k];
    if (grains.count == 0) continue;
    solid += static_cast<double>(grains.count) * sphere_volume(grains.diameter);
    if (grains.diameter > extent.minCoeff())
      throw BedGenerationError(k, "diameter",
                               "a " + format_number(grains.diameter) + " m sphere does not fit in the box (" +
                                   format_number(extent.x()) + " m x " + format_number(extent.y()) + " m x " +
                                   format_number(extent.z()) + " m)");
  }
  if (solid > kHopelessFraction * extent.prod())
    throw BedGenerationError(std::nullopt, "classes",
                             "the classes would fill the box to a solid fraction of " +
                                 format_number(solid / extent.prod()) +
                                 ", beyond random sequential addition (it jams near " +
                                 format_number(kJammingFraction) + "); enlarge the box or lower the counts");
}

std::vector<SphereSpec> generate_fill(const FillSpec& spec) {
  check_fill(spec);
  const Vec3 extent = spec.max - spec.min;
  double largest_diameter = 0.0, solid = 0.0;
  std::int64_t total = 0;
  for (const GrainClassSpec& grains : spec.classes) {
    total += grains.count;
    if (grains.count == 0) continue;
    largest_diameter = std::max(largest_diameter, grains.diameter);
    solid += static_cast<double>(grains.count) * sphere_volume(grains.diameter);
  }
  std::vector<SphereSpec> spheres;
  if (total == 0) return spheres;
  spheres.reserve(static_cast<std::size_t>(total));
  OverlapGrid grid(spec.min, spec.max, largest_diameter, total);
  std::mt19937_64 random(spec.seed);
  // Largest first: big grains placed after small ones would rarely find a hole, and a mixture packs closer so.
  for (std::size_t index : largest_first<GrainClassSpec>(spec.classes, [](const GrainClassSpec&) { return true; })) {
    const GrainClassSpec& grains = spec.classes[index];
    const RandomPlacement result = place_randomly(grains, grains.count, spec.min, spec.max, random, grid, spheres);
    if (result.placed < grains.count)
      throw BedGenerationError(index, "count",
                               jam_summary(result, grains.count, "") +
                                   "; the box asks for a solid fraction of " +
                                   format_number(solid / extent.prod()) + ": enlarge the box or lower the counts");
  }
  return spheres;
}

namespace {

/// inside_tank along one axis: the coordinate of the centre against that axis's bounds.
bool inside_tank_along(const TankModel& tank, int axis, double coordinate, double radius, bool across_seam) {
  // Along a periodic axis there is no wall: the centre must lie in the period [origin, origin + size), and a sphere
  // may reach across the seam.
  if (across_seam && tank.periodic[static_cast<std::size_t>(axis)])
    return coordinate >= tank.origin[axis] &&
           coordinate <= std::nextafter(tank.origin[axis] + tank.size[axis], -1e308);
  // A sphere that touches a wall fits: the slack (a billionth of the radius) keeps lattice rounding from dropping a
  // block's last row (0.0025 + 7 x 0.005 lands 1 ulp past 0.04 - 0.0025).
  const double slack = 1e-9 * radius;
  return coordinate >= tank.origin[axis] + (radius - slack) &&
         coordinate <= (tank.origin[axis] + tank.size[axis]) - (radius - slack);
}

Vec3 block_site(const SphereBlockSpec& block, std::int64_t i, std::int64_t j, std::int64_t k) {
  const Vec3 index(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k));
  if (block.lattice == SphereBlockSpec::Lattice::kCubic) return block.low + block.spacing * index;
  // Hexagonal close packing: odd rows (counted across layers) shifted half a spacing along x, odd layers a third of
  // a row along y, so each upper sphere sits over the centroid of a triangle of the layer below.
  const Vec3 pitch = block.pitch();
  const double row_shift = ((j + k) % 2 == 0) ? 0.0 : 0.5;
  const double layer_shift = (k % 2 == 0) ? 0.0 : 1.0 / 3.0;
  return block.low + Vec3(pitch.x() * (index.x() + row_shift), pitch.y() * (index.y() + layer_shift),
                          pitch.z() * index.z());
}

/// The hexagonal lattice's sites inside the tank, in generation order (its shifts make the axes depend on each
/// other, so each site is tested whole).
template <class Visit>
void for_each_hexagonal_site_inside(const SphereBlockSpec& block, const TankModel& tank, Visit&& visit) {
  for (std::int64_t k = 0; k < block.counts[2]; ++k)
    for (std::int64_t j = 0; j < block.counts[1]; ++j)
      for (std::int64_t i = 0; i < block.counts[0]; ++i) {
        const Vec3 site = block_site(block, i, j, k);
        if (inside_tank(tank, site, block.sphere.radius, false)) visit(site);
      }
}

/// Per axis, the lattice indices whose coordinate keeps the block's sphere inside the tank: a site is inside exactly
/// when each of its three indices is listed. Whole spheres only, also along a periodic axis: a lattice that does not
/// divide the period would overlap its own first row across the seam.
std::array<std::vector<std::int64_t>, 3> block_sites_inside(const SphereBlockSpec& block, const TankModel& tank) {
  std::array<std::vector<std::int64_t>, 3> sites;
  for (int axis = 0; axis < 3; ++axis)
    for (std::int64_t n = 0; n < block.counts[static_cast<std::size_t>(axis)]; ++n) {
      const Vec3 site = block_site(block, axis == 0 ? n : 0, axis == 1 ? n : 0, axis == 2 ? n : 0);
      if (inside_tank_along(tank, axis, site[axis], block.sphere.radius, false))
        sites[static_cast<std::size_t>(axis)].push_back(n);
    }
  return sites;
}

}  // namespace

bool inside_tank(const TankModel& tank, const Vec3& centre, double radius, bool across_seam) {
  for (int axis = 0; axis < 3; ++axis)
    if (!inside_tank_along(tank, axis, centre[axis], radius, across_seam)) return false;
  return true;
}

std::int64_t block_sphere_count(const SphereBlockSpec& block, const TankModel& tank) {
  if (block.lattice == SphereBlockSpec::Lattice::kHexagonal) {
    std::int64_t count = 0;
    for_each_hexagonal_site_inside(block, tank, [&](const Vec3&) { ++count; });
    return count;
  }
  const std::array<std::vector<std::int64_t>, 3> sites = block_sites_inside(block, tank);
  return static_cast<std::int64_t>(sites[0].size() * sites[1].size() * sites[2].size());
}

std::vector<SphereSpec> generate_block(const SphereBlockSpec& block, const TankModel& tank) {
  std::vector<SphereSpec> spheres;
  if (block.lattice == SphereBlockSpec::Lattice::kHexagonal) {
    SphereSpec sphere = block.sphere;
    for_each_hexagonal_site_inside(block, tank, [&](const Vec3& site) {
      sphere.position = site;
      spheres.push_back(sphere);
    });
    return spheres;
  }
  const std::array<std::vector<std::int64_t>, 3> sites = block_sites_inside(block, tank);
  spheres.reserve(sites[0].size() * sites[1].size() * sites[2].size());
  SphereSpec sphere = block.sphere;
  for (const std::int64_t k : sites[2])
    for (const std::int64_t j : sites[1])
      for (const std::int64_t i : sites[0]) {
        sphere.position = block_site(block, i, j, k);
        spheres.push_back(sphere);
      }
  return spheres;
}

namespace {

/// A generator's spheres, or its BedGenerationError as the SceneError the scene reader would have raised at its key.
template <class Spec, class Generate>
std::vector<SphereSpec> generated(const Spec& spec, Generate generate) {
  try {
    return generate(spec);
  } catch (const BedGenerationError& error) {
    const std::string key =
        error.class_index() ? "classes[" + std::to_string(*error.class_index()) + "]." + error.key() : error.key();
    throw SceneError({spec.source.problem(key, std::string(error.what()) +
                                                   " (found when the run laid the grains out; `riffle check` reads "
                                                   "the table but does not generate it)")});
  }
}

}  // namespace

void for_each_scene_sphere(const Model& model, const std::function<void(const SphereSpec&)>& add) {
  const SolidsModel& solids = model.solids;
  for (const SphereSpec& sphere : solids.spheres) add(sphere);
  for (const SphereBlockSpec& block : solids.blocks)
    for (const SphereSpec& sphere : generate_block(block, model.tank)) add(sphere);
  for (const LayeredBedSpec& bed : solids.layered_beds)
    for (const SphereSpec& sphere : generated(bed, generate_layered_bed)) add(sphere);
  for (const FillSpec& fill : solids.fills)
    for (const SphereSpec& sphere : generated(fill, generate_fill)) add(sphere);
}

std::vector<SphereSpec> scene_spheres(const Model& model) {
  std::vector<SphereSpec> spheres;
  for_each_scene_sphere(model, [&](const SphereSpec& sphere) { spheres.push_back(sphere); });
  return spheres;
}

}  // namespace riffle
