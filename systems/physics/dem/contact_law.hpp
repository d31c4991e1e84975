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
// (Cundall & Strack 1979). Rolling friction, [contact] rolling_law (Ai, Chen, Rotter & Ooi 2011, Powder Technol.
// 206, 269):
//   "constant_torque" (seed 003 Eq. 20; their model A): T = -mu_r R* F_n (w_rel / |w_rel|);
//   "elastic_plastic" (their model C, after Iwashita & Oda 1998): a spring torque M, M += -k_r w_rel dt each
//   sub-step with k_r = 2.25 mu_r^2 R*^2 k_n (k_n the normal stiffness F_n / d of the law), capped at
//   |M| <= mu_r R* F_n, plus a dashpot -C_r w_rel while below the cap, C_r = 2 eta_r sqrt(I_r k_r) with eta_r = 0.3
//   (their choice) and I_r the pair's rolling inertia 1 / sum 1 / (I + m R^2) (7/5 m R^2 per sphere; a wall or a
//   fixed grain does not turn). Both act on the whole relative spin w_first - w_second, its twist about the normal
//   included; the spring is not rotated with the pair (a contact turns little while it lasts).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "components/vec.hpp"
#include "components/model.hpp"

namespace riffle {

/// The rolling-friction term of a contact evaluation: none (no pair has mu_r), or one of the RollingLaw models.
enum class RollingTerm { kNone, kConstantTorque, kElasticPlastic };
inline RollingTerm rolling_term(RollingLaw law, bool any_rolling_friction) {
  if (!any_rolling_friction) return RollingTerm::kNone;
  return law == RollingLaw::kElasticPlastic ? RollingTerm::kElasticPlastic : RollingTerm::kConstantTorque;
}
/// Ai et al. (2011): k_r = kRollingStiffnessFactor mu_r^2 R*^2 k_n (2.25 in 3D) and the dashpot's fraction of
/// critical damping eta_r.
inline constexpr double kRollingStiffnessFactor = 2.25;
inline constexpr double kRollingDampingRatio = 0.3;

struct ContactGeometry {
  Vec3 normal;                     ///< [1] unit, from the first body to the second
  double overlap = 0.0;            ///< [m] > 0 while touching
  Vec3 contact_velocity;           ///< [m/s] second surface point minus first, at the contact
  Vec3 relative_angular_velocity;  ///< [rad/s] w_first - w_second (rolling friction)
  double effective_radius = 0.0;   ///< [m] R*: 1/R* = 1/R_i + 1/R_j (a plane has 1/R = 0)
  double effective_mass = 0.0;     ///< [kg] m*: 1/m* = 1/m_i + 1/m_j (a wall has 1/m = 0)
  double rolling_inertia = 0.0;    ///< [kg m^2] I_r (elastic-plastic rolling only): 1/I_r = sum 1/(I + m R^2)
};

struct ContactResponse {
  Vec3 force_on_first = Vec3::Zero();           ///< [N]
  Vec3 rolling_torque_on_first = Vec3::Zero();  ///< [N m] (the second body gets the negative)
  double normal_force = 0.0;                    ///< [N] >= 0
  bool sliding = false;
};

// The law is written once, as contact_law_lane: straight-line, branch-free code (selects only) on plain doubles, so
// that the batched kernel (evaluate_sphere_pair_batch, what runs for grain-grain pairs) vectorises it, and the scalar
// call (evaluate_contact, what runs for grain-wall pairs and in the calibration) is the same code on one contact.
// The branches of the law become selects with both sides computed (the compiler will not speculate a possibly
// trapping division into a select); a division by zero on the discarded side yields inf or NaN that is never used.

/// One contact in the law's own terms (one lane of a batch): the geometry, the pair's coefficients and the spring.
struct ContactLaneInput {
  double nx, ny, nz;                ///< [1] unit normal, from the first body to the second
  double overlap;                   ///< [m] > 0 while touching
  double cvx, cvy, cvz;             ///< [m/s] contact velocity, second surface point minus first
  double rwx, rwy, rwz;             ///< [rad/s] w_first - w_second (rolling friction)
  double effective_radius;          ///< [m] R*
  double effective_mass;            ///< [kg] m*
  double stiffness_a, stiffness_b;  ///< the pair's normal and tangential stiffness coefficients
  double damping;                   ///< c (Hertz-Mindlin) or the linear law's D
  double damping_ratio;             ///< gamma_t / gamma_n
  double friction, rolling;         ///< mu, mu_r
  double sx, sy, sz;                ///< [m] tangential spring before this sub-step
  double rsx, rsy, rsz;             ///< [N m] rolling spring torque on the first body before this sub-step
  double rolling_inertia;           ///< [kg m^2] I_r (elastic-plastic rolling only)
};

struct ContactLaneOutput {
  double fx, fy, fz;     ///< [N] force on the first body
  double rtx, rty, rtz;  ///< [N m] rolling torque on the first body (the second gets the negative)
  double normal_force;   ///< [N] >= 0
  double sx, sy, sz;     ///< [m] tangential spring after this sub-step
  double rsx, rsy, rsz;  ///< [N m] rolling spring torque after this sub-step (zero but for elastic-plastic rolling)
  bool sliding;
};

/// Evaluates one contact over a sub-step of length dt and advances its tangential (and rolling) spring. kNone leaves
/// out rolling friction (exactly zero torque); otherwise a pair with mu_r = 0 or no relative spin gets 0 * w_rel.
template <ContactLaw kLaw, RollingTerm kRolling>
[[gnu::always_inline]] inline ContactLaneOutput contact_law_lane(const ContactLaneInput& in, double dt) {
  const double nx = in.nx, ny = in.ny, nz = in.nz;
  const double overlap = in.overlap;
  const double normal_speed = in.cvx * nx + in.cvy * ny + in.cvz * nz;  // < 0 while approaching
  const double vtx = in.cvx - normal_speed * nx, vty = in.cvy - normal_speed * ny, vtz = in.cvz - normal_speed * nz;
  double normal_stiffness, normal_damping, tangential_stiffness;
  if constexpr (kLaw == ContactLaw::kHertzMindlin) {
    const double root = std::sqrt(in.effective_radius * overlap);  // sqrt(R* d)
    normal_stiffness = in.stiffness_a * root;
    // gamma_n = c sqrt(k_n(d) m*): the scaling in which c alone sets the restitution, whatever the speed.
    normal_damping = in.damping * std::sqrt(normal_stiffness * in.effective_mass);
    tangential_stiffness = in.stiffness_b * root;
  } else {
    normal_stiffness = in.stiffness_a * in.effective_mass;
    normal_damping = in.damping * in.effective_mass;  // the linear law's D
    tangential_stiffness = in.stiffness_b * normal_stiffness;
  }
  const double tangential_damping = in.damping_ratio * normal_damping;
  const double normal_force = std::max(0.0, normal_stiffness * overlap - normal_damping * normal_speed);

  // Keep the spring in the current tangent plane, with its length (the contact frame rotates with the pair). With
  // no out-of-plane part this is an exact identity (the ratio of equal squared lengths is 1).
  double spring_x = in.sx, spring_y = in.sy, spring_z = in.sz;
  const double out_of_plane = spring_x * nx + spring_y * ny + spring_z * nz;
  const double length_squared = spring_x * spring_x + spring_y * spring_y + spring_z * spring_z;
  spring_x -= out_of_plane * nx;
  spring_y -= out_of_plane * ny;
  spring_z -= out_of_plane * nz;
  const double projected_squared = spring_x * spring_x + spring_y * spring_y + spring_z * spring_z;
  const double keep_length_any = std::sqrt(length_squared / projected_squared);
  const double keep_length = projected_squared > 0.0 ? keep_length_any : 1.0;
  spring_x = spring_x * keep_length + dt * vtx;
  spring_y = spring_y * keep_length + dt * vty;
  spring_z = spring_z * keep_length + dt * vtz;

  double ftx = tangential_stiffness * spring_x + tangential_damping * vtx;
  double fty = tangential_stiffness * spring_y + tangential_damping * vty;
  double ftz = tangential_stiffness * spring_z + tangential_damping * vtz;
  const double friction_limit = in.friction * normal_force;
  const double tangential_squared = ftx * ftx + fty * fty + ftz * ftz;
  // Coulomb: when sliding, scale the force to mu F_n and reset the spring to carry it alone.
  const bool sliding = tangential_squared > friction_limit * friction_limit;
  const double slide_scale_any = friction_limit / std::sqrt(tangential_squared);
  const double slide_scale = sliding ? slide_scale_any : 1.0;
  ftx *= slide_scale;
  fty *= slide_scale;
  ftz *= slide_scale;
  const bool stiff = tangential_stiffness > 0.0;
  const double reset_x = ftx / tangential_stiffness, reset_y = fty / tangential_stiffness,
               reset_z = ftz / tangential_stiffness;

  ContactLaneOutput out;
  out.sx = sliding ? (stiff ? reset_x : 0.0) : spring_x;
  out.sy = sliding ? (stiff ? reset_y : 0.0) : spring_y;
  out.sz = sliding ? (stiff ? reset_z : 0.0) : spring_z;
  out.fx = ftx - normal_force * nx;
  out.fy = fty - normal_force * ny;
  out.fz = ftz - normal_force * nz;
  out.normal_force = normal_force;
  out.sliding = sliding;

  // Rolling friction (the header's two laws; skipped when no material pair has mu_r). Constant torque,
  // T = -mu_r R* F_n w_rel / |w_rel|: a square root and a division per pair.
  out.rtx = out.rty = out.rtz = 0.0;
  out.rsx = out.rsy = out.rsz = 0.0;
  if constexpr (kRolling == RollingTerm::kConstantTorque) {
    const double spin = std::sqrt(in.rwx * in.rwx + in.rwy * in.rwy + in.rwz * in.rwz);
    const double rolling_scale_any = -in.rolling * in.effective_radius * normal_force / spin;
    const double rolling_scale = ((in.rolling > 0.0) & (spin > 0.0)) ? rolling_scale_any : 0.0;
    out.rtx = rolling_scale * in.rwx;
    out.rty = rolling_scale * in.rwy;
    out.rtz = rolling_scale * in.rwz;
  } else if constexpr (kRolling == RollingTerm::kElasticPlastic) {
    // The spring takes the sub-step's relative rotation, then is capped at the full mobilisation mu_r R* F_n (the
    // dashpot acts only below it: Ai et al.'s f = 0 at full mobilisation). k_n = F_n / d of the law: Hertz's
    // 4/3 E* sqrt(R* d), or the linear k_n; a pair with mu_r = 0 gets k_r = 0 and a zero cap.
    const double arm = in.rolling * in.effective_radius;
    const double rolling_stiffness = kRollingStiffnessFactor * arm * arm * normal_stiffness;
    const double step_stiffness = rolling_stiffness * dt;
    double mx = in.rsx - step_stiffness * in.rwx;
    double my = in.rsy - step_stiffness * in.rwy;
    double mz = in.rsz - step_stiffness * in.rwz;
    const double cap = arm * normal_force;
    const double spring_squared = mx * mx + my * my + mz * mz;
    const bool mobilised = spring_squared > cap * cap;
    const double cap_scale_any = cap / std::sqrt(spring_squared);
    const double cap_scale = mobilised ? cap_scale_any : 1.0;
    mx *= cap_scale;
    my *= cap_scale;
    mz *= cap_scale;
    const double damping_any = 2.0 * kRollingDampingRatio * std::sqrt(in.rolling_inertia * rolling_stiffness);
    const double rolling_damping = mobilised ? 0.0 : damping_any;
    out.rsx = mx;
    out.rsy = my;
    out.rsz = mz;
    out.rtx = mx - rolling_damping * in.rwx;
    out.rty = my - rolling_damping * in.rwy;
    out.rtz = mz - rolling_damping * in.rwz;
  }
  return out;
}

/// The lane's damping input: c for Hertz-Mindlin, the linear law's D.
inline double lane_damping(ContactLaw law, const ContactPairParameters& pair) {
  return law == ContactLaw::kHertzMindlin ? pair.damping : pair.normal_damping_coefficient;
}

/// The lane's inputs for `contact` with `pair`'s coefficients and `spring` under `law`.
inline ContactLaneInput contact_lane_input(ContactLaw law, const ContactPairParameters& pair,
                                           const ContactGeometry& contact, const Vec3& spring,
                                           const Vec3& rolling_spring) {
  ContactLaneInput in;
  in.nx = contact.normal.x();
  in.ny = contact.normal.y();
  in.nz = contact.normal.z();
  in.overlap = contact.overlap;
  in.cvx = contact.contact_velocity.x();
  in.cvy = contact.contact_velocity.y();
  in.cvz = contact.contact_velocity.z();
  in.rwx = contact.relative_angular_velocity.x();
  in.rwy = contact.relative_angular_velocity.y();
  in.rwz = contact.relative_angular_velocity.z();
  in.effective_radius = contact.effective_radius;
  in.effective_mass = contact.effective_mass;
  in.stiffness_a = pair.normal_stiffness_coefficient;
  in.stiffness_b = pair.tangential_stiffness_coefficient;
  in.damping = lane_damping(law, pair);
  in.damping_ratio = pair.tangential_damping_ratio;
  in.friction = pair.friction;
  in.rolling = pair.rolling_friction;
  in.sx = spring.x();
  in.sy = spring.y();
  in.sz = spring.z();
  in.rsx = rolling_spring.x();
  in.rsy = rolling_spring.y();
  in.rsz = rolling_spring.z();
  in.rolling_inertia = contact.rolling_inertia;
  return in;
}

/// Evaluates one contact over a sub-step of length dt and advances its tangential and rolling springs:
/// contact_law_lane on one contact (rolling friction only where the pair has mu_r, by `rolling_law`).
inline ContactResponse evaluate_contact(ContactLaw law, RollingLaw rolling_law, const ContactPairParameters& pair,
                                        const ContactGeometry& contact, Vec3& tangential_spring, Vec3& rolling_spring,
                                        double dt) {
  const ContactLaneInput in = contact_lane_input(law, pair, contact, tangential_spring, rolling_spring);
  const RollingTerm rolling = rolling_term(rolling_law, pair.rolling_friction > 0.0);
  ContactLaneOutput out;
  if (law == ContactLaw::kHertzMindlin) {
    if (rolling == RollingTerm::kNone) out = contact_law_lane<ContactLaw::kHertzMindlin, RollingTerm::kNone>(in, dt);
    else if (rolling == RollingTerm::kConstantTorque)
      out = contact_law_lane<ContactLaw::kHertzMindlin, RollingTerm::kConstantTorque>(in, dt);
    else out = contact_law_lane<ContactLaw::kHertzMindlin, RollingTerm::kElasticPlastic>(in, dt);
  } else {
    if (rolling == RollingTerm::kNone)
      out = contact_law_lane<ContactLaw::kLinearSpringDashpot, RollingTerm::kNone>(in, dt);
    else if (rolling == RollingTerm::kConstantTorque)
      out = contact_law_lane<ContactLaw::kLinearSpringDashpot, RollingTerm::kConstantTorque>(in, dt);
    else out = contact_law_lane<ContactLaw::kLinearSpringDashpot, RollingTerm::kElasticPlastic>(in, dt);
  }
  tangential_spring = Vec3(out.sx, out.sy, out.sz);
  rolling_spring = Vec3(out.rsx, out.rsy, out.rsz);
  ContactResponse response;
  response.force_on_first = Vec3(out.fx, out.fy, out.fz);
  response.rolling_torque_on_first = Vec3(out.rtx, out.rty, out.rtz);
  response.normal_force = out.normal_force;
  response.sliding = out.sliding;
  return response;
}

/// The same with the constant-torque rolling friction, which keeps no rolling spring (the calibration's impacts,
/// which have no spin, and callers without a contact history of their own).
inline ContactResponse evaluate_contact(ContactLaw law, const ContactPairParameters& pair,
                                        const ContactGeometry& contact, Vec3& tangential_spring, double dt) {
  Vec3 no_rolling_spring = Vec3::Zero();
  return evaluate_contact(law, RollingLaw::kConstantTorque, pair, contact, tangential_spring, no_rolling_spring, dt);
}

/// [kg m^2] A sphere's resistance to turning about a contact point on its surface, I + m R^2 = 7/5 m R^2, and a
/// pair's rolling inertia 1/I_r = 1/(I_i + m_i R_i^2) + 1/(I_j + m_j R_j^2); against a fixed grain (or a wall) the
/// free grain's own, as for pair_reduced_mass.
inline double sphere_rolling_inertia(double mass, double radius) { return 1.4 * mass * radius * radius; }
inline double pair_rolling_inertia(double mass_i, double radius_i, double mass_j, double radius_j, bool fixed_i,
                                   bool fixed_j) {
  const double inertia_i = sphere_rolling_inertia(mass_i, radius_i), inertia_j = sphere_rolling_inertia(mass_j, radius_j);
  if (fixed_j && !fixed_i) return inertia_i;
  if (fixed_i && !fixed_j) return inertia_j;
  return inertia_i * inertia_j / (inertia_i + inertia_j);
}

/// [kg] The reduced mass m_i m_j / (m_i + m_j) of a grain pair in the contact (and lubrication) laws; against a fixed
/// grain (GrainProperties::fixed, which does not respond, as a wall does not) the free grain's own mass, so that the
/// damping, and with it the restitution, is the one calibrated for a grain on a wall.
inline double pair_reduced_mass(double mass_i, double mass_j, bool fixed_i, bool fixed_j) {
  if (fixed_j && !fixed_i) return mass_i;
  if (fixed_i && !fixed_j) return mass_j;
  return mass_i * mass_j / (mass_i + mass_j);
}

/// A material pair's coefficients as the batched kernel reads them (ContactLaneInput's names).
struct SpherePairCoefficients {
  double stiffness_a = 0.0, stiffness_b = 0.0, damping = 0.0, damping_ratio = 0.0, friction = 0.0, rolling = 0.0;
};
inline SpherePairCoefficients sphere_pair_coefficients(ContactLaw law, const ContactPairParameters& pair) {
  return {pair.normal_stiffness_coefficient, pair.tangential_stiffness_coefficient, lane_damping(law, pair),
          pair.tangential_damping_ratio, pair.friction, pair.rolling_friction};
}

/// Touching sphere pairs in structure-of-arrays form, evaluated together by evaluate_sphere_pair_batch.
constexpr std::size_t kContactBatch = 64;
struct SpherePairBatch {
  // Inputs.
  alignas(64) double dx[kContactBatch], dy[kContactBatch], dz[kContactBatch];     // centre line, first to second
  alignas(64) double vix[kContactBatch], viy[kContactBatch], viz[kContactBatch];  // centre velocity of the first
  alignas(64) double vjx[kContactBatch], vjy[kContactBatch], vjz[kContactBatch];  // centre velocity of the second
  alignas(64) double wix[kContactBatch], wiy[kContactBatch], wiz[kContactBatch];  // angular velocity of the first
  alignas(64) double wjx[kContactBatch], wjy[kContactBatch], wjz[kContactBatch];  // angular velocity of the second
  alignas(64) double sx[kContactBatch], sy[kContactBatch], sz[kContactBatch];     // tangential spring (in old, out new)
  // Elastic-plastic rolling only (else not read or written): the rolling spring (in old, out new) and I_r.
  alignas(64) double rsx[kContactBatch], rsy[kContactBatch], rsz[kContactBatch];
  alignas(64) double rolling_inertia[kContactBatch];
  alignas(64) double ri[kContactBatch], rj[kContactBatch];
  alignas(64) double effective_mass[kContactBatch];  // pair_reduced_mass
  alignas(64) double mass_i[kContactBatch], mass_j[kContactBatch];  // the caller's, to form effective_mass
  // Pair coefficients, as in ContactLaneInput: `shared` for every pair when shared_coefficients (the arrays below are
  // then not read), else per pair in the arrays.
  bool shared_coefficients = false;
  SpherePairCoefficients shared;
  alignas(64) double stiffness_a[kContactBatch], stiffness_b[kContactBatch];
  alignas(64) double damping[kContactBatch], damping_ratio[kContactBatch];
  alignas(64) double friction[kContactBatch], rolling[kContactBatch];
  // Outputs.
  alignas(64) double overlap[kContactBatch];
  alignas(64) double fx[kContactBatch], fy[kContactBatch], fz[kContactBatch];     // force on the first
  alignas(64) double tix[kContactBatch], tiy[kContactBatch], tiz[kContactBatch];  // torque on the first
  alignas(64) double tjx[kContactBatch], tjy[kContactBatch], tjz[kContactBatch];  // torque on the second
  // The caller's bookkeeping, carried along and not read by the kernel.
  std::uint32_t pair[kContactBatch];
  std::uint32_t first[kContactBatch];
  std::uint32_t second[kContactBatch];
  std::size_t count = 0;
};

/// Evaluates the first b.count pairs of `b` (sphere i first, sphere j second, touching and at distinct centres):
/// contact geometry from the centres, contact_law_lane, and the torques about each centre (lever arms R_i n and
/// -R_j n) plus rolling friction. `rolling`: kNone where no pair has mu_r > 0 (skips that term), else the scene's law.
void evaluate_sphere_pair_batch(SpherePairBatch& b, ContactLaw law, RollingTerm rolling, double dt);

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
