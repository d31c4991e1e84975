#include "systems/coupling/solid_drag.hpp"

#include <cmath>

#include "systems/physics/drag_law.hpp"
#include "systems/physics/mps_common.hpp"

namespace riffle {

void SolidDrag::run(SystemContext& context) {
  Solids& solids = context.write<Solids>();
  const double density = fluid_.density;
  const double viscosity = fluid_.kinematic_viscosity * density;
  const double dt = context.dt;
  const double kPi = 3.14159265358979323846;
  for_each_particle(solids.size(), [&](std::size_t grain) {
    if (solids.fluid_weight[grain] <= 0.0) {
      solids.drag_force[grain] = Vec3::Zero();
      return;
    }
    // Mixture reading (docs/COUPLING.md): the sampled MPS velocity is the mixture's volume flux, so the pore water
    // passes the grain at (u - u_s) / eps; the seed's reading takes u as the pore velocity itself.
    const Vec3 relative = solids.fluid_velocity[grain] - solids.velocity[grain];
    const Vec3 slip = model_.mixture_velocity ? Vec3(relative / solids.voidage[grain]) : relative;
    const double diameter = 2.0 * solids.radius[grain];
    const double volume = kPi / 6.0 * diameter * diameter * diameter;
    const double coefficient = drag_per_volume(solids.voidage[grain], diameter, slip.norm(), density, viscosity, model_);
    solids.drag_force[grain] = coefficient * volume * slip;
    solids.drag_impulse[grain] += dt * solids.drag_force[grain];
  });
  context.count_items(solids.size());
}

}  // namespace riffle
