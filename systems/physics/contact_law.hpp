#pragma once
// Contact laws for spheres and planes (seed 000 Sec. 3.2, seed 003 Sec. 2.2, seed 004 Sec. 2.2; numerics.md Sec. 4).
//
// Conventions: `normal` points from the first body to the second; the overlap is positive while touching;
// `contact_velocity` is the velocity of the second body's surface point minus the first's at the contact, so the
// bodies approach while normal . contact_velocity < 0. The tangential spring is the accumulated tangential
// displacement (second relative to first), kept in the current tangent plane; the force returned acts on the first
// body (the second receives its negative).
//
// Normal force, no cohesion: F_n = max(0, k_n(d) d + gamma_n(d) d'), with
//   Hertz-Mindlin:  k_n = 4/3 E* sqrt(R* d);          gamma_n = c sqrt(m* k_n)  (so gamma_n ~ d^{1/4})
//   linear:         k_n = m* (pi^2 + ln^2 e) / t_c^2; gamma_n = c sqrt(m* k_n)
// Each is x'' = -f(x) - c g(x) x' in scaled variables, and the achieved restitution depends on c alone: c is
// calibrated once per material pair (calibrate_damping) so that the achieved restitution, cut-off included, is the
// requested one. For Hertz-Mindlin c = sqrt(5) |beta| with the seed-003 beta when the cut-off is ignored.
// Tangential: k_t = 8 G* sqrt(R* d) (Mindlin) or 2/7 k_n (linear, equal tangential and normal periods);
// gamma_t from the same c. Coulomb limit |F_t| <= mu F_n; when sliding the spring is reset to carry mu F_n alone
// (Cundall & Strack 1979). Rolling friction (seed 003 Eq. 20): T = -mu_r R* F_n (w_rel / |w_rel|).
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "components/vec.hpp"
#include "components/model.hpp"

namespace riffle {

struct ContactGeometry {
  Vec3 normal;                     ///< [1] unit, from the first body to the second
  double overlap = 0.0;            ///< [m] > 0 while touching
  Vec3 contact_velocity;           ///< [m/s] second surface point minus first, at the contact
  Vec3 relative_angular_velocity;  ///< [rad/s] w_first - w_second (rolling friction)
  double effective_radius = 0.0;   ///< [m] R*: 1/R* = 1/R_i + 1/R_j (a plane has 1/R = 0)
  double effective_mass = 0.0;     ///< [kg] m*: 1/m* = 1/m_i + 1/m_j (a wall has 1/m = 0)
};

struct ContactResponse {
  Vec3 force_on_first = Vec3::Zero();           ///< [N]
  Vec3 rolling_torque_on_first = Vec3::Zero();  ///< [N m] (the second body gets the negative)
  double normal_force = 0.0;                    ///< [N] >= 0
  bool sliding = false;
};

/// Evaluates one contact over a sub-step of length dt and advances its tangential spring.
inline ContactResponse evaluate_contact(ContactLaw law, const ContactPairParameters& pair,
                                        const ContactGeometry& contact, Vec3& tangential_spring, double dt) {
  ContactResponse response;
  const Vec3& n = contact.normal;
  const double normal_speed = contact.contact_velocity.dot(n);  // < 0 while approaching
  const Vec3 tangential_velocity = contact.contact_velocity - normal_speed * n;
  const double overlap = contact.overlap;
  const double m = contact.effective_mass;

  double normal_stiffness, normal_damping, tangential_stiffness;
  if (law == ContactLaw::kHertzMindlin) {
    const double root = std::sqrt(contact.effective_radius * overlap);  // sqrt(R* d)
    normal_stiffness = pair.normal_stiffness_coefficient * root;
    // gamma_n = c sqrt(k_n(d) m*): the scaling in which c alone sets the restitution, whatever the speed.
    normal_damping = pair.damping * std::sqrt(normal_stiffness * m);
    tangential_stiffness = pair.tangential_stiffness_coefficient * root;
  } else {
    normal_stiffness = pair.normal_stiffness_coefficient * m;
    normal_damping = pair.normal_damping_coefficient * m;
    tangential_stiffness = pair.tangential_stiffness_coefficient * normal_stiffness;
  }
  const double tangential_damping = pair.tangential_damping_ratio * normal_damping;
  const double normal_force = std::max(0.0, normal_stiffness * overlap - normal_damping * normal_speed);

  // Keep the spring in the current tangent plane, with its length (the contact frame rotates with the pair).
  Vec3 spring = tangential_spring;
  const double out_of_plane = spring.dot(n);
  if (out_of_plane != 0.0) {
    const double length_squared = spring.squaredNorm();
    spring -= out_of_plane * n;
    const double projected_squared = spring.squaredNorm();
    if (projected_squared > 0.0) spring *= std::sqrt(length_squared / projected_squared);
  }
  spring += dt * tangential_velocity;

  Vec3 tangential_force = tangential_stiffness * spring + tangential_damping * tangential_velocity;
  const double friction_limit = pair.friction * normal_force;
  const double tangential_squared = tangential_force.squaredNorm();
  if (tangential_squared > friction_limit * friction_limit) {
    response.sliding = true;
    tangential_force *= friction_limit / std::sqrt(tangential_squared);
    spring = tangential_stiffness > 0.0 ? Vec3(tangential_force / tangential_stiffness) : Vec3::Zero();
  }
  tangential_spring = spring;
  response.normal_force = normal_force;
  response.force_on_first = -normal_force * n + tangential_force;

  if (pair.rolling_friction > 0.0) {
    const double spin = contact.relative_angular_velocity.norm();
    if (spin > 0.0)
      response.rolling_torque_on_first = -pair.rolling_friction * contact.effective_radius * normal_force / spin *
                                         contact.relative_angular_velocity;
  }
  return response;
}

/// Fills the derived coefficients of `pair` from its moduli, damping and restitution (call after those are set).
void prepare_contact_pair(ContactPairParameters& pair, ContactLaw law, double collision_time);

/// Restitution achieved by the scaled normal equation of `law` with damping c (no-tension cut-off included).
double achieved_restitution(ContactLaw law, double damping);
/// The damping c for which achieved_restitution(law, c) == restitution (restitution in (0, 1]).
double calibrate_damping(ContactLaw law, double restitution);

/// Restitution that riffle's DEM actually achieves for a head-on impact at `speed` on a wall (or, in relative
/// coordinates, of two grains) integrated at sub-step `dt`: velocity Verlet as the sub-step graph runs it (half kick,
/// drift, the force from evaluate_contact at the drifted overlap and the half-step velocity, half kick), until the
/// overlap opens again. The contact starts at `phase` in [0, 1) of a sub-step (the discrete answer depends on where
/// the first touch falls). Returns +inf if the impact has not ended after `max_substeps` (an unstable damping term can
/// keep a grain inside its wall for ever). No gravity: the estimate is about the contact alone.
double discrete_restitution(ContactLaw law, const ContactPairParameters& pair, double effective_radius,
                            double effective_mass, double speed, double dt, double phase,
                            std::int64_t max_substeps = 100000);

/// The largest deviation |e_discrete - e| over `phases` evenly spread first-touch phases (see discrete_restitution).
double worst_restitution_error(ContactLaw law, const ContactPairParameters& pair, double effective_radius,
                               double effective_mass, double speed, double dt, int phases = 8);

/// Hertz: duration of an elastic impact at speed v, t_c = 2.9432 d_max / v, d_max = (15 m* v^2/(16 E* sqrt R*))^0.4.
double hertz_contact_time(double effective_young, double effective_radius, double effective_mass, double speed);
double hertz_max_overlap(double effective_young, double effective_radius, double effective_mass, double speed);
/// Rayleigh wave time of a sphere: pi R sqrt(rho / G) / (0.1631 nu + 0.8766).
double rayleigh_time(double radius, double density, double young_modulus, double poisson_ratio);

}  // namespace riffle
