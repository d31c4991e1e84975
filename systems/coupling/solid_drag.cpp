#include "systems/coupling/solid_drag.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "systems/physics/coupling/drag_law.hpp"
#include "systems/physics/coupling/lubrication.hpp"
#include "systems/physics/mps/mps_common.hpp"
#include "systems/physics/coupling/self_induced.hpp"
#include "systems/physics/geometry/tank_kinematics.hpp"

namespace riffle {

SolidDrag::SolidDrag(const Model& model)
    : model_(model.coupling),
      tank_(model.tank),
      faces_(tank_faces(model)),
      fluid_(model.fluid),
      density_(model.water_density()),
      kinematic_viscosity_(model.water_kinematic_viscosity()),
      effective_radius_(model.fluid.enabled ? mps_constants(model.fluid).effective_radius : 0.0),
      spacing_(model.fluid.spacing),
      fluid_step_(model.dt),
      inverse_distance_(model.coupling.self_induced_velocity ? self_induced_inverse_distance() : 0.0) {}

SolidDrag::TankFaces SolidDrag::tank_faces(const Model& model) {
  TankFaces faces;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side)
      faces.wall[axis][side] = !model.tank.periodic[axis] && !model.tank.face_open(axis, side);
  faces.low = model.tank.origin;
  faces.high = model.tank.origin + model.tank.size;
  return faces;
}

void SolidDrag::run(SystemContext& context) {
  const GrainState& grains = context.read<GrainState>();
  const GrainProperties& properties = context.read<GrainProperties>();
  const GrainSampledFluid& sampled = context.read<GrainSampledFluid>();
  const GrainVoidage& voidages = context.read<GrainVoidage>();
  const GrainAddedMass& added = context.read<GrainAddedMass>();
  GrainDrag& drag = context.write<GrainDrag>();
  const double density = density_;
  const double viscosity = kinematic_viscosity_ * density;
  const double dt = context.dt;
  // The exchange's delay is two fluid steps of the length this step has (a Courant- or drag-limited step is shorter
  // than run.dt).
  const double fluid_step = context.fluid_step(fluid_step_);
  const Vec3 tank_shift = model_.self_induced_velocity ? tank_kinematics(tank_.motion, context.time).displacement
                                                       : Vec3::Zero();
  // A grain the self-induced correction does not act on (dry, or in a dense bed) had its disturbance cleared and its
  // undisturbed velocity set at the step's start (solid_drag_law): it holds over the step.
  for_each_particle(grains.size(), [&](std::size_t grain) {
    if (sampled.fluid_weight[grain] <= 0.0) {
      drag.drag_force[grain] = Vec3::Zero();
      return;
    }
    const double voidage = voidages.voidage[grain];
    const double diameter = 2.0 * properties.radius[grain];
    const double volume = std::numbers::pi / 6.0 * diameter * diameter * diameter;
    // Mixture reading (docs/COUPLING.md): the sampled MPS velocity is the mixture's volume flux, so the pore water
    // passes the grain at (u - u_s) / eps; the seed's reading takes u as the pore velocity itself.
    const double share = flux_share(model_.fluid_velocity, voidage);
    if (carries_self_induced_disturbance(model_, sampled.fluid_weight[grain], voidage)) {
      // The water takes back the added-mass and history forces with the drag (fluid_drag_reaction): their reaction
      // disturbs it as the drag's does (the added mass's as the last half kick applied it, the history's memory
      // as held over the step; both zero when off).
      const Vec3 inertial_force = inertial_reaction_force(added, grain);
      drag_without_own_disturbance(grain, grains, properties, sampled, voidage, share, dt, fluid_step, tank_shift,
                                   inertial_force, drag);
    } else {
      const Vec3 relative = sampled.fluid_velocity[grain] - grains.velocity[grain];
      const Vec3 slip = relative / share;
      // In Ergun's range the law at this step's voidage is ready (solid_drag_law): only the slip is new.
      if (ergun_applies(voidage, model_))
        drag.drag_force[grain] =
            (drag.ergun_resistance[grain] + drag.ergun_inertial_resistance[grain] * slip.norm()) * slip;
      else
        drag.drag_force[grain] =
            drag_per_volume(voidage, diameter, slip.norm(), density, viscosity, model_) * volume * slip;
    }
    drag.drag_impulse[grain] += dt * drag.drag_force[grain];
  });
  context.count_items(grains.size());
}

void clear_self_induced_disturbance(GrainDrag& drag, std::size_t grain) {
  drag.self_induced_fast[grain] = drag.self_induced_middle[grain] = drag.self_induced_slow[grain] = Vec3::Zero();
  drag.self_induced_wall_x[grain] = drag.self_induced_wall_y[grain] = drag.self_induced_wall_z[grain] = Vec3::Zero();
  drag.undisturbed_velocity[grain] = Vec3::Zero();
}

// docs/COUPLING.md, "The undisturbed fluid velocity". The water received the grain's drag (over the flux share in the
// mixture reading) spread with the sampling kernel, so the sampled velocity holds the grain's own regularised
// Stokeslet: steady, u_self = -K phi(Re_R) F / flux_share with K = <1/r> / (6 pi mu), built up over time through
// three first-order lags. Each mode m relaxes over this sub-step towards -b_m K F_new (b_m the amplitudes fitted to
// the unsteady Oseen build-up at Re_R, summing to phi; self_induced_mode_amplitudes) with the exact factor
// e_m = exp(-dt / tau_m), so u_self,new = carried - alpha K F_new / flux_share with carried = sum e_m y_m and
// alpha = sum b_m (1 - e_m). The slip the drag sees, w = u_sampled - u_self,new - v, then satisfies
// w (1 - gain(|w|)) = u_sampled - v - carried (self_induced.hpp): solved along that direction.
// The Oseen linearisation has two speeds. The slow mode is the far field, built where the water is undisturbed: the
// spread force moves through it at the grain's velocity relative to the undisturbed water, Re_R = |u_sampled -
// u_carried - v| R / nu (the disturbance carried from the last sub-step: explicit). The fast and middle modes are
// the kernel's own scale, where the Lagrangian MPS water moves with the disturbance: Re_near = |u_sampled - v| R /
// nu. Each mode takes its time at its own Reynolds number (the mode times T_m R^2 / (nu (1 + T_m Re)): convection
// ends each build-up within about the time the water takes to pass the kernel); the near modes their amplitudes at
// Re_near, and the slow mode what they leave of the far field's steady phi(Re_R) (self_induced_two_speed_amplitudes).
// Measured on grains settling at Re 1, d/l0 = 1 and 2: the MPS water's own disturbance follows the unsteady Oseen
// response at Re_R (within 8 % and 3 %) until the floor comes near; with Re_near on every mode the model's came out
// 11-13 % higher, with the slow mode's own fit at Re_R beside the near modes 16 % higher, and with Re_R on every mode
// the build-up at Re 10, d/l0 = 2 lagged the water's (the terminal speed 3.3 % fast; docs/cases/settling.md).
void SolidDrag::drag_without_own_disturbance(std::size_t grain, const GrainState& grains,
                                             const GrainProperties& properties, const GrainSampledFluid& sampled,
                                             double voidage, double flux_share, double dt, double fluid_step,
                                             const Vec3& tank_shift, const Vec3& inertial_force, GrainDrag& drag) {
  const double density = fluid_.density;
  const double nu = fluid_.kinematic_viscosity;
  const double viscosity = nu * density;
  const double diameter = 2.0 * properties.radius[grain];
  const double volume = std::numbers::pi / 6.0 * diameter * diameter * diameter;
  const double kernel_radius = coupling_kernel_radius(properties.radius[grain], effective_radius_, spacing_, true);
  const double mobility = inverse_distance_ / (6.0 * std::numbers::pi * viscosity * kernel_radius);  // K [m/s per N]
  const Vec3& velocity = grains.velocity[grain];
  const Vec3& sampled_velocity = sampled.fluid_velocity[grain];

  // The speed the spread force moves through the water at, far from the grain: its velocity relative to the
  // undisturbed water, estimated with the disturbance carried from the last sub-step.
  const Vec3 carried_disturbance = carried_self_induced_disturbance(drag, grain);
  const double relative_speed = (sampled_velocity - carried_disturbance - velocity).norm();
  const double reynolds_r = relative_speed * kernel_radius / nu;
  // In a suspension the water this grain samples holds, beyond the suspension's mean flow, the share S(0) of its own
  // disturbance that its neighbours' disturbances and their backflow leave (self_induced_suspension_share): the
  // drag law's hindrance already holds the neighbours' mean effect. A lone grain reads eps = 1 (the self-corrected
  // voidage): all of it. Only with the self-corrected voidage estimate: the cloud-in-cell reading counts the grain's
  // own volume, so a lone grain would read a suspension of itself. (The Brinkman screening of a fixed array put the
  // share at 0.07-0.30 at phi = 0.05, where the water holds 0.6-0.85 of it: the suspension settled 2-18 % fast in the
  // column's frame, more as l0 shrank; docs/cases/settling.md, "Hindered settling".)
  const double suspension =
      model_.voidage_estimate == CouplingModel::VoidageEstimate::kSelfCorrected
          ? self_induced_suspension_share(1.0 - voidage)
          : 1.0;
  // The drag per grain volume at the sub-step's known slip: the walls' bound below.
  const double known_drag_per_volume =
      drag_per_volume(voidage, diameter, relative_speed / flux_share, density, viscosity, model_);
  // The slow mode is the far field (Re_R); the fast and middle ones the kernel's scale (Re_near).
  const double reynolds_near = (sampled_velocity - velocity).norm() * kernel_radius / nu;
  const auto mode_reynolds = [&](int m) { return m + 1 == SelfInducedModes::kCount ? reynolds_r : reynolds_near; };
  // The near modes shape the early build-up; the total, once built, is the far field's phi(Re_R).
  const std::array<double, SelfInducedModes::kCount> amplitudes =
      self_induced_two_speed_amplitudes(reynolds_near, reynolds_r);
  const double phi = (amplitudes[0] + amplitudes[1] + amplitudes[2]) * suspension;
  // The water shows a sub-step's drag about two fluid steps later (spread at the step's end, applied in the next
  // step's prediction, sampled at the start of the one after, used over it): each lag also waits that long (a
  // delay d ahead of a lag tau is a lag tau + d to first order).
  const double exchange_delay = 2.0 * fluid_step;
  std::array<Vec3*, SelfInducedModes::kCount> modes = {&drag.self_induced_fast[grain], &drag.self_induced_middle[grain],
                                                       &drag.self_induced_slow[grain]};
  std::array<double, SelfInducedModes::kCount> keep{};
  Vec3 carried = Vec3::Zero();
  double alpha = 0.0, slow_time = 0.0;
  for (int m = 0; m < SelfInducedModes::kCount; ++m) {
    const double tau = self_induced_mode_time(m, mode_reynolds(m)) * kernel_radius * kernel_radius / nu + exchange_delay;
    slow_time = std::max(slow_time, tau);
    keep[m] = std::exp(-dt / tau);
    carried += keep[m] * *modes[m];
    alpha += amplitudes[static_cast<std::size_t>(m)] * suspension * (1.0 - keep[m]);
  }
  // The tank's walls hold the water, so the disturbance next to them is smaller (self_induced_wall_factors), along
  // a wall's normal most: each wall takes off (1 - f) of the free disturbance, per component. And the drag law is the
  // unbounded one: with the grain's own disturbance and its images taken out, the wall's resistance on the grain
  // itself, at the grain's scale (which the water does not resolve), is put back: Brenner's (1961) lambda along
  // the normal, Faxen's along the plane, as the slip the grain would read from its own image, (1 - 1/lambda) of
  // the slip, so that a steady slip is lambda times the undisturbed one. Both are the same reflection, so each pair
  // of walls across an axis feeds one lag, built as the disturbance reaches the nearer wall and comes back (at least
  // as slow as the disturbance's slowest mode, which builds its far field), with the Oseen reduction at that
  // distance (the water's inertia screens a far wall). The walls add (reflections to first order). Below the
  // lubrication cut-off the normal resistance is the lubrication's (solid_lubrication); below 0.1 a both are held
  // (the explicit drag stays stable; contact is the lubrication's and the contact law's).
  std::array<Vec3*, 3> walls = {&drag.self_induced_wall_x[grain], &drag.self_induced_wall_y[grain],
                                &drag.self_induced_wall_z[grain]};
  // Per axis: the share of phi K F / flux_share each component loses, and the share of the slip added (the sum of
  // 1 - 1/lambda). Eigen's vectors start unset: zeroed here for the axes without walls.
  std::array<Vec3, 3> wall_reduction = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  std::array<Vec3, 3> wall_resistance_share = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  std::array<double, 3> wall_keep{};
  const Vec3& position = grains.position[grain];
  const double radius = properties.radius[grain];
  const double lubricated_gap = model_.lubrication ? model_.lubrication_cutoff_gap(radius) : 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    Vec3 reduction = Vec3::Zero(), resistance = Vec3::Zero();
    double nearest = std::numeric_limits<double>::infinity();
    for (int side = 0; side < 2; ++side) {
      if (!faces_.wall[axis][side]) continue;
      const double plane = (side == 0 ? faces_.low[axis] : faces_.high[axis]) + tank_shift[axis];
      const double height = std::max(side == 0 ? position[axis] - plane : plane - position[axis], 0.0);
      const SelfInducedWallFactors factors = self_induced_wall_factors(height / kernel_radius);
      const double gap_over_radius = std::max(height - radius, kFaxenSmallestGap * radius) / radius;
      const double normal = height - radius < lubricated_gap ? 1.0 : wall_resistance(gap_over_radius);
      const double tangential = faxen_wall_resistance_tangential(gap_over_radius);
      for (int component = 0; component < 3; ++component) {
        reduction[component] += 1.0 - (component == axis ? factors.normal : factors.tangential);
        resistance[component] += 1.0 - 1.0 / (component == axis ? normal : tangential);
      }
      nearest = std::min(nearest, height);
    }
    if (!std::isfinite(nearest)) {  // no wall across this axis (periodic or open): nothing held back
      wall_keep[axis] = 1.0;
      *walls[axis] = Vec3::Zero();
      continue;
    }
    const double image_distance = 2.0 * nearest;
    const double image_reynolds = relative_speed * image_distance / nu;
    const double screening = self_induced_oseen_factor(image_reynolds);
    // The reflection reaches the grain from its image, 2h away, when the disturbance has spread there and back: a
    // point Stokeslet's build-up at that distance (self_induced_wall_time), never faster than the slowest mode, so
    // that the lags' gain stays bounded (below). A wall 7 d away at Re 1 took effect within the slowest mode's
    // 1.4 s instead of the reflection's 8 s, and the sphere settled 0.5 % faster in a box of 15 d than in one of 30.
    const double reflection_time =
        self_induced_wall_time(image_reynolds) * image_distance * image_distance / nu + exchange_delay;
    wall_keep[axis] = std::exp(-dt / std::max(slow_time, reflection_time));
    wall_reduction[axis] = screening * reduction;
    wall_resistance_share[axis] = screening * resistance;
    carried += wall_keep[axis] * *walls[axis];
  }
  // Bounds, so that the walls added to first order cannot overturn what they correct (in a corner, at contact):
  // together they take off at most the free disturbance (phi), and their resistance shares stay below
  // 0.9 - g_i, g_i = K phi c V / flux_share^2 the steady gain of the grain's own disturbance, the bound under which
  // the lags of the solve below cannot grow (a lag of keep k on a share rho, with the solve's gain g, multiplies its
  // state by k (1 - g) / (1 - g - (1 - k) rho) per sub-step).
  const double steady_gain = mobility * phi * known_drag_per_volume * volume / (flux_share * flux_share);
  for (int component = 0; component < 3; ++component) {
    double reduction = 0.0, share = 0.0;
    for (int axis = 0; axis < 3; ++axis) {
      reduction += wall_reduction[axis][component];
      share += wall_resistance_share[axis][component];
    }
    const double share_bound = std::max(0.0, 0.9 - steady_gain);
    for (int axis = 0; axis < 3; ++axis) {
      if (reduction > phi) wall_reduction[axis][component] *= phi / reduction;
      if (share > share_bound) wall_resistance_share[axis][component] *= share_bound / share;
    }
  }
  // u_self,new = carried - K diag(m) F / flux_share - diag(rho) w, with m_i = alpha - the walls' reductions
  // (at least 0: the walls' lags are at least as slow as the slowest mode, so (1 - keep) phi <= alpha) and rho_i the
  // walls' resistance shares, each through its lag's step (1 - keep).
  Vec3 gain_share = Vec3::Constant(alpha), resistance_gain = Vec3::Zero();
  for (int axis = 0; axis < 3; ++axis) {
    gain_share -= (1.0 - wall_keep[axis]) * wall_reduction[axis];
    resistance_gain += (1.0 - wall_keep[axis]) * wall_resistance_share[axis];
  }
  gain_share = gain_share.cwiseMax(0.0);
  // The known forces beside the drag (added mass, history) push the water too: u_self,new gains -K diag(m) F_I / s.
  const Vec3 rhs = sampled_velocity - velocity - carried +
                   (mobility / flux_share) * Vec3(gain_share.cwiseProduct(inertial_force));
  const auto gains = [&](double slip_length) {
    const double coefficient = drag_per_volume(voidage, diameter, slip_length / flux_share, density, viscosity, model_);
    return Vec3((mobility * coefficient * volume / (flux_share * flux_share)) * gain_share + resistance_gain);
  };
  const Vec3 relative = solve_self_induced_slip(rhs, gains);
  const Vec3 slip = relative / flux_share;
  const double coefficient = drag_per_volume(voidage, diameter, slip.norm(), density, viscosity, model_);
  const Vec3 force = coefficient * volume * slip;
  const Vec3 on_water = force + inertial_force;  // all the water takes back from this grain
  Vec3 disturbance = Vec3::Zero();
  for (int m = 0; m < SelfInducedModes::kCount; ++m) {
    *modes[m] = keep[m] * *modes[m] -
                (amplitudes[static_cast<std::size_t>(m)] * suspension * (1.0 - keep[m]) * mobility / flux_share) * on_water;
    disturbance += *modes[m];
  }
  for (int axis = 0; axis < 3; ++axis) {
    const Vec3 target = (mobility / flux_share) * Vec3(wall_reduction[axis].cwiseProduct(on_water)) -
                        Vec3(wall_resistance_share[axis].cwiseProduct(relative));
    *walls[axis] = wall_keep[axis] * *walls[axis] + (1.0 - wall_keep[axis]) * target;
    disturbance += *walls[axis];
  }
  drag.drag_force[grain] = force;
  drag.undisturbed_velocity[grain] = sampled_velocity - disturbance;
}

}  // namespace riffle
