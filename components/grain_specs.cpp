#include "components/grain_specs.hpp"

#include <algorithm>
#include <limits>

#include "components/model.hpp"
#include "components/solids.hpp"

namespace riffle {

GrainSizes scene_grain_sizes(const SolidsModel& solids) {
  GrainSizes sizes;
  double smallest = std::numeric_limits<double>::infinity();
  // `count` grains of `radius` and `material` (radius as the laid-out grain holds it: a class's 0.5 * diameter).
  auto note = [&](std::int32_t material, double radius, std::int64_t count) {
    if (count <= 0) return;
    sizes.count += count;
    smallest = std::min(smallest, radius);
    sizes.largest_radius = std::max(sizes.largest_radius, radius);
    sizes.radius_cubed_sum += static_cast<double>(count) * radius * radius * radius;
    auto [it, inserted] = sizes.smallest_radius_by_material.emplace(material, radius);
    if (!inserted) it->second = std::min(it->second, radius);
  };
  if (const Solids* grains = solids.initial_grains.get())
    for (std::size_t i = 0; i < grains->size(); ++i) note(grains->material[i], grains->radius[i], 1);
  for (const SphereSpec& sphere : solids.spheres) note(sphere.material, sphere.radius, 1);
  for (const SphereBlockSpec& block : solids.blocks) note(block.sphere.material, block.sphere.radius, block.count);
  for (const LayeredBedSpec& bed : solids.layered_beds)
    for (const BedClassSpec& grains : bed.classes) note(grains.material, 0.5 * grains.diameter, grains.count);
  for (const FillSpec& fill : solids.fills)
    for (const GrainClassSpec& grains : fill.classes) note(grains.material, 0.5 * grains.diameter, grains.count);
  if (sizes.count > 0) sizes.smallest_radius = smallest;
  return sizes;
}

std::int64_t scene_sphere_count(const SolidsModel& solids) {
  std::int64_t count = static_cast<std::int64_t>(solids.spheres.size());
  for (const SphereBlockSpec& block : solids.blocks) count += block.count;
  for (const LayeredBedSpec& bed : solids.layered_beds)
    for (const BedClassSpec& grains : bed.classes) count += grains.count;
  for (const FillSpec& fill : solids.fills)
    for (const GrainClassSpec& grains : fill.classes) count += grains.count;
  return count;
}

}  // namespace riffle
