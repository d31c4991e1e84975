// Grains in a periodic box (docs/ARCHITECTURE.md, "Periodic boundaries and the halo"): a contact across the seam
// is the same contact as inside the box (force, tangential spring, motion), a grain crossing the seam keeps its
// velocity and reappears one period back, a periodic gas of colliding grains keeps its momentum to rounding, and
// runs are byte-identical on one and two threads and after a resume.
//
// Rounding scale: the coordinates are centimetres, whose spacing of doubles is ulp(0.04 m) = 6.9e-18 m. A pair
// across the seam differs from the same pair inside only in where its centre line is rounded: d = (x_j + L) - x_i
// instead of x_j' - x_i'. Each evaluation so differs by a few ulp of the coordinates, i.e. ~1e-17 m in an overlap of
// 1e-5..1e-4 m: a relative 1e-12 in the force. The two-body motion is not chaotic (the sensitivity of the outcome
// to the overlap is of order one), so over the few hundred sub-steps of a collision the differences stay below a
// few hundred times that; the tolerances below (1e-9 relative, 1e-13 m) sit well above it and far below any
// physical difference (a missed or doubled contact changes the force by 100 %).
#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "engine/output/checkpoint.hpp"
#include "engine/run/simulation.hpp"
#include "systems/physics/dem/contact_law.hpp"
#include "tests/support/test_support.hpp"
#include "tests/support/scene_builder.hpp"

using namespace riffle;
using riffle::test::SceneBuilder, riffle::test::TomlValue;

namespace {

struct Grain {
  Vec3 position, velocity;
  bool fixed = false;  ///< [[solids.spheres]] fixed: held for the whole run (a rough floor's grain)
};

/// Grains of `radius` in a box `size`, periodic along `periodic` (a TOML array), gravity `gravity`.
std::string scene(const Vec3& size, const std::string& periodic, const Vec3& gravity, double radius,
                  const std::vector<Grain>& grains, double dt, int substeps) {
  SceneBuilder text;
  text.run({.end_time = 10.0, .dt = dt, .solid_substeps = substeps, .gravity = test::triple(gravity)})
      .material("grain", {.density = 2650.0, .young_modulus = 1.0e8, .poisson_ratio = 0.3})
      .tank({.size = test::triple(size), .wall_material = "grain"}).set("periodic", TomlValue::verbatim(periodic))
      .contact({.restitution = 0.8, .friction = 0.5, .rolling_friction = 0.01}).solids();
  for (const Grain& grain : grains) {
    text.sphere({.position = test::triple(grain.position), .radius = radius, .material = "grain",
                 .velocity = test::triple(grain.velocity)});
    if (grain.fixed) text.set("fixed", true);
  }
  return text.toml();
}

using test::slot_of;

/// The tangential spring of the pair of ids 0 and 1, oriented for grain 0, and whether the list holds it through a
/// ghost (across the seam); zero if not in contact.
Vec3 spring_01(const Solids& solids, const Contacts& contacts, bool& across) {
  for (std::size_t i = 0; i < solids.size(); ++i)
    for (std::uint32_t k = contacts.pair_offsets[i]; k < contacts.pair_offsets[i + 1]; ++k) {
      const std::uint32_t second = contacts.pair_second[k];
      const std::uint32_t j = contacts.halo.valid ? contacts.halo.owner_of(second) : second;
      if (contacts.pair_overlap[k] <= 0.0 || solids.id[i] + solids.id[j] != 1) continue;
      across = second >= solids.size();
      return solids.id[i] == 0 ? contacts.pair_spring[k] : Vec3(-contacts.pair_spring[k]);
    }
  return Vec3::Zero();
}

/// x - y along x brought to (-L/2, L/2]: the difference of two positions on the torus.
double periodic_difference(double x, double y, double period) {
  const double d = x - y;
  return d - period * std::round(d / period);
}

/// `count` non-overlapping grains of `radius` (nearest image along x and y), random velocities up to `speed`; all
/// at z = mid-height with in-plane velocities when `flat`.
std::vector<Grain> random_gas(int count, double radius, const Vec3& size, double speed, bool flat, unsigned seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Grain> grains;
  while (static_cast<int>(grains.size()) < count) {
    Vec3 p(unit(random) * size.x(), unit(random) * size.y(),
           flat ? 0.5 * size.z() : radius + unit(random) * (size.z() - 2.0 * radius));
    bool free = true;
    for (const Grain& other : grains) {
      Vec3 d = p - other.position;
      for (int axis = 0; axis < 2; ++axis) d[axis] -= size[axis] * std::round(d[axis] / size[axis]);
      free = free && d.norm() > 2.05 * radius;
    }
    if (!free) continue;
    Vec3 v(speed * (2.0 * unit(random) - 1.0), speed * (2.0 * unit(random) - 1.0),
           flat ? 0.0 : speed * (2.0 * unit(random) - 1.0));
    grains.push_back({p, v});
  }
  return grains;
}

}  // namespace

namespace {

/// The pair of grains 0 and 1 run as given (`seam`) and shifted by half a period along x (inside the box while the
/// first is at the seam), sub-step by sub-step: the largest differences of their contact forces, tangential
/// springs, positions on the torus and velocities, and the contact's phase at each sub-step ('-' apart, 'i' inside,
/// 'a' across the seam, in the first run).
struct SeamComparison {
  double peak_force = 0.0, peak_spring = 0.0, peak_speed = 0.0;
  double force_error = 0.0, spring_error = 0.0, position_error = 0.0, velocity_error = 0.0;
  std::string phases;
  double beyond_box = 0.0;  ///< [m] the farthest a centre lay outside [0, L) along x
  double wrap_reach = 0.0;  ///< [m] how far a centre may pass a seam: half the skin, then one sub-step's drift
  bool reference_across = false;
};

SeamComparison compare_with_shifted(const std::vector<Grain>& seam, double radius, double period, int steps) {
  const Vec3 size(period, 0.02, 0.02);
  std::vector<Grain> middle = seam;
  for (Grain& grain : middle) {
    grain.position.x() += 0.5 * period;
    if (grain.position.x() >= period) grain.position.x() -= period;
  }
  const double dt = 5.0e-6;
  const std::string x = "[\"x\"]";
  auto across = Simulation::from_model(parse_scene(scene(size, x, Vec3::Zero(), radius, seam, dt, 1), "a.toml"));
  auto inside = Simulation::from_model(parse_scene(scene(size, x, Vec3::Zero(), radius, middle, dt, 1), "b.toml"));
  const Solids& a = *across->world().solids;
  const Solids& b = *inside->world().solids;
  SeamComparison result;
  for (int step = 0; step < steps; ++step) {
    across->step();
    inside->step();
    REQUIRE(across->world().step_status.ok());
    REQUIRE(inside->world().step_status.ok());
    bool a_across = false, b_across = false;
    const Vec3 spring_a = spring_01(a, *across->world().contacts, a_across);
    const Vec3 spring_b = spring_01(b, *inside->world().contacts, b_across);
    const bool touching = spring_a.norm() > 0.0 || spring_b.norm() > 0.0;
    result.phases += !touching ? '-' : a_across ? 'a' : 'i';
    result.reference_across = result.reference_across || (touching && b_across);
    result.peak_spring = std::max(result.peak_spring, spring_b.norm());
    result.spring_error = std::max(result.spring_error, (spring_a - spring_b).norm());
    for (EntityId id : {EntityId{0}, EntityId{1}}) {
      const std::size_t i = slot_of(a, id), j = slot_of(b, id);
      result.peak_force = std::max(result.peak_force, b.contact_force[j].norm());
      result.peak_speed = std::max(result.peak_speed, b.velocity[j].norm());
      result.force_error = std::max(result.force_error, (a.contact_force[i] - b.contact_force[j]).norm());
      result.beyond_box = std::max({result.beyond_box, -a.position[i].x(), a.position[i].x() - period});
      // Positions agree on the torus: the second run is the first shifted by half a period.
      result.position_error =
          std::max({result.position_error,
                    std::abs(periodic_difference(a.position[i].x() + 0.5 * period, b.position[j].x(), period)),
                    (a.position[i] - b.position[j]).tail<2>().norm()});
      result.velocity_error =
          std::max(result.velocity_error, (a.velocity[i] - b.velocity[j]).norm() +
                                              (a.angular_velocity[i] - b.angular_velocity[j]).norm() * radius);
    }
  }
  result.wrap_reach = 0.5 * across->world().contacts->skin + result.peak_speed * dt;
  MESSAGE("peak force ", result.peak_force, " N, force error ", result.force_error, " N; peak spring ",
          result.peak_spring, " m, error ", result.spring_error, " m; position error ", result.position_error,
          " m; velocity error ", result.velocity_error, " m/s; contact phases ", result.phases.substr(0, 80));
  return result;
}

/// The checks common to both seam cases: a real collision, and the two runs equal to rounding (file header).
void check_same_as_inside(const SeamComparison& result) {
  // Positions are wrapped into [0, L) at the neighbour rebuild that follows a crossing, before a grain is half a
  // skin past the face (the rebuild's own criterion, checked at the start of a sub-step: then one drift more).
  CHECK(result.beyond_box <= result.wrap_reach);
  CHECK_FALSE(result.reference_across);      // the reference pair stayed inside while in contact
  CHECK(result.peak_force > 0.1);            // a real collision (Hertz at 0.1 m/s: ~0.3 N)
  CHECK(result.peak_spring > 1e-7);          // with a loaded tangential spring
  CHECK(result.force_error <= 1e-9 * result.peak_force);
  CHECK(result.spring_error <= 1e-9 * result.peak_spring);
  CHECK(result.position_error <= 1e-13);
  CHECK(result.velocity_error <= 1e-9 * result.peak_speed);
}

/// Whether `phases` (one letter per sub-step) passes through the contact phases `wanted` in order, each for at
/// least `least` sub-steps.
bool passes_through(const std::string& phases, const std::string& wanted, std::size_t least) {
  std::size_t at = 0;
  for (char phase : wanted) {
    const std::size_t run = phases.find(std::string(least, phase), at);
    if (run == std::string::npos) return false;
    at = run + least;
  }
  return true;
}

}  // namespace

TEST_CASE("two grains pressed together across the seam feel the same force and spring, and move the same, as inside") {
  // Two 5 mm grains overlapping by 20 um, closing at 0.1 m/s and sliding past each other at 0.1 m/s while both
  // drift at -20 m/s along x (Galilean invariance: the contact does not care): grain 0 crosses x = 0 in the first
  // sub-step, and the pair stays across the seam until the rebuild that wraps grain 0 (its skin of 1.25 mm half used
  // up after 6 sub-steps of 0.1 mm), then is inside, in mid-contact, with its spring carried over by id.
  const double radius = 2.5e-3, period = 0.04;
  const double x0 = 1.0e-4, x1 = x0 - (2.0 * radius - 2.0e-5);
  const SeamComparison result = compare_with_shifted({{Vec3(x0, 0.01, 0.01), Vec3(-20.05, 0.05, 0.0)},
                                                      {Vec3(x1 + period, 0.01, 0.01), Vec3(-19.95, -0.05, 0.01)}},
                                                     radius, period, 400);
  check_same_as_inside(result);
  CHECK(passes_through(result.phases, "ai", 5));  // across, then inside with the spring carried over
}

TEST_CASE("a contact that goes from inside to across the seam and back keeps its spring by id pair") {
  // The same collision drifting at -80 m/s (Galilean invariance: the contact does not care; 0.4 mm a sub-step, within
  // the skin): the pair starts inside, grain 1 crosses x = 0 after 5 sub-steps (the pair is across the seam), grain
  // 0 after 17 (inside again, from the other side), all within the 31 sub-steps of the collision.
  const double radius = 2.5e-3, period = 0.04;
  const double x1 = 2.0e-3, x0 = x1 + (2.0 * radius - 2.0e-5);
  const SeamComparison result = compare_with_shifted({{Vec3(x0, 0.01, 0.01), Vec3(-80.05, 0.05, 0.0)},
                                                      {Vec3(x1, 0.01, 0.01), Vec3(-79.95, -0.05, 0.01)}},
                                                     radius, period, 200);
  check_same_as_inside(result);
  CHECK(passes_through(result.phases, "iai", 4));
}

TEST_CASE("a grain hitting a fixed grain across the seam rebounds as inside the box, at the restitution asked for") {
  // A rough floor's grain (fixed) just inside x = L, a free grain 10.3 um beyond it across the seam (contact at 20.6
  // sub-steps: not on a sub-step boundary, where rounding would decide the first touch) coming at it head-on
  // at 0.1 m/s: the contact reads the fixed flag through the ghost's owner, so the pair's reduced mass is the free
  // grain's own and it rebounds at e = 0.8 (the scene's), as against a wall, and exactly as the same pair inside the
  // box (the file header's rounding bounds). A collision of Hertz grains at 0.1 m/s lasts about 20 sub-steps of
  // 5 us here: e is then within 1.5 % (docs/BENCHMARKS.md, "DEM accuracy against sub-step": -1.3 % at 16).
  const double radius = 2.5e-3, period = 0.04;
  const double x1 = period - 5.0e-4, x0 = x1 + 2.0 * radius + 1.03e-5 - period;
  REQUIRE((x0 < 2.0 * radius && x1 > period - 2.0 * radius));  // on either side of x = 0: across the seam
  const SeamComparison result = compare_with_shifted(
      {{Vec3(x0, 0.01, 0.01), Vec3(-0.1, 0.0, 0.0)}, {Vec3(x1, 0.01, 0.01), Vec3::Zero(), true}}, radius, period,
      300);
  CHECK(result.beyond_box <= result.wrap_reach);
  CHECK_FALSE(result.reference_across);
  CHECK(result.peak_force > 0.1);
  CHECK(result.force_error <= 1e-9 * result.peak_force);
  CHECK(result.position_error <= 1e-13);
  CHECK(result.velocity_error <= 1e-9 * result.peak_speed);
  // The outcome, from the run across the seam.
  const Vec3 size(period, 0.02, 0.02);
  auto across = Simulation::from_model(parse_scene(
      scene(size, "[\"x\"]", Vec3::Zero(), radius,
            {{Vec3(x0, 0.01, 0.01), Vec3(-0.1, 0.0, 0.0)}, {Vec3(x1, 0.01, 0.01), Vec3::Zero(), true}}, 5.0e-6, 1),
      "fixed_seam.toml"));
  for (int step = 0; step < 300; ++step) across->step();
  const Solids& grains = *across->world().solids;
  const std::size_t free_slot = slot_of(grains, 0), fixed_slot = slot_of(grains, 1);
  CHECK(grains.position[fixed_slot] == Vec3(x1, 0.01, 0.01));
  CHECK(grains.velocity[fixed_slot] == Vec3::Zero());
  CHECK(grains.velocity[free_slot].x() / 0.1 == doctest::Approx(0.8).epsilon(0.015));
  // With the two-body reduced mass (m/2, as before the fix) Hertz damping is 1/sqrt(2) of the calibrated: e ~ 0.86.
}

TEST_CASE("a grain crossing the seam keeps its velocity and arrives one period back") {
  const double period = 0.04;
  const Vec3 size(period, 0.03, 0.02);
  const Vec3 start(0.039, 0.0295, 0.01), velocity(1.0, 0.5, 0.0);
  auto simulation = Simulation::from_model(
      parse_scene(scene(size, "[\"x\", \"y\"]", Vec3::Zero(), 1.0e-3, {{start, velocity}}, 5.0e-6, 1), "cross.toml"));
  const Solids& solids = *simulation->world().solids;
  for (int step = 0; step < 400; ++step) simulation->step();
  REQUIRE(simulation->world().step_status.ok());
  // Free flight for 2 ms: x = 0.039 + 0.002 - L = 0.001, y = 0.0295 + 0.001 - 0.03 = 0.0005. Each of the 400 drifts
  // rounds at ulp(0.04) = 6.9e-18 m (ulp(0.03) = 3.5e-18 m along y), and the wrap once more.
  CHECK(std::abs(solids.position[0].x() - 0.001) <= 401 * 6.9e-18);
  CHECK(std::abs(solids.position[0].y() - 0.0005) <= 401 * 3.5e-18);
  CHECK(solids.position[0].z() == start.z());
  CHECK(solids.velocity[0] == velocity);  // bit for bit: no force acted
  CHECK(solids.id[0] == 0);
}

namespace {
/// The sum over the touching pairs of |f|, each pair's contact force evaluated by the law at the present state (the
/// positions the last contact pass saw; the velocities after the sub-step's final kick, a change of order dt).
double touching_pair_force_sum(const Model& model, const Solids& solids, const Contacts& contacts, double dt) {
  const Halo& halo = contacts.halo;
  const auto position = ghosted(solids.position, contacts.ghosts.position, halo);
  const auto velocity = ghosted(solids.velocity, contacts.ghosts.velocity, halo);
  const auto angular_velocity = ghosted(solids.angular_velocity, contacts.ghosts.angular_velocity, halo);
  double sum = 0.0;
  for (std::uint32_t i = 0; i < solids.size(); ++i)
    for (std::uint32_t k = contacts.pair_offsets[i]; k < contacts.pair_offsets[i + 1]; ++k) {
      if (contacts.pair_overlap[k] <= 0.0) continue;
      const std::uint32_t j = contacts.pair_second[k], owner = halo.owner_of(j);
      const Vec3 centre_line = position[j] - position[i];
      const double distance = centre_line.norm();
      ContactGeometry geometry;
      geometry.normal = centre_line / distance;
      geometry.overlap = solids.radius[i] + solids.radius[owner] - distance;
      geometry.contact_velocity = velocity[j] - angular_velocity[j].cross(solids.radius[owner] * geometry.normal) -
                                  velocity[i] - angular_velocity[i].cross(solids.radius[i] * geometry.normal);
      geometry.relative_angular_velocity = angular_velocity[i] - angular_velocity[j];
      geometry.effective_radius = solids.radius[i] * solids.radius[owner] / (solids.radius[i] + solids.radius[owner]);
      geometry.effective_mass = pair_reduced_mass(solids.mass[i], solids.mass[owner], false, false);
      Vec3 spring = contacts.pair_spring[k];
      sum += evaluate_contact(model.contact.law, model.contact.pair(solids.material[i], solids.material[owner]),
                              geometry, spring, dt)
                 .force_on_first.norm();
    }
  return sum;
}
}  // namespace

TEST_CASE("a periodic gas of colliding grains without walls along x and y keeps its momentum to rounding") {
  // 70 grains of 3 mm in a 4 cm x 4 cm box periodic along x and y, all centres at mid-height with in-plane
  // velocities and no gravity: every force is in the plane and they never reach the floor or the lid. Contact forces
  // act in equal and opposite pairs, so the total momentum changes only by rounding. The bound, accumulated over the
  // sub-steps: each half kick m (v + dt F / 2m) rounds by eps m |v| (twice: the quotient and the sum) per grain, two
  // kicks per sub-step, and each grain's force is a sum of at most 12 pair forces, rounded by 12 eps sum |F| before
  // dt/2 turns it into momentum: |dP| <= sum_steps (4 eps sum_i m_i |v_i| + 12 eps dt sum_i |F_i|pairs).
  const double radius = 1.5e-3;
  const Vec3 size(0.04, 0.04, 0.02);
  const std::vector<Grain> grains = random_gas(70, radius, size, 0.5, true, 11);
  const double dt = 5.0e-6;
  auto simulation =
      Simulation::from_model(parse_scene(scene(size, "[\"x\", \"y\"]", Vec3::Zero(), radius, grains, dt, 1), "g.toml"));
  const Solids& solids = *simulation->world().solids;
  const Contacts& contacts = *simulation->world().contacts;
  auto momentum = [&] {
    long double px = 0.0L, py = 0.0L;
    for (std::size_t i = 0; i < solids.size(); ++i) {
      px += static_cast<long double>(solids.mass[i]) * solids.velocity[i].x();
      py += static_cast<long double>(solids.mass[i]) * solids.velocity[i].y();
    }
    return std::array<long double, 2>{px, py};
  };
  const auto initial = momentum();
  const double eps = std::numeric_limits<double>::epsilon();
  double bound = 0.0, largest_error = 0.0, scale = 0.0;
  int seam_contacts = 0;
  for (int step = 0; step < 2000; ++step) {
    simulation->step();
    REQUIRE(simulation->world().step_status.ok());
    double mv = 0.0;
    for (std::size_t i = 0; i < solids.size(); ++i) mv += solids.mass[i] * solids.velocity[i].norm();
    for (std::size_t k = 0; k < contacts.pair_count(); ++k)
      seam_contacts += contacts.pair_overlap[k] > 0.0 && contacts.pair_second[k] >= solids.size();
    // Each pair's force enters both grains' sums.
    const double pair_forces = 2.0 * touching_pair_force_sum(simulation->model(), solids, contacts, dt);
    bound += 4.0 * eps * mv + 12.0 * eps * dt * pair_forces;
    scale = std::max(scale, mv);
    const auto now = momentum();
    largest_error = std::max(largest_error, static_cast<double>(std::max(std::abs(now[0] - initial[0]),
                                                                         std::abs(now[1] - initial[1]))));
    CHECK(solids.position[0].z() == grains[0].position.z());
  }
  MESSAGE("momentum change ", largest_error, " kg m/s, bound ", bound, " kg m/s, sum m|v| ", scale, " kg m/s, contacts "
       "across the seam (pair-steps) ", seam_contacts);
  CHECK(seam_contacts > 50);  // the seam was crossed by contacts, not only by grains
  CHECK(largest_error <= bound);
}

namespace {
std::string busy_periodic_scene() {
  return scene(Vec3(0.04, 0.04, 0.03), "[\"x\", \"y\"]", Vec3(0.0, 0.0, -9.81), 1.0e-3,
               random_gas(600, 1.0e-3, Vec3(0.04, 0.04, 0.03), 0.3, false, 5), 2.0e-5, 4);
}
std::string bytes_after(const std::string& text, int threads, int steps) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  auto simulation = Simulation::from_model(parse_scene(text, "busy_periodic.toml"));
  for (int step = 0; step < steps; ++step) simulation->step();
  REQUIRE(simulation->world().step_status.ok());
  return encode_checkpoint(simulation->checkpoint_data());
}
}  // namespace

TEST_CASE("a periodic box of 600 grains: one and two threads, and a resumed run, give byte-identical checkpoints") {
  const std::string text = busy_periodic_scene();
  const std::string one = bytes_after(text, 1, 100);
  const std::string two = bytes_after(text, 2, 100);
  CHECK(one == two);

  const auto directory = test::scratch_dir("periodic_resume");
  auto first_part = Simulation::from_model(parse_scene(text, "busy_periodic.toml"));
  for (int step = 0; step < 47; ++step) first_part->step();
  const Contacts& contacts = *first_part->world().contacts;
  CHECK(contacts.rebuilds > 1);  // rebuilt since the start (grains wrapped, the halo built again)
  CHECK(contacts.halo.size() > 0);
  bool ghost_pair = false;
  for (std::size_t k = 0; k < contacts.pair_count(); ++k)
    ghost_pair = ghost_pair || (contacts.pair_second[k] >= first_part->world().solids->size());
  CHECK(ghost_pair);  // the checkpoint holds pairs across the seam: the resumed run must rebuild the same halo
  const std::string path = (directory / "part.ckpt").string();
  write_checkpoint(path, first_part->checkpoint_data());
  first_part.reset();
  auto resumed = Simulation::from_checkpoint(path);
  for (int step = 47; step < 100; ++step) resumed->step();
  REQUIRE(resumed->world().step_status.ok());
  CHECK(encode_checkpoint(resumed->checkpoint_data()) == two);
}
