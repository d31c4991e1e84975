#include "systems/coupling/solid_history_force.hpp"

#include "systems/coupling/solid_drag.hpp"
#include "systems/physics/coupling/drag_law.hpp"

#include <array>

#include "systems/physics/mps/mps_common.hpp"

namespace riffle {

static_assert(BassetModes::kCount == GrainAddedMass::kHistoryModes, "one grain field per mode");

SolidHistoryForce::SolidHistoryForce(const Model& model)
    : modes_(BassetModes::make(model.coupling.history_window, model.dt)),
      density_(model.water_density()),
      viscosity_(model.water_kinematic_viscosity() * model.water_density()),
      fluid_velocity_(model.coupling.fluid_velocity),
      coupling_(model.coupling) {}

void SolidHistoryForce::run(SystemContext& context) {
  const GrainState& grains = context.read<GrainState>();
  const GrainProperties& properties = context.read<GrainProperties>();
  const GrainSampledFluid& sampled = context.read<GrainSampledFluid>();
  const GrainVoidage& voidages = context.read<GrainVoidage>();
  const GrainDrag& drag = context.read<GrainDrag>();
  GrainAddedMass& added = context.write<GrainAddedMass>();
  const double dt = context.dt;
  // The modes' decay and gain over this step are the same for every grain (advance_basset_mode, once per mode).
  std::array<double, BassetModes::kCount> decay{}, gain{};
  for (std::size_t k = 0; k < BassetModes::kCount; ++k) {
    Vec3 unit = Vec3::UnitX(), response = Vec3::Zero();
    advance_basset_mode(unit, modes_.rate[k], dt, Vec3::Zero());
    advance_basset_mode(response, modes_.rate[k], dt, Vec3::UnitX());
    decay[k] = unit.x();
    gain[k] = response.x();
  }
  const double root = basset_prefactor(1.0, density_, viscosity_);  // 3/2 (pi rho mu)^(1/2); times d^2 per grain
  for_each_particle(grains.size(), [&](std::size_t grain) {
    if (sampled.fluid_weight[grain] <= 0.0) {  // dry: no history; it starts afresh when the grain enters the water
      added.history_force[grain] = Vec3::Zero();
      added.history_relative_velocity[grain] = Vec3::Zero();
      for (auto& mode : added.history_mode) mode[grain] = Vec3::Zero();
      return;
    }
    // The grain's own disturbance as the correction carried it at the last sub-step, for a grain it applies to at
    // this step's voidage (solid_drag_law clears the lags of the others, but after this system), so the slip is the
    // drag's, not the water the grain drags along.
    const double voidage = voidages.voidage[grain];
    const Vec3 own = carries_self_induced_disturbance(coupling_, sampled.fluid_weight[grain], voidage)
                         ? carried_self_induced_disturbance(drag, grain)
                         : Vec3::Zero();
    const Vec3 relative = sampled.fluid_velocity[grain] - own - grains.velocity[grain];
    const Vec3 slip = relative / flux_share(fluid_velocity_, voidage);
    const Vec3 change = slip - added.history_relative_velocity[grain];
    added.history_relative_velocity[grain] = slip;
    Vec3 integral = Vec3::Zero();
    for (std::size_t k = 0; k < BassetModes::kCount; ++k) {
      Vec3& mode = added.history_mode[k][grain];
      mode = decay[k] * mode + gain[k] * change;
      integral += modes_.weight[k] * mode;
    }
    const double diameter = 2.0 * properties.radius[grain];
    added.history_force[grain] = (root * diameter * diameter) * integral;
  });
  context.count_items(grains.size());
}

}  // namespace riffle
