// DEM contact laws against closed forms (numerics.md Sec. 4; seed 003 Sec. 2.2, seed 004 Sec. 2.2): normal impacts
// (Hertz theory, linear spring-dashpot, restitution), oblique impacts with friction (sliding and sticking), a sphere
// on an incline (rolling and sliding), energy conservation of an elastic gas, and the choice of the DEM sub-step.
//
// The grains are the seed's small spheres (5 mm, specific gravity 1.318) with the softened E = 1e8 Pa, nu = 0.3 of
// scenes/dry_bed_settle.toml. Every expectation is computed here from the physics, independently of the code
// (Hertz's formulas are written out again below); every tolerance comes from an error estimate stated beside it.
//
// Error estimates used below (N = sub-steps per collision, omega = sqrt(k/m*) the contact frequency):
//  * Velocity Verlet is second order, but the contact force has a kink where the bodies touch and part. A contact
//    begins at a fraction s of a sub-step; Verlet's trapezoid credits dt/2 F(d_1) to that sub-step while the exact
//    impulse is the integral of the linear rise, so the entry impulse is off by k v dt^2 s(1-s)/2 <= m* v (omega
//    dt)^2 / 8, and the exit likewise with the opposite sign: an elastic collision changes the normal relative speed
//    by at most (omega dt)^2/8 of itself, its energy by (omega dt)^2/4 (the Hertz force, whose kink is d^{3/2},
//    does better than the linear one).
//  * Verlet's harmonic frequency is omega (1 + (omega dt)^2/24 + ...), so durations are off by (omega dt)^2/24.
//  * A dashpot makes both errors first order: its force jumps at first touch (linear law: by gamma v, so the entry
//    impulse is off by gamma v dt (s - 1/2)), and it sees the half-step velocity v(t - dt/2), i.e.
//    -gamma v(t) + gamma (dt/2) a(t): the mass is lessened by gamma dt/2 and ln e grows by the fraction
//    gamma dt / (4 m* (1 - zeta^2)), zeta = c/2 the damping ratio. Hence |delta e| / e <= gamma dt / (2 m*) (1 +
//    |ln e| / (2 (1 - zeta^2))) + (omega dt)^2: about 1.1/N for e = 0.5 with the linear law.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "engine/run/simulation.hpp"
#include "systems/physics/dem/contact_law.hpp"
#include "tests/support/test_support.hpp"
#include "tests/support/scene_builder.hpp"

using namespace riffle;
using riffle::test::SceneBuilder;

namespace {

constexpr double kRadius = 2.5e-3;     // [m] the seed's small grain (5 mm)
constexpr double kDensity = 1318.0;    // [kg/m^3]
constexpr double kYoung = 1.0e8;       // [Pa]
constexpr double kPoisson = 0.3;       // [1]
const double kMass = kDensity * 4.0 / 3.0 * std::numbers::pi * kRadius * kRadius * kRadius;  // [kg] 8.626e-5
// Two bodies of the same material: 1/E* = 2 (1 - nu^2) / E, 1/G* = 2 (2 - nu) / G, G = E / (2 (1 + nu)).
const double kEffectiveYoung = kYoung / (2.0 * (1.0 - kPoisson * kPoisson));                    // 5.4945e7 Pa
const double kEffectiveShear = kYoung / (2.0 * (1.0 + kPoisson)) / (2.0 * (2.0 - kPoisson));    // 1.1312e7 Pa

/// Hertz (Timoshenko & Goodier): m* v^2 / 2 = (8/15) E* sqrt(R*) d_max^{5/2}, and the duration is
/// 2 (d_max / v) integral_0^1 dx / sqrt(1 - x^{5/2}) = (4/5) B(2/5, 1/2) d_max / v.
double hertz_overlap(double effective_radius, double effective_mass, double speed) {
  return std::pow(15.0 * effective_mass * speed * speed / (16.0 * kEffectiveYoung * std::sqrt(effective_radius)), 0.4);
}
double hertz_duration(double effective_radius, double effective_mass, double speed) {
  const double beta = std::tgamma(0.4) * std::tgamma(0.5) / std::tgamma(0.9);  // B(2/5, 1/2)
  return 0.8 * beta * hertz_overlap(effective_radius, effective_mass, speed) / speed;
}

struct Body {
  Vec3 position;
  Vec3 velocity = Vec3::Zero();
  Vec3 angular_velocity = Vec3::Zero();
  bool fixed = false;  ///< [solids.spheres] fixed: held for the whole run (a rough floor's grain)
};

struct SceneSpec {
  std::string law = "hertz_mindlin";
  double restitution = 1.0;
  double friction = 0.0;
  double rolling_friction = 0.0;
  std::string rolling_law = "";    ///< [contact] rolling_law; empty: the default
  double collision_time = 2.0e-4;  ///< [s] linear law only
  double young = kYoung;
  double max_impact_speed = 1.0;   ///< [m/s] the design impact speed of the sub-step estimate (the default)
  double dt = 1.0e-3;
  long substeps = 1;               ///< 0: leave run.solid_substeps out (the reader chooses)
  Vec3 gravity = Vec3::Zero();
  Vec3 tank = Vec3::Constant(0.02);
  std::vector<Body> bodies{};  ///< ids 0, 1, ... in this order
};

std::string scene_text(const SceneSpec& spec) {
  SceneBuilder scene;
  scene.run({.end_time = 10.0, .dt = spec.dt});
  if (spec.substeps > 0) scene.set("solid_substeps", spec.substeps);
  scene.set("gravity", test::triple(spec.gravity))
      .material("grain", {.density = kDensity, .young_modulus = spec.young, .poisson_ratio = kPoisson})
      .tank({.size = test::triple(spec.tank), .wall_material = "grain"})
      .contact({.law = spec.law, .restitution = spec.restitution, .friction = spec.friction,
                .rolling_friction = spec.rolling_friction, .max_impact_speed = spec.max_impact_speed});
  if (spec.law == "linear_spring_dashpot") scene.set("collision_time", spec.collision_time);
  if (!spec.rolling_law.empty()) scene.set("rolling_law", spec.rolling_law);
  scene.solids();
  for (const Body& body : spec.bodies) {
    scene.sphere({.position = test::triple(body.position), .radius = kRadius, .material = "grain",
                  .velocity = test::triple(body.velocity), .angular_velocity = test::triple(body.angular_velocity)});
    if (body.fixed) scene.set("fixed", true);
  }
  return scene.toml();
}

std::unique_ptr<Simulation> simulate(const SceneSpec& spec) {
  return Simulation::from_model(parse_scene(scene_text(spec), "dem_contact.toml"));
}

/// The largest overlap of the contacts evaluated in the last sub-step (0 when none touches).
double largest_overlap(const Contacts& contacts) {
  double largest = 0.0;
  for (double overlap : contacts.pair_overlap) largest = std::max(largest, overlap);
  for (double overlap : contacts.wall_pair_overlap) largest = std::max(largest, overlap);
  return largest;
}

/// What a sphere hits: the floor, a sphere coming at it, or a fixed sphere (a rough floor's grain: it does not
/// respond, so the pair's reduced mass is the moving sphere's own, as on a wall).
enum class Target { kFloor, kSphere, kFixedSphere };
std::string name_of(Target target) {
  return target == Target::kFloor ? "sphere on the floor" : target == Target::kSphere ? "two spheres" : "sphere on a fixed sphere";
}
/// R* and m* of the collision: a wall is a plane that does not move, R* = R, m* = m; two equal spheres R* = R/2,
/// m* = m/2; a sphere on a fixed one R* = R/2, m* = m.
double effective_radius_of(Target target) { return target == Target::kFloor ? kRadius : 0.5 * kRadius; }
double effective_mass_of(Target target) { return target == Target::kSphere ? 0.5 * kMass : kMass; }

using test::slot_of;

/// The signed overlap of the one contact of a collision scene (the floor is z = 0), negative while apart.
double signed_overlap(const Solids& solids, Target target) {
  return target == Target::kFloor ? kRadius - solids.position[0][2]
                                  : 2.0 * kRadius - (solids.position[1] - solids.position[0]).norm();
}

struct CollisionImpact {
  double duration = 0.0;     ///< [s] time with positive overlap (zero crossings of the sampled overlap)
  double max_overlap = 0.0;  ///< [m] largest sampled overlap
  Solids final_state;        ///< the grains once apart
  bool finished = false;
};

/// Runs `spec` (solid_substeps = 1, so every sub-step is sampled) until its one contact has come and gone.
CollisionImpact run_collision(const SceneSpec& spec, Target target) {
  auto simulation = simulate(spec);
  const World& world = simulation->world();
  CollisionImpact impact;
  double previous = signed_overlap(*world.solids, target), entry = 0.0, mismatch = 0.0;
  bool touched = false;
  for (int step = 1; step < 100000 && !impact.finished; ++step) {
    simulation->step();
    const double overlap = signed_overlap(*world.solids, target);
    // The contact evaluated the same overlap at these positions (the closing kick moves no grain).
    mismatch = std::max(mismatch, std::abs(largest_overlap(*world.contacts) - std::max(overlap, 0.0)));
    // Between samples a grain drifts in a straight line, so the crossing is interpolated linearly.
    const double crossing = (step - 1) * spec.dt + spec.dt * previous / (previous - overlap);
    if (!touched && overlap > 0.0) {
      touched = true;
      entry = crossing;
    }
    if (touched) impact.max_overlap = std::max(impact.max_overlap, overlap);
    if (touched && overlap <= 0.0) {
      // The force is zero from here on (gravity is off): the velocities are final.
      impact.duration = crossing - entry;
      impact.final_state = *world.solids;
      impact.finished = true;
    }
    previous = overlap;
  }
  CHECK(mismatch < 1e-15);  // rounding of centimetre coordinates is ~1e-18 m
  return impact;
}

/// A head-on impact at relative `speed`, gravity off. Contact begins at the fraction `phase` of a sub-step (free
/// flight is exact), so that different runs exercise different phases. Returns the impact and e = v_after/v_before.
std::pair<CollisionImpact, double> normal_impact(const std::string& law, Target target, double speed, double restitution,
                                        double dt, double phase) {
  SceneSpec spec;
  spec.law = law;
  spec.restitution = restitution;
  spec.dt = dt;
  spec.tank = Vec3::Constant(0.03);
  const double gap = (3.0 + phase) * speed * dt;
  const Vec3 centre = 0.5 * spec.tank;
  if (target == Target::kFloor) {
    spec.bodies.push_back({Vec3(centre[0], centre[1], kRadius + gap), Vec3(0.0, 0.0, -speed)});
  } else if (target == Target::kSphere) {
    spec.bodies.push_back({centre - Vec3(kRadius + 0.5 * gap, 0.0, 0.0), Vec3(0.5 * speed, 0.0, 0.0)});
    spec.bodies.push_back({centre + Vec3(kRadius + 0.5 * gap, 0.0, 0.0), Vec3(-0.5 * speed, 0.0, 0.0)});
  } else {
    spec.bodies.push_back({centre - Vec3(2.0 * kRadius + gap, 0.0, 0.0), Vec3(speed, 0.0, 0.0)});
    spec.bodies.push_back({centre, Vec3::Zero(), Vec3::Zero(), true});
  }
  CollisionImpact impact = run_collision(spec, target);
  double restitution_achieved = 0.0;
  if (impact.finished) {
    const Solids& solids = impact.final_state;
    restitution_achieved = target == Target::kFloor
                               ? solids.velocity[0][2] / speed
                               : (solids.velocity[slot_of(solids, 1)][0] - solids.velocity[slot_of(solids, 0)][0]) / speed;
  }
  return {std::move(impact), restitution_achieved};
}

/// The time scales of one collision of a law at `speed` (relative, normal): the duration t_c (elastic Hertz, or the
/// linear law's collision time), the stiffest local frequency omega_max (sqrt(k/m*) for the linear law, sqrt(dF/dd /
/// m*) at the elastic d_max for Hertz, dF/dd = 2 E* sqrt(R* d)), and gamma_max / m* = c sqrt(k/m*), k = F/d at d_max.
struct CollisionScales {
  double duration = 0.0, overlap = 0.0, omega_max = 0.0, damping = 0.0, damping_rate = 0.0;
};
CollisionScales collision_scales(const std::string& law, double effective_radius, double effective_mass, double speed,
                                 double restitution, double collision_time) {
  CollisionScales scales;
  const bool hertz = law == "hertz_mindlin";
  double secant;  // F/d at d_max
  if (hertz) {
    scales.overlap = hertz_overlap(effective_radius, effective_mass, speed);
    scales.duration = hertz_duration(effective_radius, effective_mass, speed);
    secant = 4.0 / 3.0 * kEffectiveYoung * std::sqrt(effective_radius * scales.overlap);
    scales.omega_max = std::sqrt(1.5 * secant / effective_mass);
  } else {
    // k = m* (pi^2 + ln^2 e) / t_c^2; with e = 1 half a period of sqrt(k/m*) is t_c and d_max = v / omega.
    const double log_e = std::log(restitution);
    secant = effective_mass * (std::numbers::pi * std::numbers::pi + log_e * log_e) / (collision_time * collision_time);
    scales.duration = collision_time;
    scales.omega_max = std::sqrt(secant / effective_mass);
    scales.overlap = speed / scales.omega_max;
  }
  scales.damping = calibrate_damping(hertz ? ContactLaw::kHertzMindlin : ContactLaw::kLinearSpringDashpot,
                                     restitution);
  scales.damping_rate = scales.damping * std::sqrt(secant / effective_mass);
  return scales;
}

/// The first-order bound on |delta e| / e of the top of the file for a collision resolved by sub-steps of dt.
double restitution_tolerance(const CollisionScales& scales, double restitution, double dt) {
  const double zeta = 0.5 * scales.damping;  // gamma = c sqrt(k m*): the damping ratio against F/d
  const double omega_dt = scales.omega_max * dt;
  return 0.5 * scales.damping_rate * dt * (1.0 + std::abs(std::log(restitution)) / (2.0 * (1.0 - zeta * zeta))) +
         omega_dt * omega_dt;
}

}  // namespace

TEST_CASE("elastic normal impacts last the Hertz (or the linear law's) contact time and reach its overlap") {
  // e = 1, no damping, N = 100 sub-steps per collision. From the top of the file: the duration is off by
  // (omega dt)^2/24, the speed (hence d_max) by (omega dt)^2/8, the sampled maximum misses the true one by at most
  // |d''| dt^2 / 8 = (omega dt)^2/8 of it, and the interpolated crossings are exact for the straight drift between
  // samples. (omega_max dt)^2 / 2 covers each sum; (omega_max dt)^2 / 8 bounds the rebound speed's error.
  const double N = 100.0, collision_time = 2.0e-4;  // SceneSpec's default for the linear law
  for (const std::string law : {"hertz_mindlin", "linear_spring_dashpot"})
    for (Target target : {Target::kFloor, Target::kSphere, Target::kFixedSphere}) {
      const double effective_radius = effective_radius_of(target), effective_mass = effective_mass_of(target);
      int run = 0;
      for (double speed : {0.05, 0.2, 1.0}) {
        const CollisionScales scales =
            collision_scales(law, effective_radius, effective_mass, speed, 1.0, collision_time);
        const double dt = scales.duration / N;
        const auto [impact, restitution] = normal_impact(law, target, speed, 1.0, dt, 0.15 + 0.35 * run++);
        INFO(law << ", " << name_of(target) << ", v = " << speed << " m/s");
        REQUIRE(impact.finished);
        const double omega_dt2 = (scales.omega_max * dt) * (scales.omega_max * dt);
        CHECK(std::abs(impact.duration / scales.duration - 1.0) < 0.5 * omega_dt2);
        CHECK(std::abs(impact.max_overlap / scales.overlap - 1.0) < 0.5 * omega_dt2);
        CHECK(std::abs(restitution - 1.0) < 0.125 * omega_dt2);
      }
    }
}

TEST_CASE("damped normal impacts rebound at the requested restitution, whatever the speed") {
  // e = 0.5, N = 200 sub-steps per collision. The calibrated c makes e independent of the speed for both laws (the
  // scaled equations of contact_law.hpp contain c alone), so every speed must give 0.5, to the first-order bound of
  // the top of the file (0.6 % for the linear law, 0.7 % for Hertz whose bound takes gamma at d_max).
  const double N = 200.0, restitution = 0.5, collision_time = 2.0e-4;
  for (const std::string law : {"hertz_mindlin", "linear_spring_dashpot"})
    for (Target target : {Target::kFloor, Target::kSphere, Target::kFixedSphere}) {
      const double effective_radius = effective_radius_of(target), effective_mass = effective_mass_of(target);
      int run = 0;
      for (double speed : {0.05, 0.2, 1.0}) {
        const CollisionScales scales =
            collision_scales(law, effective_radius, effective_mass, speed, restitution, collision_time);
        const double dt = scales.duration / N;
        const double tolerance = restitution_tolerance(scales, restitution, dt);
        const auto [impact, achieved] = normal_impact(law, target, speed, restitution, dt, 0.1 + 0.4 * run++);
        INFO(law << ", " << name_of(target) << ", v = " << speed << " m/s, tolerance " << tolerance);
        REQUIRE(impact.finished);
        CHECK(std::abs(achieved / restitution - 1.0) < tolerance);
      }
    }
}

TEST_CASE("an oblique impact in gross sliding: dv_t = -mu (1 + e) v_n and dw = (5/2) mu (1 + e) v_n / R") {
  // A sphere moving along +x hits the floor (normal +z) at v_n = 0.2 m/s with v_t = 1 m/s and no spin, mu = 0.3,
  // e = 0.5. Friction at the contact point (0, 0, -R) from the centre is -mu F_n x, so m dv_x = -mu F_n dt and
  // I dw_y = -R (-mu F_n) dt (torque r x F): over the contact dv_x = -mu dv_z and dw_y = (5/2) mu dv_z / R with
  // I = (2/5) m R^2, dv_z = (1 + e) v_n. The slip v_x - R w_y drops by (7/2) mu dv_z = 0.315 m/s < 1 m/s, so the
  // sphere slides throughout. Every sub-step applies |F_t| = mu F_n in both kicks, so dv_x = -mu dv_z and
  // R dw_y = (5/2) mu dv_z hold to rounding (sums of ~300 terms: 1e-12 absolute); dv_z itself carries the
  // restitution error bound of the top of the file.
  const double v_n = 0.2, v_t = 1.0, friction = 0.3, restitution = 0.5, N = 200.0;
  for (const std::string law : {"hertz_mindlin", "linear_spring_dashpot"}) {
    SceneSpec spec{.law = law, .restitution = restitution, .friction = friction, .tank = Vec3(0.05, 0.02, 0.02)};
    const CollisionScales scales = collision_scales(law, kRadius, kMass, v_n, restitution, spec.collision_time);
    spec.dt = scales.duration / N;
    const double gap = 3.5 * v_n * spec.dt;
    spec.bodies.push_back({Vec3(0.01, 0.01, kRadius + gap), Vec3(v_t, 0.0, -v_n)});
    const CollisionImpact impact = run_collision(spec, Target::kFloor);
    INFO(law);
    REQUIRE(impact.finished);
    const Vec3& v = impact.final_state.velocity[0];
    const Vec3& w = impact.final_state.angular_velocity[0];
    const double dv_z = v[2] + v_n, dv_x = v[0] - v_t, dw_y = w[1];
    CHECK(std::abs(dv_x + friction * dv_z) < 1e-12);
    CHECK(std::abs(kRadius * dw_y - 2.5 * friction * dv_z) < 1e-12);
    const double tolerance = restitution * v_n * restitution_tolerance(scales, restitution, spec.dt);
    CHECK(std::abs(dv_z - (1.0 + restitution) * v_n) < tolerance);
    CHECK(std::abs(dv_x + friction * (1.0 + restitution) * v_n) < friction * tolerance);
    CHECK(std::abs(dw_y - 2.5 * friction * (1.0 + restitution) * v_n / kRadius) < 2.5 * friction * tolerance / kRadius);
    CHECK(v[0] - kRadius * w[1] > 0.0);  // still sliding forward: the gross-sliding regime held
    CHECK(std::abs(v[1]) + std::abs(w[0]) + std::abs(w[2]) == 0.0);  // nothing out of the plane of motion
  }
}

TEST_CASE("two spinning spheres in gross sliding: friction impulse mu P_n, equal spin-down, momentum kept") {
  // Two equal spheres meet head-on along x (relative normal speed v_n = 0.2 m/s, e = 0.5, mu = 0.3), both spinning
  // at w0 = 200 rad/s about z: their contact points move at +R w0 y (first) and -R w0 y (second), a slip of
  // 2 R w0 = 1 m/s. Normal impulse P_n = m* (1 + e) v_n with m* = m/2; friction on the first is -mu P_n y (along the
  // second's slip) at arm R x, on the second +mu P_n y at arm -R x: both torques are -R mu P_n z. So
  //   dv_y = -/+ mu (1 + e) v_n / 2,   dw_z = -(5/2) mu (1 + e) v_n / (2 R) for both;
  // the slip falls by (7/2) mu (1 + e) v_n = 0.315 m/s < 1 m/s: sliding throughout. Tolerances: dP_n carries the
  // restitution bound of the top of the file; the friction kicks drift the centres apart along y by at most
  // mu (1 + e) v_n t_c, turning the normal by theta <= mu (1 + e) v_n t_c / (2 R) and moving up to theta P_n between
  // the x and y impulses, i.e. theta / mu of the friction impulse. Equal radii make the two torques identical, and
  // the pair forces are opposite: dw_first = dw_second and total momentum are exact to rounding.
  const double v_n = 0.2, spin = 200.0, friction = 0.3, restitution = 0.5, N = 200.0;
  for (const std::string law : {"hertz_mindlin", "linear_spring_dashpot"}) {
    SceneSpec spec{.law = law, .restitution = restitution, .friction = friction, .tank = Vec3::Constant(0.03)};
    const CollisionScales scales = collision_scales(law, 0.5 * kRadius, 0.5 * kMass, v_n, restitution, spec.collision_time);
    spec.dt = scales.duration / N;
    const double gap = 3.7 * v_n * spec.dt;
    const Vec3 centre = 0.5 * spec.tank, spin_z(0.0, 0.0, spin);
    spec.bodies.push_back({centre - Vec3(kRadius + 0.5 * gap, 0.0, 0.0), Vec3(0.5 * v_n, 0.0, 0.0), spin_z});
    spec.bodies.push_back({centre + Vec3(kRadius + 0.5 * gap, 0.0, 0.0), Vec3(-0.5 * v_n, 0.0, 0.0), spin_z});
    const CollisionImpact impact = run_collision(spec, Target::kSphere);
    INFO(law);
    REQUIRE(impact.finished);
    const Solids& solids = impact.final_state;
    const std::size_t first = slot_of(solids, 0), second = slot_of(solids, 1);
    const Vec3 dv_first = solids.velocity[first] - Vec3(0.5 * v_n, 0.0, 0.0);
    const Vec3 dv_second = solids.velocity[second] - Vec3(-0.5 * v_n, 0.0, 0.0);
    const Vec3 dw_first = solids.angular_velocity[first] - spin_z;
    const Vec3 dw_second = solids.angular_velocity[second] - spin_z;
    CHECK((dv_first + dv_second).norm() < 1e-13);  // ~400 kicks of 0.1 m/s, rounded at 1e-17 each
    CHECK((dw_first - dw_second).norm() < 1e-12 * dw_first.norm());
    const double theta = friction * (1.0 + restitution) * v_n * scales.duration / (2.0 * kRadius);
    const double impulse_tolerance = restitution * restitution_tolerance(scales, restitution, spec.dt) / (1.0 + restitution);
    const double tolerance = impulse_tolerance + theta / friction;  // relative, on the friction impulse
    const double dv_y = friction * (1.0 + restitution) * v_n / 2.0;
    CHECK(std::abs(dv_first[1] + dv_y) < tolerance * dv_y);
    CHECK(std::abs(dw_first[2] + 2.5 * dv_y / kRadius) < tolerance * 2.5 * dv_y / kRadius);
    // Along x: the normal impulse, less (1 - cos theta) of it, plus up to theta of the friction impulse.
    const double dv_x = 0.5 * (1.0 + restitution) * v_n;
    CHECK(std::abs(dv_first[0] + dv_x) < (impulse_tolerance + 0.5 * theta * theta) * dv_x + theta * dv_y);
  }
}

TEST_CASE("an oblique elastic impact that sticks reverses the contact-point slip (linear law, k_t = 2/7 k_n)") {
  // Linear law, e = 1 (no damping, normal or tangential), mu = 10. Contact-point slip along x: c = v_x - R w_y.
  // With the spring xi (c = xi'), F_t = -k_t xi acts on the sphere at (0, 0, -R): m v_x' = F_t, I w_y' = -R F_t, so
  // c' = F_t (1/m + R^2/I) = (7/2) F_t / m and xi'' = -(7/2)(k_t/m) xi = -(k_n/m) xi for k_t = 2/7 k_n: the slip
  // oscillates at the normal frequency and the contact lasts exactly half its period. From xi(0) = 0, c(0) = c0:
  // c = c0 cos(omega t), so at separation c = -c0: dc = -2 c0 = dv_x - R dw_y with m dv_x = -(I/R) dw_y, giving
  // dv_x = -(4/7) c0 and dw_y = (10/7) c0 / R. No slip requires |F_t| <= mu F_n: (2/7) c0 / v_n = 0.21 << mu.
  // Error: the entry and exit impulse errors of each spring are (omega dt)^2/8 of the speeds; the spring's head start
  // (it is incremented by c dt from the first overlapping sub-step, whatever the phase) adds delta cos(omega t) to
  // xi, whose velocity -delta omega sin(omega t) vanishes at the half period; the frequency error of Verlet enters
  // c(T) = c0 cos(pi (1 + eps)) only squared. (omega dt)^2 c0 bounds the sum.
  const double v_n = 0.2, v_t = 0.1, spin = -20.0, N = 100.0;
  const double c0 = v_t - kRadius * spin;  // 0.15 m/s: the contact point slides forward
  SceneSpec spec;
  spec.law = "linear_spring_dashpot";
  spec.restitution = 1.0;
  spec.friction = 10.0;
  spec.tank = Vec3(0.05, 0.02, 0.02);
  spec.dt = spec.collision_time / N;
  const double gap = 3.3 * v_n * spec.dt;
  spec.bodies.push_back({Vec3(0.01, 0.01, kRadius + gap), Vec3(v_t, 0.0, -v_n), Vec3(0.0, spin, 0.0)});
  const CollisionImpact impact = run_collision(spec, Target::kFloor);
  REQUIRE(impact.finished);
  const Vec3& v = impact.final_state.velocity[0];
  const Vec3& w = impact.final_state.angular_velocity[0];
  const double omega_dt = std::numbers::pi / N;
  const double tolerance = omega_dt * omega_dt * c0;
  CHECK(std::abs(v[0] - (v_t - 4.0 / 7.0 * c0)) < tolerance);
  CHECK(std::abs(kRadius * w[1] - (kRadius * spin + 10.0 / 7.0 * c0)) < tolerance);
  CHECK(std::abs((v[0] - kRadius * w[1]) + c0) < 2.0 * tolerance);  // the slip reversed
  CHECK(std::abs(v[2] - v_n) < 0.125 * omega_dt * omega_dt * v_n);  // elastic normal rebound
}

TEST_CASE("a sphere on an incline rolls without slip below the friction limit and slides above it") {
  // The floor stays horizontal and gravity is tilted: g = 9.81 (sin th, 0, -cos th), th = 30 deg. The sphere starts
  // at rest, pressed to its static overlap (F_n = m g cos th), and is followed for T = 0.1 s with the sub-step the
  // scene reader chooses. Contact at (0, 0, -R): m dv_x = (m g sin th + F_x) dt and I dw_y = -R F_x dt, exactly in
  // every Verlet kick, so with the slip c = v_x - R w_y: v_x = (5/7) g sin th t + (2/7) c (I = 2/5 m R^2).
  //  * Rolling (mu = 0.5 > (4/7) tan th, so even the start-up overshoot of F_t to twice its mean cannot slip): the
  //    slip is the velocity of the spring xi, a damped oscillator c' = g sin th - (7/2)(k_t xi + gamma_t c)/m driven
  //    from rest, |c| <= g sin th / omega_d with omega_t^2 = (7/2) k_t / m and xi <= 2 g sin th / omega_t^2. Twice
  //    that bounds the damped frequency's 1/sqrt(1 - zeta^2) and the start-up half kick (made before any contact
  //    force exists): |v_x - a t| <= (4/7) g sin th / omega_t, |R w_y - v_x| <= 2 g sin th / omega_t, with
  //    a = (5/7) g sin th, and the position is off by (2/7) xi.
  //  * Sliding (mu = 0.1 < (2/7) tan th): F_x = -mu F_n once the spring has reached the Coulomb limit, and the
  //    z-momentum gives integral F_n dt = m (g cos th t + v_z). The spring needs less than half a slip period,
  //    pi / omega_t, to load, and v_z stays below the start-up kick g cos th dt; so a = g (sin th - mu cos th) and
  //    dw/dt = (5/2) mu g cos th / R, to within mu g cos th (pi / omega_t + dt) on v_x and (5/2)/R times it on w_y.
  const double g = 9.81, theta = std::numbers::pi / 6.0, T = 0.1, restitution = 0.5;
  const double sin_t = std::sin(theta), cos_t = std::cos(theta);
  for (const std::string law : {"hertz_mindlin", "linear_spring_dashpot"})
    for (const bool rolling : {true, false}) {
      SceneSpec spec;
      spec.law = law;
      spec.restitution = restitution;
      spec.friction = rolling ? 0.5 : 0.1;
      spec.dt = 1.0e-3;
      spec.substeps = 0;  // the reader's choice
      spec.gravity = g * Vec3(sin_t, 0.0, -cos_t);
      spec.tank = Vec3(0.05, 0.02, 0.02);
      const Vec3 start(0.01, 0.01, kRadius);
      spec.bodies.push_back({start});
      // Static overlap and tangential stiffness there: Hertz F_n = 4/3 E* sqrt(R) d^{3/2}, k_t = 8 G* sqrt(R d);
      // linear F_n = k_n d, k_n = m (pi^2 + ln^2 e) / t_c^2, k_t = 2/7 k_n.
      const double weight = kMass * g * cos_t;
      double overlap, tangential_stiffness;
      if (law == "hertz_mindlin") {
        overlap = std::pow(3.0 * weight / (4.0 * kEffectiveYoung * std::sqrt(kRadius)), 2.0 / 3.0);
        tangential_stiffness = 8.0 * kEffectiveShear * std::sqrt(kRadius * overlap);
      } else {
        const double log_e = std::log(restitution);
        const double stiffness =
            kMass * (std::numbers::pi * std::numbers::pi + log_e * log_e) / (spec.collision_time * spec.collision_time);
        overlap = weight / stiffness;
        tangential_stiffness = 2.0 / 7.0 * stiffness;
      }
      const double omega_t = std::sqrt(3.5 * tangential_stiffness / kMass);
      auto simulation = simulate(spec);
      // The reader refuses a sphere that overlaps a wall; press it in by hand.
      simulation->world().solids->position[0][2] = kRadius - overlap;
      const int steps = static_cast<int>(std::lround(T / spec.dt));
      for (int step = 0; step < steps; ++step) simulation->step();
      REQUIRE(simulation->world().step_status.ok());
      const Solids& solids = *simulation->world().solids;
      const Vec3& x = solids.position[0];
      const Vec3& v = solids.velocity[0];
      const Vec3& w = solids.angular_velocity[0];
      const double sub_dt = simulation->model().solid_dt();
      INFO(law << (rolling ? ", rolling" : ", sliding") << ", " << simulation->model().solid_substeps << " sub-steps");
      if (rolling) {
        const double a = 5.0 / 7.0 * g * sin_t;
        const double slip_bound = 2.0 * g * sin_t / omega_t;
        CHECK(std::abs(v[0] - a * T) < 2.0 / 7.0 * slip_bound);
        CHECK(std::abs(kRadius * w[1] - v[0]) < slip_bound);
        CHECK(std::abs(x[0] - start[0] - 0.5 * a * T * T) < 2.0 / 7.0 * 2.0 * slip_bound / omega_t + 1e-12);
      } else {
        const double a = g * (sin_t - spec.friction * cos_t);
        const double alpha = 2.5 * spec.friction * g * cos_t / kRadius;  // dw/dt
        const double bound = spec.friction * g * cos_t * (std::numbers::pi / omega_t + sub_dt);
        CHECK(std::abs(v[0] - a * T) < bound);
        CHECK(std::abs(w[1] - alpha * T) < 2.5 / kRadius * bound);
        CHECK(std::abs(x[0] - start[0] - 0.5 * a * T * T) < bound * T);
        CHECK(v[0] - kRadius * w[1] > 0.0);  // still sliding
      }
    }
}

namespace {

/// A sphere (the seed's small grain, E = 1e7 Pa, mu = 0.5) released at rest on the floor, pressed to its static
/// Hertz overlap, under gravity tilted by atan(tan_theta), for T = 1 s at 1 ms steps of `substeps` sub-steps: its
/// velocity at T, its mean speed over the second half, the sub-step, the static overlap and x(T) - x(T/2).
struct InclineRoll {
  double velocity, creep_speed, substep, overlap;
};
constexpr double kInclineTime = 1.0, kInclineYoung = 1.0e7, kInclineRolling = 0.1;
InclineRoll roll_on_incline(double tan_theta, long substeps, const std::string& rolling_law) {
  const double g = 9.81, theta = std::atan(tan_theta);
  SceneSpec spec;
  spec.young = kInclineYoung;
  spec.restitution = 0.5;
  spec.friction = 0.5;
  spec.rolling_friction = kInclineRolling;
  spec.rolling_law = rolling_law;
  spec.max_impact_speed = 0.5;  // the seed scenes' design speed: 40 sub-steps a millisecond
  spec.dt = 1.0e-3;
  spec.substeps = substeps;
  spec.gravity = g * Vec3(std::sin(theta), 0.0, -std::cos(theta));
  spec.tank = Vec3(0.2, 0.02, 0.02);
  spec.bodies.push_back({Vec3(0.01, 0.01, kRadius)});
  auto simulation = simulate(spec);
  // The reader refuses a sphere that overlaps a wall; press it in by hand to its static Hertz overlap.
  const double effective_young = kInclineYoung / (2.0 * (1.0 - kPoisson * kPoisson));
  const double overlap =
      std::pow(3.0 * kMass * g * std::cos(theta) / (4.0 * effective_young * std::sqrt(kRadius)), 2.0 / 3.0);
  simulation->world().solids->position[0][2] = kRadius - overlap;
  const int steps = static_cast<int>(std::lround(kInclineTime / spec.dt));
  double x_half = 0.0;
  for (int step = 0; step < steps; ++step) {
    if (step == steps / 2) x_half = simulation->world().solids->position[0][0];
    simulation->step();
  }
  REQUIRE(simulation->world().step_status.ok());
  const Solids& solids = *simulation->world().solids;
  return {solids.velocity[0][0], (solids.position[0][0] - x_half) / (0.5 * kInclineTime),
          simulation->model().solid_dt(), overlap};
}

/// Above the rolling angle both rolling laws give the torque mu_r R F_n against the spin once rolling, so the sphere
/// rolls with a = (5/7) g (sin th - mu_r cos th), to within the incline test's slip bound with the rolling torque
/// added to the drive, |v - a t| <= (4/7) g (sin th + mu_r cos th) / omega_t, plus one sub-step's kick
/// (5/2) g (sin th + mu_r cos th) dt. The elastic-plastic spring reaches the cap only after the sphere has turned by
/// th_c = mu_r R F_n / k_r = d / (2.25 mu_r R); until then its torque is below the cap, a deficit of at most the
/// cap's impulse over that time. The angular acceleration about the contact point is at least a / R all along, so
/// the time is at most sqrt(2 th_c R / a), and the sphere may be faster by R mu_r R F_n sqrt(2 th_c R / a) / I_c,
/// I_c = 7/5 m R^2. Checked at the scenes' 40 sub-steps a millisecond and at 80 (the bound's sub-step term halves).
void check_rolls_above_the_rolling_angle(const std::string& rolling_law) {
  const double g = 9.81, mu_r = kInclineRolling, tan_theta = 1.5 * mu_r, theta = std::atan(tan_theta);
  for (const long substeps : {40L, 80L}) {
    const InclineRoll result = roll_on_incline(tan_theta, substeps, rolling_law);
    const double a = 5.0 / 7.0 * g * (std::sin(theta) - mu_r * std::cos(theta));
    const double effective_shear = kInclineYoung / (2.0 * (1.0 + kPoisson)) / (2.0 * (2.0 - kPoisson));
    const double omega_t = std::sqrt(3.5 * 8.0 * effective_shear * std::sqrt(kRadius * result.overlap) / kMass);
    const double drive = g * (std::sin(theta) + mu_r * std::cos(theta));
    double bound = 4.0 / 7.0 * drive / omega_t + 2.5 * drive * result.substep;
    if (rolling_law == "elastic_plastic") {
      const double turn_to_cap = result.overlap / (2.25 * mu_r * kRadius);
      bound += mu_r * g * std::cos(theta) / 1.4 * std::sqrt(2.0 * turn_to_cap * kRadius / a);
    }
    INFO(rolling_law << ", " << substeps << " sub-steps: v " << result.velocity << " m/s against a T = "
                     << a * kInclineTime << ", bound " << bound);
    CHECK(std::abs(result.velocity - a * kInclineTime) <= bound);
  }
}

}  // namespace

TEST_CASE("constant-torque rolling friction rolls a sphere down an incline above the rolling angle and holds it below, up to a creep of first order in the sub-step") {
  // The constant-torque rolling friction (seed 003 Eq. 20; Ai et al. 2011, Powder Technol. 206, 269, their model A),
  // T = -mu_r R* F_n w_rel / |w_rel|, on a sphere on the floor (R* = R) under gravity tilted by th, mu = 0.5 so that
  // the contact sticks. About the contact point the friction force has no arm, so the angular momentum
  // L = m R v + I w = (7/5) m R^2 w (rolling without slip) changes only by the weight's torque m g R sin th and the
  // rolling torque, whose largest value is mu_r R m g cos th. Above the rolling angle (tan th > mu_r): see
  // check_rolls_above_the_rolling_angle. Below it the exact answer is rest. The discrete law takes the torque's sign
  // from the spin at the start of each sub-step, so the spin chatters about zero within one sub-step's kick of the
  // torques about the centre, (m g sin th + mu_r m g cos th) R dt / I, and the sphere creeps with it:
  // |v| <= (5/2) g (sin th + mu_r cos th) dt, an error of first order: halving the sub-step halves the bound (the
  // creep itself is irregular, the chatter being a sign switch, so only the bound is checked, at three sub-steps).
  // This creep is what moves with the sub-step in a bed at rest (tools/riffle-tools bed-creep).
  const double g = 9.81, mu_r = kInclineRolling;
  SUBCASE("below the rolling angle (tan th = mu_r / 2)") {
    const double tan_theta = 0.5 * mu_r, theta = std::atan(tan_theta);
    for (const long substeps : {40L, 80L, 160L}) {
      const InclineRoll result = roll_on_incline(tan_theta, substeps, "constant_torque");
      const double bound = 2.5 * g * (std::sin(theta) + mu_r * std::cos(theta)) * result.substep;
      INFO(substeps << " sub-steps: creep " << result.creep_speed << " m/s, bound " << bound);
      CHECK(std::abs(result.creep_speed) <= bound);
    }
  }
  SUBCASE("above the rolling angle (tan th = 1.5 mu_r)") { check_rolls_above_the_rolling_angle("constant_torque"); }
}

TEST_CASE("elastic-plastic rolling friction holds a sphere at rest on an incline below the rolling angle at every sub-step, and rolls it above") {
  // Ai et al.'s model C: below the cap mu_r R F_n the rolling spring holds the weight's torque m g R sin th with a
  // rotation th_s = m g R sin th / k_r, k_r = 2.25 mu_r^2 R^2 k_n, k_n = F_n / d, so the sphere settles a distance
  // R th_s = tan th d / (2.25 mu_r^2) (2.2 d here, some 4 um) down the slope and stays. The spring's oscillation,
  // of frequency omega_r = sqrt(k_r / I_r) (I_r = 7/5 m R^2; about 300 rad/s here) with the dashpot's damping ratio
  // 0.3, has decayed by exp(-0.3 omega_r T/2) ~ e^-45 by T/2: over the second half the sphere may move by no more
  // than a thousandth of R th_s (room for the tangential spring's coupling), at every sub-step.
  const double mu_r = kInclineRolling;
  SUBCASE("below the rolling angle (tan th = mu_r / 2)") {
    const double tan_theta = 0.5 * mu_r;
    for (const long substeps : {40L, 80L, 160L}) {
      const InclineRoll result = roll_on_incline(tan_theta, substeps, "elastic_plastic");
      const double settling = tan_theta * result.overlap / (2.25 * mu_r * mu_r);
      const double moved = result.creep_speed * 0.5 * kInclineTime;
      INFO(substeps << " sub-steps: moved " << moved << " m over the second half, R th_s " << settling);
      CHECK(std::abs(moved) <= 1e-3 * settling);
    }
  }
  SUBCASE("above the rolling angle (tan th = 1.5 mu_r)") { check_rolls_above_the_rolling_angle("elastic_plastic"); }
}

TEST_CASE("an elastic frictionless gas of grains in a closed box keeps its energy to the sub-step's bound") {
  // 27 grains with random velocities (|v_i| <= 0.5 m/s) in a 3 cm box, gravity off, linear law with e = 1 and
  // mu = 0, N = 50 sub-steps per collision (t_c = 1 ms, so E = 1e6 Pa keeps the Rayleigh limit out of the way).
  // Energy is exchanged only through the springs k = m* pi^2 / t_c^2 (omega = pi / t_c for every pair and wall).
  // From the top of the file, each contact's entry and exit change the energy by at most (omega dt)^2 / 4 of its
  // normal energy E_n = m* v_n^2 / 2 at first touch, and during a contact Verlet's energy (v^2 + omega^2 d^2) / 2
  // differs from its invariant (v^2 + omega^2 d^2 (1 - (omega dt)^2 / 4)) / 2 by (omega dt)^2 / 4 of E_n: the total
  // energy (kinetic plus k d^2 / 2 of the open contacts) may drift by (omega dt)^2 / 2 sum E_n over all contacts.
  // Every sub-step is sampled (solid_substeps = 1) to find the contacts as they open.
  const double collision_time = 1.0e-3, N = 50.0, T = 0.3;
  SceneSpec spec;
  spec.law = "linear_spring_dashpot";
  spec.collision_time = collision_time;
  spec.young = 1.0e6;
  spec.dt = collision_time / N;
  spec.tank = Vec3::Constant(0.03);
  std::mt19937_64 random(20240611);
  auto uniform = [&] { return static_cast<double>(random() >> 11) * 0x1.0p-53 * 2.0 - 1.0; };  // [-1, 1)
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) {
        const Vec3 velocity = 0.5 / std::sqrt(3.0) * Vec3(uniform(), uniform(), uniform());
        spec.bodies.push_back({Vec3(0.007 + 0.008 * i, 0.007 + 0.008 * j, 0.007 + 0.008 * k), velocity});
      }
  auto simulation = simulate(spec);
  const World& world = simulation->world();
  const Solids& solids = *world.solids;
  const Contacts& contacts = *world.contacts;
  const double omega_dt = std::numbers::pi / N;
  auto stiffness = [&](double effective_mass) { return effective_mass * std::numbers::pi * std::numbers::pi / (collision_time * collision_time); };
  auto total_energy = [&] {
    double energy = 0.0;
    for (std::size_t i = 0; i < solids.size(); ++i)
      energy += 0.5 * solids.mass[i] * solids.velocity[i].squaredNorm() +
                0.5 * solids.moment_of_inertia[i] * solids.angular_velocity[i].squaredNorm();
    if (!contacts.valid) return energy;  // no list before the first sub-step (and no grain touches at t = 0)
    for (std::size_t i = 0; i < solids.size(); ++i) {
      for (std::uint32_t k = contacts.pair_offsets[i]; k < contacts.pair_offsets[i + 1]; ++k) {
        const std::size_t j = contacts.pair_second[k];
        const double overlap = contacts.pair_overlap[k];
        if (overlap > 0.0)
          energy += 0.5 * stiffness(solids.mass[i] * solids.mass[j] / (solids.mass[i] + solids.mass[j])) * overlap * overlap;
      }
      for (std::uint32_t k = contacts.wall_pair_offsets[i]; k < contacts.wall_pair_offsets[i + 1]; ++k) {
        const double overlap = contacts.wall_pair_overlap[k];
        if (overlap > 0.0) energy += 0.5 * stiffness(solids.mass[i]) * overlap * overlap;
      }
    }
    return energy;
  };
  const double initial_energy = total_energy();
  // Contacts by grain ids (slots are reordered at neighbour-list rebuilds); a wall is keyed as id 1000 + slot.
  std::set<std::pair<EntityId, EntityId>> open, now_open;
  std::vector<Vec3> velocity_before(solids.size());  // by id: ids are 0..26
  double normal_energy_sum = 0.0;
  int contact_count = 0;
  const int steps = static_cast<int>(std::lround(T / spec.dt));
  for (int step = 0; step < steps; ++step) {
    for (std::size_t i = 0; i < solids.size(); ++i) velocity_before[solids.id[i]] = solids.velocity[i];
    simulation->step();
    now_open.clear();
    for (std::size_t i = 0; i < solids.size(); ++i) {
      for (std::uint32_t k = contacts.pair_offsets[i]; k < contacts.pair_offsets[i + 1]; ++k) {
        if (contacts.pair_overlap[k] <= 0.0) continue;
        const std::size_t j = contacts.pair_second[k];
        const auto key = std::minmax(solids.id[i], solids.id[j]);
        now_open.insert(key);
        if (open.count(key)) continue;
        const Vec3 normal = (solids.position[j] - solids.position[i]).normalized();
        const double v_n = (velocity_before[solids.id[j]] - velocity_before[solids.id[i]]).dot(normal);
        normal_energy_sum += 0.5 * (solids.mass[i] * solids.mass[j] / (solids.mass[i] + solids.mass[j])) * v_n * v_n;
        ++contact_count;
      }
      for (std::uint32_t k = contacts.wall_pair_offsets[i]; k < contacts.wall_pair_offsets[i + 1]; ++k) {
        if (contacts.wall_pair_overlap[k] <= 0.0) continue;
        const std::pair<EntityId, EntityId> key{solids.id[i], 1000 + contacts.wall_pair_wall[k]};
        now_open.insert(key);
        if (open.count(key)) continue;
        const double v_n = velocity_before[solids.id[i]].dot(world.walls->normal[contacts.wall_pair_wall[k]]);
        normal_energy_sum += 0.5 * solids.mass[i] * v_n * v_n;
        ++contact_count;
      }
    }
    std::swap(open, now_open);
  }
  REQUIRE(world.step_status.ok());
  const double drift = std::abs(total_energy() / initial_energy - 1.0);
  const double bound = 0.5 * omega_dt * omega_dt * normal_energy_sum / initial_energy + 1e-12;
  INFO(contact_count << " contacts, drift " << drift << ", bound " << bound);
  CHECK(contact_count > 100);  // many collisions, as meant
  CHECK(drift < bound);
}

namespace {
/// A scene of two grain sizes of "grain" in a tank of "glass", for the sub-step estimates.
std::string substep_scene(const std::string& law, const std::string& substeps_line,
                          const std::string& contact_lines = "") {
  SceneBuilder scene;
  scene.run({.end_time = 1.0, .dt = 1.0e-3}).verbatim(substeps_line)
      .material("grain", {.density = 1318.0, .young_modulus = 1.0e8, .poisson_ratio = 0.3})
      .material("glass", {.density = 2500.0, .young_modulus = 1.0e10, .poisson_ratio = 0.25})
      .tank({.size = {0.05, 0.05, 0.05}, .wall_material = "glass"})
      .contact({.law = law, .restitution = 0.5, .friction = 0.4}).verbatim(contact_lines);
  if (law == "linear_spring_dashpot") scene.set("collision_time", 1.0e-3);
  return scene.sphere({.position = {0.01, 0.01, 0.01}, .radius = 0.0025, .material = "grain"})
      .sphere({.position = {0.03, 0.03, 0.03}, .radius = 0.005, .material = "grain"}).toml();
}
}  // namespace

TEST_CASE("the DEM sub-step is chosen within the stability estimates, and a scene asking for more is refused") {
  // The estimate (numerics.md Sec. 4.2, 4.5): 0.25 x the Rayleigh time of the smallest grain, and the contact time
  // divided by 16 steps per collision, for the smallest grains against each other and against a wall. Hertz's
  // contact time is taken at max_impact_speed = 1 m/s. Recomputed here from the scene's constants:
  const double rayleigh = rayleigh_time(kRadius, kDensity, kYoung, kPoisson);
  // Grain-grain: E* = E / (2 (1 - nu^2)), R* = R/2, m* = m/2. Grain-glass wall: 1/E* = (1 - nu^2)/E + (1 - nu_w^2)/E_w,
  // R* = R, m* = m. The stiff glass makes the wall contact the shortest.
  const double wall_young = 1.0 / ((1.0 - kPoisson * kPoisson) / kYoung + (1.0 - 0.25 * 0.25) / 1.0e10);
  const double hertz_estimate =
      std::min({0.25 * rayleigh, hertz_contact_time(kEffectiveYoung, 0.5 * kRadius, 0.5 * kMass, 1.0) / 16.0,
                hertz_contact_time(wall_young, kRadius, kMass, 1.0) / 16.0});
  REQUIRE(hertz_estimate == hertz_contact_time(wall_young, kRadius, kMass, 1.0) / 16.0);  // as meant: the wall
  // Linear law: collision_time / 16 = 62.5 us is longer than the Rayleigh limit (12.4 us), which sets it.
  const double linear_estimate = std::min(0.25 * rayleigh, 1.0e-3 / 16.0);
  REQUIRE(linear_estimate == 0.25 * rayleigh);
  const double dt = 1.0e-3;
  for (const auto& [law, estimate] : {std::pair<std::string, double>{"hertz_mindlin", hertz_estimate},
                                      std::pair<std::string, double>{"linear_spring_dashpot", linear_estimate}}) {
    INFO(law << ", estimate " << estimate << " s");
    const Model chosen = parse_scene(substep_scene(law, ""), "substeps.toml");
    CHECK(chosen.contact.stable_solid_dt == doctest::Approx(estimate).epsilon(1e-12));
    // The fewest sub-steps that respect it: dt / n <= estimate < dt / (n - 1).
    CHECK(chosen.solid_dt() <= estimate * (1.0 + 1e-12));
    CHECK(dt / static_cast<double>(chosen.solid_substeps - 1) > estimate);

    // Asking for one sub-step fewer than needed is refused, naming the key and the estimate.
    const long too_few = static_cast<long>(std::ceil(dt / estimate)) - 1;
    REQUIRE(dt / static_cast<double>(too_few) > estimate);
    std::string message;
    try {
      parse_scene(substep_scene(law, "solid_substeps = " + std::to_string(too_few) + "\n"), "substeps.toml");
    } catch (const SceneError& error) {
      message = error.what();
    }
    char estimate_text[32];
    std::snprintf(estimate_text, sizeof estimate_text, "%.4g s", estimate);
    INFO(message);
    CHECK(message.find("substeps.toml:") != std::string::npos);
    CHECK(message.find("run.solid_substeps") != std::string::npos);
    CHECK(message.find(estimate_text) != std::string::npos);
    CHECK(message.find(law == "hertz_mindlin" ? "on a wall" : "Rayleigh time") != std::string::npos);  // why
    // Exactly enough is accepted, and kept as given.
    const long enough = too_few + 1;
    const Model given =
        parse_scene(substep_scene(law, "solid_substeps = " + std::to_string(enough) + "\n"), "substeps.toml");
    CHECK(given.solid_substeps == enough);
  }
}

TEST_CASE("a stiff elastic-plastic rolling spring shortens the sub-step to resolve its swing as a collision is") {
  // The rolling spring k_r = 2.25 mu_r^2 R*^2 k_n turns the pair's relative spin at omega_r^2 = k_r / I (1/I the sum
  // of 1 / (2/5 m R^2) over the spheres that turn), the normal contact at omega_n^2 = k_n / m*. On the glass wall
  // (R* = R, m* = m, the wall does not turn): omega_r / omega_n = sqrt(2.25 mu_r^2 / 0.4) = 2.372 mu_r; two equal
  // 5 mm grains: R* = R/2, m* = m/2, I = m R^2 / 5, so 1.186 mu_r. The swing's half period is the contact time over
  // that ratio, and the estimate resolves it by the same 16 steps wherever it is the shorter.
  const double wall_young = 1.0 / ((1.0 - kPoisson * kPoisson) / kYoung + (1.0 - 0.25 * 0.25) / 1.0e10);
  const double wall_contact = hertz_contact_time(wall_young, kRadius, kMass, 1.0);
  for (const double mu_r : {0.1, 0.4, 0.8, 1.5}) {
    const double wall_ratio = std::sqrt(2.25 * mu_r * mu_r / 0.4);
    const double pair_ratio = std::sqrt(2.25 * mu_r * mu_r * 0.25 * 0.5 / 0.2);
    const double pair_contact = hertz_contact_time(kEffectiveYoung, 0.5 * kRadius, 0.5 * kMass, 1.0);
    const double expected = std::min({wall_contact / 16.0, wall_contact / (16.0 * wall_ratio),
                                      pair_contact / (16.0 * std::max(1.0, pair_ratio))});
    INFO("mu_r = " << mu_r << ", rolling over normal frequency: wall " << wall_ratio << ", grains " << pair_ratio);
    const std::string rolling = "rolling_friction = " + std::to_string(mu_r) + "\n";
    const Model elastic =
        parse_scene(substep_scene("hertz_mindlin", "", rolling + "rolling_law = \"elastic_plastic\"\n"), "s.toml");
    CHECK(elastic.contact.stable_solid_dt == doctest::Approx(expected).epsilon(1e-12));
    if (wall_ratio > 1.0) CHECK(elastic.contact.stable_solid_dt_reason.find("rolling spring") != std::string::npos);
    // The default law is the elastic-plastic one.
    const Model by_default = parse_scene(substep_scene("hertz_mindlin", "", rolling), "s.toml");
    CHECK(by_default.contact.stable_solid_dt == elastic.contact.stable_solid_dt);
    // The constant torque has no spring: the contact alone sets the sub-step, whatever mu_r.
    const Model constant =
        parse_scene(substep_scene("hertz_mindlin", "", rolling + "rolling_law = \"constant_torque\"\n"), "s.toml");
    CHECK(constant.contact.stable_solid_dt == doctest::Approx(wall_contact / 16.0).epsilon(1e-12));
  }
}

TEST_CASE("at the sub-step riffle chooses, impacts rebound within restitution_tolerance, down to e = 0") {
  // A sub-step chosen from the stiffness alone can break restitution: with the linear law and e = 0.01, a sphere
  // hitting a wall at 3.9 m/s would leave at 7.63 m/s (the damping term beyond its explicit stability limit), and
  // Hertz would give 0.0051 for 0.01. The sub-step must meet the requested restitution within contact.restitution_tolerance (0.02, the
  // user's requirement) for a head-on impact at max_impact_speed, whatever the law and e; and the estimate
  // (discrete_restitution) must be what the DEM actually does.
  const double speed = 3.9;
  for (const std::string law : {"hertz_mindlin", "linear_spring_dashpot"})
    for (const double restitution : {0.0, 0.01, 0.2, 0.5}) {
      SceneSpec spec;
      spec.law = law;
      spec.restitution = restitution;
      spec.max_impact_speed = speed;
      spec.substeps = 0;  // chosen by the reader
      spec.tank = Vec3::Constant(0.06);
      spec.bodies.push_back({Vec3(0.03, 0.03, kRadius + 1e-4), Vec3(0.0, 0.0, -speed)});
      const Model model = parse_scene(scene_text(spec), "restitution.toml");
      INFO(law << ", e = " << restitution << ", " << model.solid_substeps << " sub-steps of " << model.solid_dt()
               << " s (" << model.contact.stable_solid_dt_reason << ")");
      CHECK(model.contact.restitution_error <= model.contact.restitution_tolerance);
      // The run: one engine step of many sub-steps holds the whole impact; the velocity once apart is final.
      auto simulation = Simulation::from_model(model);
      const Solids& solids = *simulation->world().solids;
      double achieved = -1.0;
      for (int step = 0; step < 10 && achieved < 0.0; ++step) {
        simulation->step();
        if (solids.position[0][2] > kRadius && solids.velocity[0][2] > 0.0) achieved = solids.velocity[0][2] / speed;
      }
      CHECK(std::abs(achieved - restitution) <= model.contact.restitution_tolerance);
      // The estimate integrates the same scheme: the run's rebound lies within its spread over first-touch phases.
      const ContactPairParameters& pair = model.contact.pair(0, 0);
      const double worst = worst_restitution_error(model.contact.law, pair, kRadius, kMass, speed, model.solid_dt(), 32);
      CHECK(std::abs(achieved - restitution) <= worst + 1e-9);
    }
}

TEST_CASE("absurd materials give a bounded sub-step count or a clear refusal, never an overflowed one") {
  // E = 1e308 or dt >= 1e300 ask for more sub-steps than an integer holds (an unchecked cast would give -9.2e18:
  // grains frozen, exit 0), and E = 5e-324 for none.
  auto substeps_or_message = [](const SceneSpec& spec) -> std::pair<std::int64_t, std::string> {
    try {
      return {parse_scene(scene_text(spec), "absurd.toml").solid_substeps, ""};
    } catch (const SceneError& error) {
      return {0, error.what()};
    }
  };
  SceneSpec spec;
  spec.substeps = 0;
  spec.bodies.push_back({Vec3::Constant(0.01)});
  spec.young = 1e308;
  auto [stiff_count, stiff_message] = substeps_or_message(spec);
  INFO(stiff_message);
  CHECK(stiff_count == 0);
  CHECK(stiff_message.find("absurd.toml:") != std::string::npos);
  CHECK(stiff_message.find("run.dt") != std::string::npos);
  CHECK(stiff_message.find("more than 1e+06") != std::string::npos);
  spec.young = 5e-324;
  CHECK(substeps_or_message(spec).first == 1);
  spec.young = kYoung;
  spec.dt = 1e300;
  CHECK(substeps_or_message(spec).first == 0);
  spec.dt = 1.0e-3;
  spec.max_impact_speed = 1e-308;  // a contact time of 0 s
  CHECK(substeps_or_message(spec).first == 0);
}
