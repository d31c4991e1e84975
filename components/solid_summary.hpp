#pragma once
// Reductions over the solids that the diagnostics CSV and the time-step report need, refreshed every step.
#include "components/component_id.hpp"

namespace riffle {

struct SolidSummary {
  static constexpr ComponentId kId = component_id<SolidSummary>;
  static constexpr std::string_view kName = "solid_summary";
  static constexpr bool kPersistent = false;

  double translational_energy = 0.0;  ///< [J] sum of m |v|^2 / 2
  double rotational_energy = 0.0;     ///< [J] sum of I |w|^2 / 2
  double potential_energy = 0.0;      ///< [J] sum of -m g . x (relative to the origin)
  double max_speed = 0.0;             ///< [m/s] largest |v|
  /// The grains are spread over MPI ranks (systems/physics/ranks/grain_ranks.hpp): the sums above are the whole bed's,
  /// reduced over the ranks in rank order, the same on every rank.
  bool over_ranks = false;
};

}  // namespace riffle
