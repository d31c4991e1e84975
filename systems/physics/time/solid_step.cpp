#include "systems/physics/time/solid_step.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numbers>

#include "components/solids.hpp"
#include "systems/physics/dem/contact_law.hpp"

namespace riffle {

namespace {

/// Worst |achieved - requested| restitution of `impact` at sub-step dt; 0 when the contact lasts over 1000
/// sub-steps (resolved far beyond the tolerance, and too long to integrate cheaply).
double restitution_error(ContactLaw law, const DesignImpact& impact, double speed, double dt) {
  const double steps_per_contact = impact.contact_time / dt;
  if (!(steps_per_contact < 1000.0)) return 0.0;
  return worst_restitution_error(law, *impact.pair, impact.effective_radius, impact.effective_mass, speed, dt);
}

}  // namespace

StableStep stable_solid_step(const Model& model, std::vector<DesignImpact>& impacts) {
  const ContactModel& contact = model.contact;
  // From the scene's descriptions (its beds' size classes, not generated spheres), so check and run agree.
  const std::map<std::int32_t, double> smallest_radius = scene_grain_sizes(model.solids).smallest_radius_by_material;
  StableStep best{std::numeric_limits<double>::infinity(), ""};
  auto consider = [&](double candidate, const std::string& reason) {
    if (candidate < best.solid_dt) best = {candidate, reason};
  };
  auto mass_of = [&](std::int32_t material, double radius) {
    return model.materials[static_cast<std::size_t>(material)].density * 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
  };
  // The elastic-plastic rolling spring (contact_law.hpp) swings the pair's relative spin at omega_r^2 = k_r / I,
  // 1/I = sum 1/(2/5 m R^2) over the spheres that turn (the spins alone: the stiffest, the contact point held by the
  // tangential spring), where the normal contact swings at omega_n^2 = k_n / m*. With k_r = 2.25 mu_r^2 R*^2 k_n the
  // ratio omega_r / omega_n = sqrt(2.25 mu_r^2 R*^2 m* / I) does not depend on k_n, so the rolling swing's half
  // period is the contact time over it, resolved by as many sub-steps as a collision: a bound only where the ratio
  // passes 1 (a grain on a wall at mu_r > 0.42, two equal grains at 0.84).
  auto rolling_ratio = [&](const ContactPairParameters& pair, double effective_radius, double effective_mass,
                           double inverse_spin_inertia) {
    if (contact.rolling_law != RollingLaw::kElasticPlastic || !(pair.rolling_friction > 0.0)) return 0.0;
    const double arm = pair.rolling_friction * effective_radius;
    return std::sqrt(kRollingStiffnessFactor * arm * arm * effective_mass * inverse_spin_inertia);
  };
  auto inverse_spin_inertia_of = [&](std::int32_t material, double radius) {
    return 1.0 / (0.4 * mass_of(material, radius) * radius * radius);
  };
  char text[256];
  // The contact time over the rolling spring's frequency ratio, where that ratio passes 1; `impact` names the pair.
  auto consider_rolling = [&](double contact_time, double ratio, const char* impact) {
    if (!(ratio > 1.0)) return;
    std::snprintf(text, sizeof text,
                  "the elastic-plastic rolling spring's half swing, contact time %.3g s / %.3g, / %g steps per "
                  "collision (%s)",
                  contact_time, ratio, contact.steps_per_collision, impact);
    consider(contact_time / (ratio * contact.steps_per_collision), text);
  };
  char impact_name[160];
  for (const auto& [material, radius] : smallest_radius) {
    const Material& props = model.materials[static_cast<std::size_t>(material)];
    const double rayleigh = rayleigh_time(radius, props.density, props.young_modulus, props.poisson_ratio);
    std::snprintf(text, sizeof text, "%g x the Rayleigh time %.3g s of a %g m grain of %s", contact.rayleigh_fraction,
                  rayleigh, radius, props.name.c_str());
    consider(contact.rayleigh_fraction * rayleigh, text);
    for (const auto& [other, other_radius] : smallest_radius) {
      const ContactPairParameters& pair = contact.pair(material, other);
      const double effective_radius = radius * other_radius / (radius + other_radius);
      const double first_mass = mass_of(material, radius), second_mass = mass_of(other, other_radius);
      const double effective_mass = first_mass * second_mass / (first_mass + second_mass);
      const double collision = contact.law == ContactLaw::kHertzMindlin
                                   ? hertz_contact_time(pair.effective_young, effective_radius, effective_mass,
                                                        contact.max_impact_speed)
                                   : contact.collision_time;
      std::snprintf(text, sizeof text, "contact time %.3g s / %g steps per collision (%s grains of %g and %g m)",
                    collision, contact.steps_per_collision, props.name.c_str(), radius, other_radius);
      consider(collision / contact.steps_per_collision, text);
      std::snprintf(impact_name, sizeof impact_name, "%s grains of %g and %g m", props.name.c_str(), radius,
                    other_radius);
      consider_rolling(collision,
                       rolling_ratio(pair, effective_radius, effective_mass,
                                     inverse_spin_inertia_of(material, radius) +
                                         inverse_spin_inertia_of(other, other_radius)),
                       impact_name);
      if (material <= other) {
        std::snprintf(text, sizeof text, "a %g m grain of %s on a %g m grain of %s", radius, props.name.c_str(), other_radius,
                      model.materials[static_cast<std::size_t>(other)].name.c_str());
        impacts.push_back({&pair, effective_radius, effective_mass, collision, text});
      }
    }
    const ContactPairParameters& wall = contact.pair(material, model.tank.wall_material);
    const double wall_collision = contact.law == ContactLaw::kHertzMindlin
                                      ? hertz_contact_time(wall.effective_young, radius, mass_of(material, radius),
                                                           contact.max_impact_speed)
                                      : contact.collision_time;
    std::snprintf(text, sizeof text, "contact time %.3g s / %g steps per collision (%g m grain of %s on a wall)",
                  wall_collision, contact.steps_per_collision, radius, props.name.c_str());
    consider(wall_collision / contact.steps_per_collision, text);
    std::snprintf(impact_name, sizeof impact_name, "%g m grain of %s on a wall", radius, props.name.c_str());
    consider_rolling(wall_collision,
                     rolling_ratio(wall, radius, mass_of(material, radius), inverse_spin_inertia_of(material, radius)),
                     impact_name);
    std::snprintf(text, sizeof text, "a %g m grain of %s on a wall", radius, props.name.c_str());
    impacts.push_back({&wall, radius, mass_of(material, radius), wall_collision, text});
  }
  // The restitution at that sub-step: shorten it by 20 % at a time until every design impact is within tolerance.
  if (std::isfinite(best.solid_dt) && best.solid_dt > 0.0) {
    const double estimate = best.solid_dt;
    for (const DesignImpact& impact : impacts) {
      const double error_at_estimate = restitution_error(contact.law, impact, contact.max_impact_speed, estimate);
      if (error_at_estimate <= contact.restitution_tolerance) continue;
      // From the sub-step the impacts before this one left (best only shortens), at most 60 shortenings.
      double dt = best.solid_dt;
      double error = dt == estimate ? error_at_estimate
                                    : restitution_error(contact.law, impact, contact.max_impact_speed, dt);
      for (int shortening = 0; shortening < 60 && error > contact.restitution_tolerance; ++shortening) {
        dt *= 0.8;
        error = restitution_error(contact.law, impact, contact.max_impact_speed, dt);
      }
      if (dt < best.solid_dt) {
        std::snprintf(text, sizeof text,
                      "restitution %g within %g: %s at %g m/s rebounds at %.3g off it at the contact-time estimate "
                      "%.3g s",
                      impact.pair->restitution, contact.restitution_tolerance, impact.name.c_str(),
                      contact.max_impact_speed, error_at_estimate, estimate);
        best = {dt, text};
      }
    }
  }
  return best;
}

RestitutionError worst_design_impact_error(const ContactModel& contact, const std::vector<DesignImpact>& impacts,
                                           double dt) {
  RestitutionError worst;
  for (const DesignImpact& impact : impacts) {
    const double error = restitution_error(contact.law, impact, contact.max_impact_speed, dt);
    if (error >= worst.error) {
      worst.error = error;
      worst.impact = impact.name;
    }
  }
  return worst;
}

}  // namespace riffle
