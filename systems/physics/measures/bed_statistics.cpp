#include "systems/physics/measures/bed_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "systems/physics/math/not_a_number.hpp"

namespace riffle {

namespace {
constexpr std::size_t kMaxLayers = kMaxBedLayers;

/// Index of the layer holding `height` above the floor, or count if outside [0, count h).
std::size_t layer_of(double height, double thickness, std::size_t count) {
  if (!(height >= 0.0)) return count;  // also NaN
  const double index = std::floor(height / thickness);
  return index < static_cast<double>(count) ? static_cast<std::size_t>(index) : count;
}
}  // namespace

std::vector<ClassCentroid> class_centroids(const Solids& solids, const std::vector<std::int32_t>& classes,
                                           double floor_z) {
  std::vector<ClassCentroid> result(classes.size());
  std::vector<double> weighted(classes.size(), 0.0), volume(classes.size(), 0.0);
  for (std::size_t k = 0; k < classes.size(); ++k) result[k].size_class = classes[k];
  // Serial, in slot order: the same state gives the same bits.
  for (std::size_t i = 0; i < solids.size(); ++i) {
    const auto found = std::find(classes.begin(), classes.end(), solids.size_class[i]);
    if (found == classes.end()) continue;
    const auto k = static_cast<std::size_t>(found - classes.begin());
    const double r = solids.radius[i];
    const double weight = r * r * r;  // proportional to the volume
    ++result[k].grains;
    weighted[k] += weight * (solids.position[i].z() - floor_z);
    volume[k] += weight;
  }
  for (std::size_t k = 0; k < classes.size(); ++k)
    result[k].height = result[k].grains ? weighted[k] / volume[k] : kNaN;
  return result;
}

double BedLayer::coordination_number() const {
  return grains ? 2.0 * static_cast<double>(contacts) / static_cast<double>(grains) : kNaN;
}

double BedLayer::mean_dimensionless_overlap() const {
  return contacts ? overlap_ratio_sum / static_cast<double>(contacts) : kNaN;
}

BedProfile bed_profile(const Solids& solids, const Contacts* contacts, double floor_z, double thickness,
                       std::size_t layer_count) {
  BedProfile profile;
  profile.layers.resize(layer_count);
  for (std::size_t k = 0; k < layer_count; ++k) {
    profile.layers[k].z_low = static_cast<double>(k) * thickness;
    profile.layers[k].z_high = static_cast<double>(k + 1) * thickness;
  }
  for (std::size_t i = 0; i < solids.size(); ++i) {
    const std::size_t k = layer_of(solids.position[i].z() - floor_z, thickness, layer_count);
    if (k < layer_count) ++profile.layers[k].grains;
  }
  if (!contacts) {
    profile.contacts_known = true;
    return profile;
  }
  const Contacts& list = *contacts;
  profile.contacts_known = list.valid && list.pair_offsets.size() == solids.size() + 1 &&
                           list.pair_overlap.size() == list.pair_second.size();
  if (!profile.contacts_known) return profile;
  for (std::size_t i = 0; i < solids.size(); ++i) {
    const double r_i = solids.radius[i];
    for (std::uint32_t p = list.pair_offsets[i]; p < list.pair_offsets[i + 1]; ++p) {
      const double overlap = list.pair_overlap[p];
      if (!(overlap > 0.0)) continue;
      // In a periodic box the second may be a ghost: its owner's image across the seam (components/halo.hpp).
      const std::uint32_t second = list.pair_second[p];
      const bool ghost = second >= solids.size();
      if (ghost && !(list.halo.valid && second - solids.size() < list.halo.size())) continue;
      const std::uint32_t j = ghost ? list.halo.owner_of(second) : second;
      const Vec3 position_j =
          ghost ? Vec3(solids.position[j] + list.halo.shift[second - solids.size()]) : solids.position[j];
      const Vec3 centre_line = position_j - solids.position[i];
      const double distance = centre_line.norm();
      // The contact point: the middle of the overlap, r_i - delta/2 from the first centre along the line of centres.
      const double z = solids.position[i].z() +
                       (distance > 0.0 ? (r_i - 0.5 * overlap) * centre_line.z() / distance : 0.0);
      const std::size_t k = layer_of(z - floor_z, thickness, layer_count);
      if (k >= layer_count) continue;
      ++profile.layers[k].contacts;
      profile.layers[k].overlap_ratio_sum += overlap / (r_i + solids.radius[j]);  // d_ij = (d_i + d_j)/2 = r_i + r_j
    }
  }
  return profile;
}

std::vector<std::int32_t> size_classes(const Solids& solids) {
  const std::set<std::int32_t> classes(solids.size_class.begin(), solids.size_class.end());
  return {classes.begin(), classes.end()};
}

double bed_layer_thickness(const Model& model, const Solids& solids) {
  if (model.output.bed_layer_thickness > 0.0) return model.output.bed_layer_thickness;
  if (solids.size() == 0) return 0.0;
  return 2.0 * *std::min_element(solids.radius.begin(), solids.radius.end());
}

std::size_t bed_layer_count(const Model& model, double thickness) {
  if (!(thickness > 0.0)) return 1;
  const double count = std::ceil(model.tank.size.z() / thickness * (1.0 - 1e-12));
  return static_cast<std::size_t>(std::clamp(count, 1.0, static_cast<double>(kMaxLayers)));
}

double tank_floor_z(const Model& model, const World& world) {
  return model.tank.origin.z() + (world.tank_motion ? world.tank_motion->displacement.z() : 0.0);
}

double oscillation_periods(const Model& model, double time) {
  if (model.tank.motion.kind != TankMotionModel::Kind::kSinusoidal) return kNaN;
  return time * model.tank.motion.frequency;
}

}  // namespace riffle
