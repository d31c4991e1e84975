#include "systems/coupling/solid_drag.hpp"

#include <algorithm>
#include <cmath>

#include "systems/physics/coupling/drag_law.hpp"
#include "systems/physics/mps/mps_common.hpp"
#include "systems/physics/coupling/self_induced.hpp"

namespace riffle {

SolidDrag::SolidDrag(const Model& model)
    : model_(model.coupling),
      fluid_(model.fluid),
      density_(model.water_density()),
      kinematic_viscosity_(model.water_kinematic_viscosity()),
      effective_radius_(model.fluid.enabled ? mps_constants(model.fluid).effective_radius : 0.0),
      fluid_step_(model.dt),
      inverse_distance_(model.coupling.self_induced_velocity ? self_induced_inverse_distance() : 0.0) {}

void SolidDrag::run(SystemContext& context) {
  const GrainState& grains = context.read<GrainState>();
  const GrainProperties& properties = context.read<GrainProperties>();
  const GrainSampledFluid& sampled = context.read<GrainSampledFluid>();
  const GrainVoidage& voidages = context.read<GrainVoidage>();
  GrainDrag& drag = context.write<GrainDrag>();
  const double density = density_;
  const double viscosity = kinematic_viscosity_ * density;
  const double dt = context.dt;
  // The exchange's delay is two fluid steps of the length this step has (a Courant- or drag-limited step is shorter
  // than run.dt).
  const double fluid_step = context.fluid_step(fluid_step_);
  const double kPi = 3.14159265358979323846;
  for_each_particle(grains.size(), [&](std::size_t grain) {
    if (sampled.fluid_weight[grain] <= 0.0) {
      drag.drag_force[grain] = Vec3::Zero();
      if (model_.self_induced_velocity) clear_disturbance(drag, grain);
      return;
    }
    const double voidage = voidages.voidage[grain];
    const double diameter = 2.0 * properties.radius[grain];
    const double volume = kPi / 6.0 * diameter * diameter * diameter;
    // Mixture reading (docs/COUPLING.md): the sampled MPS velocity is the mixture's volume flux, so the pore water
    // passes the grain at (u - u_s) / eps; the seed's reading takes u as the pore velocity itself.
    const double share = flux_share(model_.fluid_velocity, voidage);
    if (model_.self_induced_velocity && voidage > kSelfInducedMinVoidage) {
      drag_without_own_disturbance(grain, grains, properties, sampled, voidage, share, dt, fluid_step, drag);
    } else {
      const Vec3 relative = sampled.fluid_velocity[grain] - grains.velocity[grain];
      const Vec3 slip = relative / share;
      const double coefficient = drag_per_volume(voidage, diameter, slip.norm(), density, viscosity, model_);
      drag.drag_force[grain] = coefficient * volume * slip;
      if (model_.self_induced_velocity) {  // a grain in a dense bed: no correction (its validity: dilute grains)
        clear_disturbance(drag, grain);
        drag.undisturbed_velocity[grain] = sampled.fluid_velocity[grain];
      }
    }
    drag.drag_impulse[grain] += dt * drag.drag_force[grain];
  });
  context.count_items(grains.size());
}

void SolidDrag::clear_disturbance(GrainDrag& drag, std::size_t grain) {
  drag.self_induced_fast[grain] = drag.self_induced_middle[grain] = drag.self_induced_slow[grain] = Vec3::Zero();
  drag.undisturbed_velocity[grain] = Vec3::Zero();
}

// docs/COUPLING.md, "The undisturbed fluid velocity". The water received the grain's drag (over the flux share in the
// mixture reading) spread with the sampling kernel, so the sampled velocity holds the grain's own regularised
// Stokeslet: steady, u_self = -K phi(Re_R) F / flux_share with K = <1/r> / (6 pi mu), built up over time through
// three first-order lags (SelfInducedModes). Each mode m relaxes over this sub-step towards -a_m K phi F_new with the
// exact factor e_m = exp(-dt / tau_m), so u_self,new = carried - alpha K phi F_new / flux_share with
// carried = sum e_m y_m and alpha = sum a_m (1 - e_m). The slip the drag sees, w = u_sampled - u_self,new - v, then
// satisfies w (1 - gain(|w|)) = u_sampled - v - carried (self_induced.hpp): solved along that direction.
// The Oseen linearisation is about the water the spread force moves through: in the Lagrangian MPS water the
// particles around the grain move with its disturbance, so Re_R = |u_sampled - v| R / nu (known for the sub-step,
// so phi is explicit). Convection also ends the build-up: the mode times are T_m R^2 / (nu (1 + T_m Re_R)), the
// diffusive time capped by the time R / |u_sampled - v| the water takes to pass the kernel.
void SolidDrag::drag_without_own_disturbance(std::size_t grain, const GrainState& grains,
                                             const GrainProperties& properties, const GrainSampledFluid& sampled,
                                             double voidage, double flux_share, double dt, double fluid_step,
                                             GrainDrag& drag) {
  const double kPi = 3.14159265358979323846;
  const double density = fluid_.density;
  const double nu = fluid_.kinematic_viscosity;
  const double viscosity = nu * density;
  const double diameter = 2.0 * properties.radius[grain];
  const double volume = kPi / 6.0 * diameter * diameter * diameter;
  const double kernel_radius = properties.radius[grain] + effective_radius_;
  const double mobility = inverse_distance_ / (6.0 * kPi * viscosity * kernel_radius);  // K [m/s per N]
  const Vec3& velocity = grains.velocity[grain];
  const Vec3& sampled_velocity = sampled.fluid_velocity[grain];

  const double reynolds_r = (sampled_velocity - velocity).norm() * kernel_radius / nu;
  const double phi = self_induced_oseen_factor(reynolds_r);
  // The water shows a sub-step's drag about two fluid steps later (spread at the step's end, applied in the next
  // step's prediction, sampled at the start of the one after, used over it): each lag also waits that long (a
  // delay d ahead of a lag tau is a lag tau + d to first order).
  const double exchange_delay = 2.0 * fluid_step;
  std::array<Vec3*, SelfInducedModes::kCount> modes = {&drag.self_induced_fast[grain], &drag.self_induced_middle[grain],
                                                       &drag.self_induced_slow[grain]};
  std::array<double, SelfInducedModes::kCount> keep{};
  Vec3 carried = Vec3::Zero();
  double alpha = 0.0;
  for (int m = 0; m < SelfInducedModes::kCount; ++m) {
    const double tau = SelfInducedModes::time[m] * kernel_radius * kernel_radius /
                           (nu * (1.0 + SelfInducedModes::time[m] * reynolds_r)) +
                       exchange_delay;
    keep[m] = std::exp(-dt / tau);
    carried += keep[m] * *modes[m];
    alpha += SelfInducedModes::amplitude[m] * (1.0 - keep[m]);
  }
  const Vec3 rhs = sampled_velocity - velocity - carried;
  const double rhs_length = rhs.norm();
  const auto gain = [&](double slip_length) {
    const double coefficient = drag_per_volume(voidage, diameter, slip_length / flux_share, density, viscosity, model_);
    return alpha * mobility * phi * coefficient * volume / (flux_share * flux_share);
  };
  const double slip_length = solve_self_induced_slip(rhs_length, gain);
  const Vec3 relative = rhs_length > 0.0 ? Vec3(rhs * (slip_length / rhs_length)) : Vec3::Zero();
  const Vec3 slip = relative / flux_share;
  const double coefficient = drag_per_volume(voidage, diameter, slip.norm(), density, viscosity, model_);
  const Vec3 force = coefficient * volume * slip;
  Vec3 disturbance = Vec3::Zero();
  for (int m = 0; m < SelfInducedModes::kCount; ++m) {
    *modes[m] = keep[m] * *modes[m] -
                (SelfInducedModes::amplitude[m] * (1.0 - keep[m]) * mobility * phi / flux_share) * force;
    disturbance += *modes[m];
  }
  drag.drag_force[grain] = force;
  drag.undisturbed_velocity[grain] = sampled_velocity - disturbance;
}

}  // namespace riffle
