#include "systems/coupling/solid_drag_law.hpp"
#include <numbers>

#include "systems/coupling/solid_drag.hpp"
#include "systems/physics/coupling/drag_law.hpp"
#include "systems/physics/mps/mps_common.hpp"

namespace riffle {

SolidDragLaw::SolidDragLaw(const Model& model)
    : model_(model.coupling),
      density_(model.water_density()),
      viscosity_(model.water_kinematic_viscosity() * model.water_density()) {}

void SolidDragLaw::run(SystemContext& context) {
  const GrainProperties& properties = context.read<GrainProperties>();
  const GrainVoidage& voidages = context.read<GrainVoidage>();
  const GrainSampledFluid& sampled = context.read<GrainSampledFluid>();
  GrainDrag& drag = context.write<GrainDrag>();
  for_each_particle(voidages.voidage.size(), [&](std::size_t grain) {
    const double voidage = voidages.voidage[grain];
    const double weight = sampled.fluid_weight[grain];
    if (model_.self_induced_velocity && !carries_self_induced_disturbance(model_, weight, voidage)) {
      clear_self_induced_disturbance(drag, grain);
      if (weight > 0.0) drag.undisturbed_velocity[grain] = sampled.fluid_velocity[grain];
    }
    if (!ergun_applies(voidage, model_)) {
      drag.ergun_resistance[grain] = drag.ergun_inertial_resistance[grain] = 0.0;
      return;
    }
    const double diameter = 2.0 * properties.radius[grain];
    const double volume = std::numbers::pi / 6.0 * diameter * diameter * diameter;  // as solid_drag's other branches
    const ErgunDrag ergun = ergun_drag(voidage, diameter, density_, viscosity_, model_);
    drag.ergun_resistance[grain] = volume * ergun.viscous;
    drag.ergun_inertial_resistance[grain] = volume * ergun.inertial;
  });
  context.count_items(voidages.voidage.size());
}

}  // namespace riffle
