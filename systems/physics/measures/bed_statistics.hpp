#pragma once
// Statistics of the grain bed for comparison with seed 000: the concentration centroid height of each size class
// (Figs. 5-6, against t/T) and, per horizontal sub-layer, the coordination number Z = 2 Nc / Np (Eq. 27) and the
// mean dimensionless overlap delta* = mean over contacts of delta / d_ij, d_ij = (d_i + d_j) / 2 (Eq. 28), with
// sub-layers of thickness d_s1 = 5 mm, the smallest grain diameter (Sec. 5.1, Fig. 12).
//
// Conventions (also in docs/SCENES.md):
//   - heights are measured from the tank floor (the inner bottom face, following the tank if it moves vertically);
//   - sub-layer k holds the heights [k h, (k + 1) h); layers cover the tank height;
//   - a grain belongs to the sub-layer of its centre (Np);
//   - a grain-grain contact (overlap > 0) belongs to the sub-layer of its contact point (Nc), the middle of the
//     overlap on the line of centres, x_i + (r_i - delta / 2) n_ij: the seed counts "contacting points" per
//     sub-layer. Grain-wall contacts are not counted (d_ij is not defined for them);
//   - the centroid of a class is the volume-weighted mean centre height of its grains, which for the equal grains
//     of one class is their plain mean.
// The functions are pure (no I/O); engine/output/bed_profile_writer.hpp puts them into bed_profile.csv and
// class_centroids.csv.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "components/contacts.hpp"
#include "components/solids.hpp"
#include "components/model.hpp"
#include "components/world.hpp"

namespace riffle {

/// Most sub-layers a bed profile may have (bed_layer_thickness is refused below tank height / this).
inline constexpr std::size_t kMaxBedLayers = 1000000;

struct ClassCentroid {
  std::int32_t size_class = 0;
  std::size_t grains = 0;
  double height = 0.0;  ///< [m] volume-weighted mean centre height above the floor; NaN if the class has no grain
};

/// The centroid of each of `classes` (in that order).
std::vector<ClassCentroid> class_centroids(const Solids& solids, const std::vector<std::int32_t>& classes,
                                           double floor_z);

struct BedLayer {
  double z_low = 0.0;             ///< [m] above the floor
  double z_high = 0.0;            ///< [m] above the floor (exclusive)
  std::size_t grains = 0;         ///< Np: grain centres in the layer
  std::size_t contacts = 0;       ///< Nc: grain-grain contact points in the layer
  double overlap_ratio_sum = 0.0; ///< [1] sum over those contacts of delta / d_ij

  /// Z = 2 Nc / Np (seed Eq. 27); NaN if the layer holds no grain.
  double coordination_number() const;
  /// delta* (seed Eq. 28); NaN if the layer holds no contact.
  double mean_dimensionless_overlap() const;
};

struct BedProfile {
  std::vector<BedLayer> layers;
  /// False when the contact list is not built yet (before the first step): contacts and Z are then unknown.
  bool contacts_known = false;
};

/// `layer_count` layers of `thickness` from `floor_z` up. Grains and contacts outside them are left out.
/// `contacts` may be null (a scene without [contact]: no contacts, known). Overlaps are Contacts::pair_overlap, as
/// the contact forces of the last sub-step saw them; contact points use the current positions.
BedProfile bed_profile(const Solids& solids, const Contacts* contacts, double floor_z, double thickness,
                       std::size_t layer_count);

/// The size classes of the grains, ascending, each once.
std::vector<std::int32_t> size_classes(const Solids& solids);
/// [m] The sub-layer thickness: output.bed_layer_thickness, or if that is 0 the smallest grain diameter (0 without
/// grains). From the grains themselves, not the scene's spheres: a run may start from another run's grains.
double bed_layer_thickness(const Model& model, const Solids& solids);
/// Layers of `thickness` covering the tank height (at least one, at most 1e6).
std::size_t bed_layer_count(const Model& model, double thickness);
/// [m] z of the tank floor now.
double tank_floor_z(const Model& model, const World& world);
/// t/T = t f for a sinusoidally moving tank; NaN otherwise.
double oscillation_periods(const Model& model, double time);

}  // namespace riffle
