#include "systems/physics/dem/contact_law.hpp"

#include <limits>
#include <stdexcept>

namespace riffle {

namespace {

/// Scaled normal force: Hertz -x^{3/2} - c x^{1/4} x', linear -x - c x'.
double scaled_force(ContactLaw law, double damping, double x, double v) {
  if (law == ContactLaw::kHertzMindlin) {
    const double root = std::sqrt(std::max(x, 0.0));
    return -x * root - damping * std::sqrt(root) * v;
  }
  return -x - damping * v;
}

}  // namespace

double achieved_restitution(ContactLaw law, double damping) {
  // Start touching with unit approach speed; RK4 in scaled time until the force would pull (cut-off) or the
  // overlap closes. The scaled contact lasts about 3.2 (Hertz) or pi (linear) time units.
  const double step = 1e-3;
  double x = 0.0, v = 1.0;
  for (int k = 0; k < 100000; ++k) {
    auto acceleration = [&](double xx, double vv) { return scaled_force(law, damping, xx, vv); };
    const double k1x = v, k1v = acceleration(x, v);
    const double k2x = v + 0.5 * step * k1v, k2v = acceleration(x + 0.5 * step * k1x, v + 0.5 * step * k1v);
    const double k3x = v + 0.5 * step * k2v, k3v = acceleration(x + 0.5 * step * k2x, v + 0.5 * step * k2v);
    const double k4x = v + step * k3v, k4v = acceleration(x + step * k3x, v + step * k3v);
    const double x_next = x + step / 6.0 * (k1x + 2 * k2x + 2 * k3x + k4x);
    const double v_next = v + step / 6.0 * (k1v + 2 * k2v + 2 * k3v + k4v);
    const double force_next = scaled_force(law, damping, x_next, v_next);
    if (v_next < 0.0 && (force_next >= 0.0 || x_next <= 0.0)) {
      // The contact ends inside this step: interpolate the speed at the sign change of force (or overlap).
      const double force_now = scaled_force(law, damping, x, v);
      double fraction = 1.0;
      if (force_next >= 0.0 && force_now < 0.0) fraction = -force_now / (force_next - force_now);
      else if (x_next <= 0.0 && x > 0.0) fraction = x / (x - x_next);
      return -(v + fraction * (v_next - v));
    }
    x = x_next;
    v = v_next;
  }
  throw std::logic_error("achieved_restitution: the scaled collision did not end");
}

void prepare_contact_pair(ContactPairParameters& pair, ContactLaw law, double collision_time) {
  if (law == ContactLaw::kHertzMindlin) {
    pair.normal_stiffness_coefficient = 4.0 / 3.0 * pair.effective_young;
    pair.normal_damping_coefficient = 0.0;
    pair.tangential_stiffness_coefficient = 8.0 * pair.effective_shear;
    // Seed 003: gamma_t / sqrt(k_t m*) = sqrt(2/3) gamma_n / sqrt(k_n m*), so gamma_t / gamma_n = sqrt(2/3 k_t/k_n).
    pair.tangential_damping_ratio =
        pair.effective_young > 0.0 ? std::sqrt(4.0 * pair.effective_shear / pair.effective_young) : 0.0;
  } else {
    const double log_e = std::log(pair.calibrated_restitution);
    pair.normal_stiffness_coefficient =
        (3.14159265358979323846 * 3.14159265358979323846 + log_e * log_e) / (collision_time * collision_time);
    pair.normal_damping_coefficient = pair.damping * std::sqrt(pair.normal_stiffness_coefficient);
    // k_t = 2/7 k_n and gamma_t = 2/7 gamma_n: a solid sphere's tangential and normal periods are then equal.
    pair.tangential_stiffness_coefficient = 2.0 / 7.0;
    pair.tangential_damping_ratio = 2.0 / 7.0;
  }
}

double calibrate_damping(ContactLaw law, double restitution) {
  if (!(restitution > 0.0 && restitution <= 1.0))
    throw std::invalid_argument("calibrate_damping: restitution must be in (0, 1]");
  if (restitution == 1.0) return 0.0;
  double low = 0.0, high = 1.0;
  while (achieved_restitution(law, high) > restitution) high *= 2.0;
  for (int iteration = 0; iteration < 60 && high - low > 1e-12 * high; ++iteration) {
    const double middle = 0.5 * (low + high);
    (achieved_restitution(law, middle) > restitution ? low : high) = middle;
  }
  return 0.5 * (low + high);
}

double discrete_restitution(ContactLaw law, const ContactPairParameters& pair, double effective_radius,
                            double effective_mass, double speed, double dt, double phase, std::int64_t max_substeps) {
  // The grain moves along +x towards a wall whose surface it reaches `phase` of a sub-step after the start.
  ContactGeometry geometry;
  geometry.normal = Vec3::UnitX();  // from the grain (first body) towards the wall
  geometry.relative_angular_velocity = Vec3::Zero();
  geometry.effective_radius = effective_radius;
  geometry.effective_mass = effective_mass;
  Vec3 spring = Vec3::Zero();
  double overlap = -(1.0 - phase) * speed * dt;  // after the first drift the overlap is phase * speed * dt
  double velocity = speed;                       // towards the wall
  double force = 0.0;                            // on the grain, along +x
  bool touched = false;
  for (std::int64_t k = 0; k < max_substeps; ++k) {
    velocity += 0.5 * dt * force / effective_mass;  // solid_kick_drift: half kick, drift
    overlap += dt * velocity;
    force = 0.0;
    if (overlap > 0.0) {  // solid_contact_forces: only touching pairs carry a force
      touched = true;
      geometry.overlap = overlap;
      geometry.contact_velocity = Vec3(-velocity, 0.0, 0.0);  // the wall's surface point minus the grain's
      force = evaluate_contact(law, pair, geometry, spring, dt).force_on_first.x();
    }
    velocity += 0.5 * dt * force / effective_mass;  // solid_kick
    if (touched && overlap <= 0.0) return -velocity / speed;
  }
  return std::numeric_limits<double>::infinity();
}

double worst_restitution_error(ContactLaw law, const ContactPairParameters& pair, double effective_radius,
                               double effective_mass, double speed, double dt, int phases) {
  double worst = 0.0;
  for (int k = 0; k < phases; ++k) {
    const double achieved = discrete_restitution(law, pair, effective_radius, effective_mass, speed, dt,
                                                 (k + 0.5) / static_cast<double>(phases));
    worst = std::max(worst, std::abs(achieved - pair.restitution));  // +inf (never ended) stays +inf
    if (!std::isfinite(worst)) break;
  }
  return worst;
}

double hertz_max_overlap(double effective_young, double effective_radius, double effective_mass, double speed) {
  return std::pow(15.0 * effective_mass * speed * speed / (16.0 * effective_young * std::sqrt(effective_radius)),
                  0.4);
}

double hertz_contact_time(double effective_young, double effective_radius, double effective_mass, double speed) {
  // t_c = 2 d_max / v * integral_0^1 dx / sqrt(1 - x^{5/2}) = 2.94328 d_max / v (Timoshenko & Goodier).
  return 2.94328 * hertz_max_overlap(effective_young, effective_radius, effective_mass, speed) / speed;
}

double rayleigh_time(double radius, double density, double young_modulus, double poisson_ratio) {
  const double shear_modulus = young_modulus / (2.0 * (1.0 + poisson_ratio));
  return 3.14159265358979323846 * radius * std::sqrt(density / shear_modulus) / (0.1631 * poisson_ratio + 0.8766);
}

}  // namespace riffle
