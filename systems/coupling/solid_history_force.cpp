#include "systems/coupling/solid_history_force.hpp"

#include "systems/coupling/solid_drag.hpp"
#include "systems/physics/coupling/drag_law.hpp"

#include <array>

#include "systems/physics/mps/mps_common.hpp"

namespace riffle {

static_assert(BassetModes::kCount == GrainAddedMass::kHistoryModes, "one grain field per mode");

SolidHistoryForce::SolidHistoryForce(const Model& model)
    : modes_(BassetModes::make(model.coupling.history_window, model.dt)),
      finite_reynolds_(model.coupling.history_kernel == CouplingModel::HistoryKernel::kMeiAdrian
                           ? MeiAdrianModeWeights(modes_)
                           : MeiAdrianModeWeights()),
      basset_kernel_(model.coupling.history_kernel == CouplingModel::HistoryKernel::kBasset),
      kinematic_viscosity_(model.water_kinematic_viscosity()),
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
  std::array<BassetModeStep, BassetModes::kCount> steps{};
  for (std::size_t k = 0; k < BassetModes::kCount; ++k) steps[k] = basset_mode_step(modes_.rate[k], dt);
  const double root = basset_prefactor(1.0, density_, viscosity_);  // 3/2 (pi rho mu)^(1/2); times d^2 per grain
  for_each_particle(grains.size(), [&](std::size_t grain) {
    // Dry, or inside a bed (a lone sphere's kernel does not hold there): no history; it starts afresh when the grain
    // enters the water or leaves the bed.
    const double voidage = voidages.voidage[grain];
    if (sampled.fluid_weight[grain] <= 0.0 || voidage <= kSelfInducedMinVoidage) {
      added.history_force[grain] = Vec3::Zero();
      added.history_mass[grain] = 0.0;
      added.history_relative_velocity[grain] = Vec3::Zero();
      for (auto& mode : added.history_mode) mode[grain] = Vec3::Zero();
      return;
    }
    // The grain's own disturbance as the correction carried it at the last sub-step, for a grain it applies to at
    // this step's voidage (solid_drag_law clears the lags of the others, but after this system), so the slip is the
    // drag's, not the water the grain drags along.
    const Vec3 own = carries_self_induced_disturbance(coupling_, sampled.fluid_weight[grain], voidage)
                         ? carried_self_induced_disturbance(drag, grain)
                         : Vec3::Zero();
    const Vec3 relative = sampled.fluid_velocity[grain] - own - grains.velocity[grain];
    const double share = flux_share(fluid_velocity_, voidage);
    const Vec3 slip = relative / share;
    const Vec3 change = slip - added.history_relative_velocity[grain];
    added.history_relative_velocity[grain] = slip;
    const double diameter = 2.0 * properties.radius[grain];
    const std::array<double, BassetModes::kCount> weight =
        basset_kernel_ ? modes_.weight
                       : finite_reynolds_.weights(MeiAdrianKernel::time_scale(slip.norm(), diameter,
                                                                              kinematic_viscosity_));
    // In a suspension the other grains resist the water (Brinkman): the unsteady Stokes layer's sqrt(s / nu)
    // becomes sqrt(s / nu + l_B^-2), so the memory is Basset's kernel times exp(-nu t / l_B^2) (the rest of that
    // symbol is steady drag, the hindered drag law's). Every mode's rate grows by nu / l_B^2; zero for a lone grain.
    const double screening_rate =
        suspension_resistance_per_volume(coupling_, voidage, diameter, relative.norm(), share, density_, viscosity_) /
        density_;
    // The states take the last step's change; the force held over this step is the memory of the changes so far at
    // the step's end (each state decayed over one more step), and this step's own change of slip is the kicks'
    // implicit part m_H (a_f - dv/dt), m_H = C d^2 dt sum_k w_k gain_k: the kernel's integral over one step
    // (backward Euler in the force, as the added mass; explicit, the step's own part drove light grains in a
    // viscous liquid unstable).
    Vec3 memory = Vec3::Zero();
    double own_step = 0.0;
    for (std::size_t k = 0; k < BassetModes::kCount; ++k) {
      Vec3& mode = added.history_mode[k][grain];
      const BassetModeStep step =
          screening_rate > 0.0 ? basset_mode_step(modes_.rate[k] + screening_rate, dt) : steps[k];
      mode = step.decay * mode + step.gain * change;
      memory += (weight[k] * step.decay) * mode;
      own_step += weight[k] * step.gain;
    }
    const double prefactor = root * diameter * diameter;
    added.history_force[grain] = prefactor * memory;
    added.history_mass[grain] = prefactor * own_step * dt;
  });
  context.count_items(grains.size());
}

}  // namespace riffle
