#include "systems/coupling/solid_drag.hpp"

#include <cmath>

#include "systems/physics/drag_law.hpp"
#include "systems/physics/mps_common.hpp"

namespace riffle {

void SolidDrag::run(SystemContext& context) {
  const GrainState& grains = context.read<GrainState>();
  const GrainProperties& properties = context.read<GrainProperties>();
  const GrainSampledFluid& sampled = context.read<GrainSampledFluid>();
  const GrainVoidage& voidages = context.read<GrainVoidage>();
  GrainDrag& drag = context.write<GrainDrag>();
  const double density = fluid_.density;
  const double viscosity = fluid_.kinematic_viscosity * density;
  const double dt = context.dt;
  const double kPi = 3.14159265358979323846;
  for_each_particle(grains.size(), [&](std::size_t grain) {
    if (sampled.fluid_weight[grain] <= 0.0) {
      drag.drag_force[grain] = Vec3::Zero();
      return;
    }
    // Mixture reading (docs/COUPLING.md): the sampled MPS velocity is the mixture's volume flux, so the pore water
    // passes the grain at (u - u_s) / eps; the seed's reading takes u as the pore velocity itself.
    const Vec3 relative = sampled.fluid_velocity[grain] - grains.velocity[grain];
    const Vec3 slip = model_.mixture_velocity ? Vec3(relative / voidages.voidage[grain]) : relative;
    const double diameter = 2.0 * properties.radius[grain];
    const double volume = kPi / 6.0 * diameter * diameter * diameter;
    const double coefficient = drag_per_volume(voidages.voidage[grain], diameter, slip.norm(), density, viscosity, model_);
    drag.drag_force[grain] = coefficient * volume * slip;
    drag.drag_impulse[grain] += dt * drag.drag_force[grain];
  });
  context.count_items(grains.size());
}

}  // namespace riffle
