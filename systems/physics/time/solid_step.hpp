#pragma once
// The grains' sub-step bound, beside the fluid's step bounds (time_step.hpp): the longest DEM sub-step that resolves
// every design impact of the scene's grains (its smallest grains of each material against each other and against
// the walls) stably and within contact.restitution_tolerance of the requested restitution. Pure functions of the
// model; the scene reader asks once and keeps the answer in model.contact (stable_solid_dt, its reason, the
// restitution error achieved at the sub-step the run uses).
#include <string>
#include <vector>

#include "components/model.hpp"

namespace riffle {

/// The largest stable DEM sub-step: a fraction of the Rayleigh time of the smallest grain of each material, and the
/// contact time (Hertz at max_impact_speed, or the linear law's collision time) divided by steps_per_collision, for
/// the smallest grains of every pair of materials in use and for each of them against the walls (and, with the
/// elastic-plastic rolling law, that contact time over the rolling spring's frequency over the normal one, where the
/// rolling spring is the stiffer: mu_r above about 0.42 on a wall); then shortened
/// until each of those impacts, integrated as the DEM integrates it, rebounds within restitution_tolerance of the
/// requested restitution (a damping term beyond its explicit stability limit creates energy instead of removing it).
struct StableStep {
  double solid_dt = 0.0;  ///< [s] the stable estimate (infinity without grains)
  std::string reason;     ///< what set it, for messages and `riffle check`
};

/// One head-on impact the sub-step must resolve: the smallest grains of two materials, or of one against a wall.
struct DesignImpact {
  const ContactPairParameters* pair;  ///< into model.contact: valid while the model lives
  double effective_radius, effective_mass, contact_time;  ///< [m], [kg], [s]
  std::string name;
};

/// The stable sub-step of `model`'s grains (scene_grain_sizes: its spheres, the size classes of its blocks, beds and
/// fills, and the grains of [solids] initial_state; nothing generated); `impacts` receives the design impacts it was
/// judged on.
StableStep stable_solid_step(const Model& model, std::vector<DesignImpact>& impacts);

/// The worst |achieved - requested| restitution over `impacts` at sub-step `dt`, and which impact gives it.
struct RestitutionError {
  double error = 0.0;
  std::string impact;
};
RestitutionError worst_design_impact_error(const ContactModel& contact, const std::vector<DesignImpact>& impacts,
                                           double dt);

}  // namespace riffle
