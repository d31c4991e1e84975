// Where the total momentum of water and grains goes in a coupled run (docs/COUPLING.md, "Where the total momentum
// goes"). Every system of the real pipeline runs inside a wrapper that, after the system, sums
// the total momentum
//   P = sum_fluid rho l0^3 u_j + sum_fluid l0^3 (drag reaction per volume, pending) + sum_grains m v
//       - sum_grains (drag impulse, pending: the water's share not yet handed over)
// and books the change to that system (one thread: the systems run one at a time). What the theory says of each:
//  - fluid_predict: the viscous sum nu (2D / lambda0 n0) sum_j w_ij (u_j - u_i) is symmetric in a pair, so the water's
//    momentum is exchanged in pairs (no wall within r_e here, no gravity): zero to rounding; the pending reaction it
//    hands to the water is an exchange inside P;
//  - fluid_correct: the dynamic stabilisation is a pair term, equal and opposite (partner share 1/2 between fluid
//    particles): zero to rounding; the GC pressure gradient C_i (3 / n0) sum_j (p_j - p_i) (w_ij / r_ij^2) r_ij is
//    not antisymmetric in a pair (numerics 2.6): the water gains -dt l0^3 sum_i <grad p>_i, its net pressure force,
//    which is zero in the continuum (the integral of grad p over a body of water bounded by p = 0 or by a period
//    vanishes) but not on the particles;
//  - the grains' sub-steps: velocity Verlet kicks each sub-step's force in two halves, the second in the next
//    sub-step, while solid_drag books the whole sub-step's drag at once: over an engine step of n sub-steps of
//    dt_s the grains receive dt_s (F_0 / 2 + F_1 + ... + F_{n-1} + F_n / 2) and the impulse books dt_s (F_1 + ... +
//    F_n): the budget moves by dt_s (F_0 - F_n) / 2 per step, a sum that telescopes to dt_s (F_initial - F_last) / 2
//    over the run (bounded by one sub-step's drag impulse, not a drift);
//  - fluid_drag_reaction: the water receives minus the grains' impulse (the mixture reading's 1/eps is 1 for a lone
//    grain with the self-corrected voidage): zero to rounding;
//  - the other systems (searches, sorts, the pressure solve, wall motion, sampling, voidage, checks) move nothing.
// So the whole drift is the integrated net GC pressure force, and the kept test checks that identity, and each
// share's bound, in a periodic box and in a closed tank (far from its walls). Two cases skipped by default print
// the numbers behind the docs: the sweep (dt, l0, clamping, GC, DS) and the error of momentum-conserving gradient
// forms in still water (what a conservative form would cost).
#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "engine/run/registry.hpp"
#include "engine/run/stepper.hpp"
#include "engine/scene/scene.hpp"
#include "engine/setup/initial_state.hpp"
#include "systems/physics/mps/hydrostatic.hpp"
#include "systems/physics/mps/mps_common.hpp"
#include "systems/physics/mps/mps_operators.hpp"
#include "tests/support/scene_builder.hpp"

using riffle::test::SceneBuilder, riffle::test::Triple;

namespace riffle {
namespace {

/// The total momentum P (above), summed in long double so that the sort's reordering leaves no trace at 1e-16.
Vec3 total_momentum(const World& world, const Model& model) {
  long double sum[3] = {0.0L, 0.0L, 0.0L};
  const double volume = model.fluid.spacing * model.fluid.spacing * model.fluid.spacing;
  const double particle_mass = model.fluid.density * volume;
  if (world.fluid) {
    const FluidParticles& fluid = *world.fluid;
    const std::size_t fluid_count = fluid_slot_count(fluid);
    for (std::size_t j = 0; j < fluid_count; ++j)
      for (int a = 0; a < 3; ++a)
        sum[a] += static_cast<long double>(particle_mass * fluid.velocity[j][a]) +
                  static_cast<long double>(volume * fluid.drag_reaction[j][a]);
  }
  if (world.solids) {
    const Solids& grains = *world.solids;
    for (std::size_t g = 0; g < grains.size(); ++g)
      for (int a = 0; a < 3; ++a)
        sum[a] += static_cast<long double>(grains.mass[g] * grains.velocity[g][a]) -
                  static_cast<long double>(grains.drag_impulse[g][a]);
  }
  return Vec3(static_cast<double>(sum[0]), static_cast<double>(sum[1]), static_cast<double>(sum[2]));
}

/// What the wrappers book: each system's change of P, summed over the run, and the parts the analysis names.
struct Ledger {
  const World* world = nullptr;
  const Model* model = nullptr;
  Vec3 last = Vec3::Zero();
  std::map<std::string, Vec3> by_system;
  Vec3 pressure = Vec3::Zero();      ///< -dt l0^3 sum_i <grad p>_i (applied_pressure_gradient), over the run
  Vec3 substeps_step = Vec3::Zero(); ///< the sub-step systems' share in the current engine step
  double worst_substep_residual = 0.0;  ///< max over steps of |share of the sub-steps - dt_s (F_0 - F_n) / 2|
  Vec3 step_start_drag = Vec3::Zero();  ///< sum of the grains' drag forces at the step start (F_0)
  std::vector<double> pressure_step_x;  ///< per step: -dt l0^3 sum_i d_x p_i
  // The net pressure impulse taken apart (decompose = true), from the same neighbour lists, r* and p^{k+1}:
  bool decompose = false;
  Vec3 raw = Vec3::Zero();      ///< without the GC matrix: -dt l0^3 sum_i (3 / n0) sum_j (p_j - p_i) (w / r^2) r_ij
  Vec3 surface = Vec3::Zero();  ///< the GC impulse of the particles flagged free surface
  Vec3 fringe = Vec3::Zero();   ///< of the others whose neighbourhood is cut (n_i < n0 (1 - 1e-3)): the layers below
  double worst_recomputed = 0.0;  ///< max |recomputed GC gradient - stored| / max |stored|
  double worst_sampled_gap = 0.0;  ///< max over particles and steps of |pressure_gradient - applied_pressure_gradient|
  std::size_t wall_neighbours = 0;  ///< fluid particles that had a wall or dummy particle within r_e (none here)
  std::size_t stabilised_pairs = 0;  ///< fluid pairs (counted from both sides) within the DS distance, over the run
  Vec3 stabilisation_fluid = Vec3::Zero();  ///< the DS momentum rho l0^3 du_DS of the fluid pairs, over the run
  Vec3 stabilisation_wall = Vec3::Zero();   ///< of the pairs with a wall or dummy particle
  /// The conservative gradient's pressure impulse less its fluid pairs': the wall pairs and G,
  /// -dt l0^3 sum_i [G + (3 / n0) sum_{wall j} 2 (q_i - min q) (w / r^2) r_ij], q = p - G . r* (a wall's q is q_i),
  /// G = rho g with its periodic components zeroed (the cases here have no body force and no tank motion).
  Vec3 conservative_walls = Vec3::Zero();

  void take_apart() {
    const FluidParticles& fluid = *world->fluid;
    const FluidNeighbours& lists = *world->fluid_neighbours;
    const std::size_t fluid_count = fluid_slot_count(fluid);
    const MpsConstants& constants = mps_constants(model->fluid);
    const WendlandKernel kernel{constants.effective_radius};
    const double n0 = constants.reference_density;
    const double radius_squared = constants.effective_radius * constants.effective_radius;
    const double scale = -world->last_step.dt * constants.particle_volume;
    const double stabilisation_squared = model->fluid.stabilisation_distance() * model->fluid.stabilisation_distance();
    const Ghosted<Vec3> predicted_of = fluid_ghosted(fluid.predicted_position, lists.ghosts.predicted_position, lists);
    const Ghosted<std::int32_t> kind_of = fluid_ghosted(fluid.kind, lists.ghosts.kind, lists);
    const Ghosted<double> pressure_of = fluid_ghosted(fluid.pressure, lists.ghosts.pressure, lists);
    double largest = 0.0, worst = 0.0;
    const Vec3 hydrostatic = hydrostatic_gradient(model->fluid.density, model->gravity, Vec3::Zero());
    Vec3 split = hydrostatic;
    for (int axis = 0; axis < 3; ++axis)
      if (model->tank.periodic[static_cast<std::size_t>(axis)]) split[axis] = 0.0;
    const auto reduced = [&](std::size_t i) { return fluid.pressure[i] - split.dot(fluid.predicted_position[i]); };
    double minimum = 1e300;
    for (std::size_t i = 0; i < fluid_count; ++i) minimum = std::min(minimum, reduced(i));
    for (std::size_t i = 0; i < fluid_count; ++i) {
      const Vec3 position = fluid.predicted_position[i];
      Vec3 sum = Vec3::Zero(), walls = Vec3::Zero();
      GradientMoment moment;
      bool walled = false;
      for (const std::uint32_t j : near_neighbours_of(lists, i)) {
        const Vec3 offset = predicted_of[j] - position;
        const double distance_squared = offset.squaredNorm();
        if (distance_squared == 0.0 || distance_squared >= radius_squared) continue;
        if (kind_of[j] != kFluidKind) walled = true;
        if (kind_of[j] != kFluidKind)
          walls += gradient_term(2.0 * (reduced(i) - minimum), kernel.weight(std::sqrt(distance_squared)) /
                                                                  distance_squared, offset);
        const double weight = kernel.weight(std::sqrt(distance_squared));
        const double weight_over_squared = weight / distance_squared;
        if (distance_squared < stabilisation_squared) {
          // fluid_correct's DS term, as momentum: rho l0^3 (sum of the terms) / (n0 dt).
          const bool fluid_partner = kind_of[j] == kFluidKind;
          const Vec3 term = stabilisation_term(fluid_partner ? 0.5 : 1.0, model->fluid.stabilisation_distance(),
                                               std::sqrt(distance_squared), weight_over_squared, offset) *
                            (model->fluid.density * constants.particle_volume / (n0 * world->last_step.dt));
          if (fluid_partner) {
            ++stabilised_pairs;
            stabilisation_fluid += term;
          } else {
            stabilisation_wall += term;
          }
        }
        // A wall or dummy partner's pressure is the hydrostatic extrapolation from i (amendment 1).
        const double partner = kind_of[j] == kFluidKind ? pressure_of[j] : fluid.pressure[i] + hydrostatic.dot(offset);
        sum += gradient_term(partner - fluid.pressure[i], weight_over_squared, offset);
        moment.add(weight, weight_over_squared, offset);
      }
      if (walled) ++wall_neighbours;
      const Vec3 raw_gradient = (3.0 / n0) * sum;
      const Vec3 gradient = gradient_correction_matrix(moment, n0) * raw_gradient;
      largest = std::max(largest, fluid.pressure_gradient[i].norm());
      worst = std::max(worst, (gradient - fluid.pressure_gradient[i]).norm());
      raw += scale * raw_gradient;
      conservative_walls += scale * ((3.0 / n0) * walls + split);
      if (fluid.free_surface[i])
        surface += scale * gradient;
      else if (moment.density < n0 * (1.0 - 1e-3))
        fringe += scale * gradient;
    }
    if (largest > 0.0) worst_recomputed = std::max(worst_recomputed, worst / largest);
  }

  void book(const std::string& name) {
    const Vec3 now = total_momentum(*world, *model);
    const Vec3 change = now - last;
    by_system.try_emplace(name, Vec3::Zero()).first->second += change;
    last = now;
    if (name == "fluid_correct") {
      const FluidParticles& fluid = *world->fluid;
      const std::size_t fluid_count = fluid_slot_count(fluid);
      const double volume = model->fluid.spacing * model->fluid.spacing * model->fluid.spacing;
      long double sum[3] = {0.0L, 0.0L, 0.0L};
      for (std::size_t i = 0; i < fluid_count; ++i) {
        for (int a = 0; a < 3; ++a) sum[a] += static_cast<long double>(fluid.applied_pressure_gradient[i][a]);
        worst_sampled_gap =
            std::max(worst_sampled_gap, (fluid.pressure_gradient[i] - fluid.applied_pressure_gradient[i]).norm());
      }
      const Vec3 force(static_cast<double>(sum[0]), static_cast<double>(sum[1]), static_cast<double>(sum[2]));
      const Vec3 impulse = -world->last_step.dt * volume * force;
      pressure += impulse;
      pressure_step_x.push_back(impulse.x());
      if (decompose) take_apart();
    }
  }
};

/// Runs a system of the real pipeline, then books the change of P to it.
class Booked final : public System {
 public:
  Booked(std::unique_ptr<System> inner, Ledger& ledger, bool substep)
      : inner_(std::move(inner)), ledger_(ledger), substep_(substep), name_(inner_->name()) {}
  std::string_view name() const override { return inner_->name(); }
  Access access() const override { return inner_->access(); }
  std::vector<std::string> run_after() const override { return inner_->run_after(); }
  std::vector<InnerGraph> inner_graphs() const override { return inner_->inner_graphs(); }
  void run(SystemContext& context) override {
    const Vec3 before = ledger_.last;
    inner_->run(context);
    ledger_.book(name_);
    if (substep_) ledger_.substeps_step += ledger_.last - before;
  }

 private:
  std::unique_ptr<System> inner_;
  Ledger& ledger_;
  bool substep_;
  std::string name_;
};

void book_all(std::vector<std::unique_ptr<System>>& systems, Ledger& ledger, bool substep) {
  for (auto& system : systems) system = std::make_unique<Booked>(std::move(system), ledger, substep);
}

/// A 5 mm grain (2650 kg/m^3) shot at (0.3, 0.2, 0) m/s through water at rest, l0 = 1 cm, no gravity, no pressure
/// force on the grain (`pressure_gradient = false`: that force has no reaction in the water by design). Periodic:
/// a 0.08 x 0.08 m box periodic along x and y, the water a slab 8 l0 thick filling the period, free above and
/// below, the grain crossing both seams. Closed: a 0.2 m tank, a free 10 l0 block of water in its middle (6 l0 from
/// every wall, beyond r_e = 2.4 l0), the grain staying inside it.
std::string grain_through_water(bool periodic, double dt, double spacing, const std::string& fluid_keys = "",
                                const std::string& tables = "", bool periodic_cube = false, bool colliding = false,
                                bool sealed = false) {
  struct Water {
    Triple low{}, high{};
    SceneBuilder::OptTriple velocity{};
  };
  SceneBuilder::Tank tank = periodic ? SceneBuilder::Tank{.size = {0.08, 0.08, 0.2}, .periodic = {"x", "y"}}
                                     : SceneBuilder::Tank{.size = {0.2, 0.2, 0.2}};
  std::vector<Water> water = {periodic ? Water{{0.0, 0.0, 0.06}, {0.08, 0.08, 0.14}}
                                       : Water{{0.05, 0.05, 0.05}, {0.15, 0.15, 0.15}}};
  Triple grain = periodic ? Triple{0.06, 0.07, 0.1} : Triple{0.07, 0.08, 0.1};
  if (colliding)  // the slab's two halves thrown at each other along x (they meet in the middle and at the seam)
    water = {{{0.0, 0.0, 0.06}, {0.04, 0.08, 0.14}, {0.5, 0.0, 0.0}},
             {{0.04, 0.0, 0.06}, {0.08, 0.08, 0.14}, {-0.5, 0.0, 0.0}}};
  if (sealed) {  // a box periodic along x and y full of water between its floor and its lid: no free surface
    tank = {.size = {0.08, 0.08, 0.08}, .periodic = {"x", "y"}};
    water = {{{0.0, 0.0, 0.0}, {0.08, 0.08, 0.08}}};
    grain = {0.06, 0.07, 0.04};
  }
  if (periodic_cube) {  // the closed case's block and grain in a 0.2 m box periodic along x and y
    tank = {.size = {0.2, 0.2, 0.2}, .periodic = {"x", "y"}};
    water = {{{0.05, 0.05, 0.05}, {0.15, 0.15, 0.15}}};
    grain = {0.07, 0.08, 0.1};
  }
  tank.wall_material = "grain";
  SceneBuilder scene;
  scene.run({.end_time = 10.0, .dt = dt, .gravity = {0.0, 0.0, 0.0}})
      .material("grain", {.density = 2650.0, .young_modulus = 1.0e8, .poisson_ratio = 0.3})
      .tank(tank).contact({.restitution = 0.5, .friction = 0.5})
      .sphere({.position = grain, .radius = 0.0025, .material = "grain", .velocity = {0.3, 0.2, 0.0}})
      .fluid({.spacing = spacing}).verbatim(fluid_keys);
  for (const Water& box : water) scene.fluid_box(box.low, box.high, box.velocity);
  return scene.coupling().set("pressure_gradient", false).verbatim(tables).toml();
}

struct Budget {
  Vec3 initial = Vec3::Zero();  ///< P at the start
  Vec3 drift = Vec3::Zero();    ///< P at the end less P at the start
  Ledger ledger;
  double largest_drag_impulse = 0.0;  ///< max over sub-steps of |F| dt_s (the bound of the sub-steps' share)
  std::size_t fluid_count_start = 0, fluid_count_end = 0;
  double grain_speed_end = 0.0;
  double grain_fluid_weight_min = 1.0;  ///< 0 if the grain ever left the water
};

Budget run_budget(const std::string& text, int steps, bool decompose = false) {
  tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  const Model model = parse_scene(text, "momentum.toml");
  World world = initial_world(model);
  Budget budget;
  budget.ledger.world = &world;
  budget.ledger.model = &model;
  budget.ledger.decompose = decompose;
  Pipeline pipeline = build_pipeline(model);
  book_all(pipeline.step_start, budget.ledger, false);
  book_all(pipeline.step, budget.ledger, false);
  book_all(pipeline.solid_step, budget.ledger, true);
  book_all(pipeline.substep, budget.ledger, true);
  book_all(pipeline.end_of_step, budget.ledger, false);
  Stepper stepper(std::move(pipeline), world, model);
  stepper.compute_initial_forces();
  budget.initial = budget.ledger.last = total_momentum(world, model);
  budget.fluid_count_start = fluid_slot_count(*world.fluid);
  for (int step = 0; step < steps; ++step) {
    const Vec3 start_drag = world.solids->drag_force[0];
    budget.ledger.substeps_step = Vec3::Zero();
    stepper.step();
    REQUIRE(world.step_status.ok());
    const double dt_s = world.last_step.substep;
    // The sub-steps' share against its prediction dt_s (F_0 - F_n) / 2 (drag is the only force on the grain).
    const Vec3 predicted = 0.5 * dt_s * (start_drag - world.solids->drag_force[0]);
    budget.ledger.worst_substep_residual =
        std::max(budget.ledger.worst_substep_residual, (budget.ledger.substeps_step - predicted).norm());
    budget.largest_drag_impulse = std::max(budget.largest_drag_impulse, world.solids->drag_force[0].norm() * dt_s);
    budget.grain_fluid_weight_min = std::min(budget.grain_fluid_weight_min, world.solids->fluid_weight[0]);
  }
  budget.drift = total_momentum(world, model) - budget.initial;
  budget.fluid_count_end = fluid_slot_count(*world.fluid);
  budget.grain_speed_end = world.solids->velocity[0].norm();
  return budget;
}

void print_budget(const char* title, const Budget& budget) {
  std::printf("%s: P0 = (%.6e, %.6e, %.6e), drift = (%.3e, %.3e, %.3e) = %.3e of |P0| along x\n", title,
              budget.initial.x(), budget.initial.y(), budget.initial.z(), budget.drift.x(), budget.drift.y(),
              budget.drift.z(), budget.drift.x() / budget.initial.x());
  for (const auto& entry : budget.ledger.by_system)
    std::printf("  %-28s (%+.3e, %+.3e, %+.3e)\n", entry.first.c_str(), entry.second.x(), entry.second.y(),
                entry.second.z());
  const auto line = [](const char* name, const Vec3& v) {
    std::printf("  %-28s (%+.3e, %+.3e, %+.3e)\n", name, v.x(), v.y(), v.z());
  };
  line("[net GC pressure impulse]", budget.ledger.pressure);
  if (budget.ledger.decompose) {
    line("[  of the surface particles]", budget.ledger.surface);
    line("[  of the cut, not surface]", budget.ledger.fringe);
    line("[without the GC matrix]", budget.ledger.raw);
    std::printf("  recomputed GC gradient against the stored one: %.1e; fluid particles with a wall neighbour: %zu; "
                "pairs within the DS distance (both sides, all steps): %zu\n",
                budget.ledger.worst_recomputed, budget.ledger.wall_neighbours, budget.ledger.stabilised_pairs);
    line("[DS, fluid pairs]", budget.ledger.stabilisation_fluid);
    line("[DS, wall pairs]", budget.ledger.stabilisation_wall);
  }
  const Vec3 grains = budget.ledger.by_system.at("solid_drag") + budget.ledger.by_system.at("solid_kick") +
                      budget.ledger.by_system.at("solid_kick_drift");
  line("[the sub-steps together]", grains);
  std::printf("  fluid_correct less the net GC pressure impulse: %.1e; drift less both: %.1e\n",
              (budget.ledger.by_system.at("fluid_correct") - budget.ledger.pressure).norm(),
              (budget.drift - budget.ledger.pressure - grains).norm());
  std::printf("  exchanged (the water's share, minus the grains' drag impulse) (%+.4e, %+.4e, %+.4e); drift / "
              "exchanged along x %.3e\n",
              budget.ledger.by_system.at("solid_drag").x(), budget.ledger.by_system.at("solid_drag").y(),
              budget.ledger.by_system.at("solid_drag").z(),
              budget.drift.x() / budget.ledger.by_system.at("solid_drag").x());
  std::printf("  sub-steps' residual against dt_s (F_0 - F_n) / 2: %.3e; largest |F| dt_s %.3e; fluid %zu -> %zu; "
              "grain speed at the end %.4f m/s; smallest sampled weight %.3f\n",
              budget.ledger.worst_substep_residual, budget.largest_drag_impulse, budget.fluid_count_start,
              budget.fluid_count_end, budget.grain_speed_end, budget.grain_fluid_weight_min);
}

}  // namespace

// The budget of each case and its variants, printed (not a check: the sweep behind docs/COUPLING.md's numbers).
// build/tests/riffle_verification_tests -tc="momentum budget sweep*" --no-skip
TEST_CASE("momentum budget sweep: where the total momentum goes, by system and by term" * doctest::skip()) {
  struct Variant {
    const char* name;
    double dt, spacing;
    std::string fluid_keys, tables;
  };
  const std::vector<Variant> variants = {
      {"l0 = 10 mm, dt = 1 ms", 1.0e-3, 0.01, "", ""},
      {"dt = 0.5 ms", 0.5e-3, 0.01, "", ""},
      {"l0 = 5 mm", 1.0e-3, 0.005, "", ""},
      {"no clamping of p < 0", 1.0e-3, 0.01, "clamp_negative_pressure = false\n", ""},
      {"GC off (p_j - p_min form)", 1.0e-3, 0.01, "", "\n[fluid.schemes]\ngc = false\n"},
      {"DS off", 1.0e-3, 0.01, "", "\n[fluid.schemes]\nds = false\n"},
      {"shifting on (Taylor velocity correction)", 1.0e-3, 0.01, "shifting = \"fickian\"\n", ""},
      // Appended to [coupling]: main's trilinear voidage, which reads eps < 1 for a lone grain.
      {"cloud-in-cell voidage (mixture reading's 1/eps)", 1.0e-3, 0.01, "", "voidage_estimate = \"cloud_in_cell\"\n"},
  };
  for (const Variant& variant : variants) {
    for (const bool periodic : {true, false}) {
      const int steps = static_cast<int>(std::lround(0.4 / variant.dt));
      const Budget budget = run_budget(
          grain_through_water(periodic, variant.dt, variant.spacing, variant.fluid_keys, variant.tables), steps, true);
      const std::string title = std::string(variant.name) + (periodic ? ", periodic x, y" : ", closed tank");
      print_budget(title.c_str(), budget);
    }
  }
  // The closed case's block of water in a box periodic along x and y (no seam reached: a translation of the closed
  // case, whose walls are beyond r_e of the water): the seam and the walls play no part.
  print_budget("the closed case's cube in a periodic box",
               run_budget(grain_through_water(true, 1.0e-3, 0.01, "", "", true), 400, true));
  // The slab's halves thrown at each other at 0.5 m/s: the pairs come within the DS distance, whose share
  // (fluid_correct less the net GC pressure impulse) must stay at rounding. 60 steps: the splash it throws up and
  // down stays beyond r_e of the floor and the lid.
  print_budget("the slab's halves colliding at +-0.5 m/s, periodic x, y, 60 steps",
               run_budget(grain_through_water(true, 1.0e-3, 0.01, "", "", false, true), 60, true));
}

namespace {

/// Still water, 10 l0 deep in a closed-bottom tank of 10 x 10 l0 (l0 = 1 cm), after `steps` steps: the largest error
/// |<grad p>_i - rho g| / (rho g) of the pressure gradient forms, evaluated from fluid_correct's own lists, r* and
/// p^{k+1} (wall partners at the hydrostatic extrapolation, as fluid_correct takes them), by class of particle:
/// flagged free surface, the others within r_e of the top layer, deeper. The forms: GC (the one riffle
/// applies), the raw difference form (p_j - p_i), the antisymmetric (p_i + p_j), and the symmetrised GC
/// (C_i + C_j)/2 (p_i + p_j) (a wall partner's C is I); the last two conserve momentum pair by pair.
void print_still_water_form_errors(int steps) {
  tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  const Model model = parse_scene(SceneBuilder().run({.end_time = 10.0, .dt = 1.0e-3})
      .material("glass", {.density = 2500.0})
      .tank({.size = {0.1, 0.1, 0.15}, .open_faces = {"z_max"}, .wall_material = "glass"}).fluid({.spacing = 0.01})
      .fluid_box({0.0, 0.0, 0.0}, {0.1, 0.1, 0.1}).toml(),
                                  "still.toml");
  World world = initial_world(model);
  Stepper stepper(build_pipeline(model), world, model);
  for (int step = 0; step < steps; ++step) {
    stepper.step();
    REQUIRE(world.step_status.ok());
  }
  const FluidParticles& fluid = *world.fluid;
  const FluidNeighbours& lists = *world.fluid_neighbours;
  const std::size_t fluid_count = fluid_slot_count(fluid);
  const MpsConstants& constants = mps_constants(model.fluid);
  const WendlandKernel kernel{constants.effective_radius};
  const double n0 = constants.reference_density;
  const double radius_squared = constants.effective_radius * constants.effective_radius;
  const double rho = model.fluid.density;
  const Vec3 exact = rho * model.gravity;
  const Vec3 wall_gradient = hydrostatic_gradient(rho, model.gravity, Vec3::Zero());
  const Ghosted<Vec3> predicted_of = fluid_ghosted(fluid.predicted_position, lists.ghosts.predicted_position, lists);
  const Ghosted<std::int32_t> kind_of = fluid_ghosted(fluid.kind, lists.ghosts.kind, lists);
  const Ghosted<double> pressure_of = fluid_ghosted(fluid.pressure, lists.ghosts.pressure, lists);
  // First pass: C_i of every fluid particle.
  std::vector<Eigen::Matrix3d> correction(fluid_count);
  
  const auto for_each_partner = [&](std::size_t i, auto&& body) {
    const Vec3 position = fluid.predicted_position[i];
    for (const std::uint32_t j : near_neighbours_of(lists, i)) {
      const Vec3 offset = predicted_of[j] - position;
      const double distance_squared = offset.squaredNorm();
      if (distance_squared == 0.0 || distance_squared >= radius_squared) continue;
      const bool fluid_partner = kind_of[j] == kFluidKind;
      const double partner = fluid_partner ? pressure_of[j]
                                           : hydrostatic_extrapolation(fluid.pressure[i], wall_gradient, offset);
      const double weight = kernel.weight(std::sqrt(distance_squared));
      body(j, fluid_partner, offset, partner, weight, weight / distance_squared);
    }
  };
  for (std::size_t i = 0; i < fluid_count; ++i) {
    GradientMoment moment;
    for_each_partner(i, [&](std::uint32_t, bool, const Vec3& offset, double, double weight, double w_r2) {
      moment.add(weight, w_r2, offset);
    });
    correction[i] = gradient_correction_matrix(moment, n0);
  }
  // q = p - G . r* - min (the form of [fluid.schemes] conservative_gradient, G = rho g here: a closed tank at rest).
  double reduced_minimum = 1e300;
  for (std::size_t i = 0; i < fluid_count; ++i)
    reduced_minimum = std::min(reduced_minimum, fluid.pressure[i] - exact.dot(fluid.predicted_position[i]));
  double top = -1e300;
  for (std::size_t i = 0; i < fluid_count; ++i) top = std::max(top, fluid.predicted_position[i].z());
  constexpr int kForms = 5;
  const char* form_names[kForms] = {"GC (applied)", "raw (p_j - p_i)", "(p_i + p_j)", "(C_i + C_j)/2 (p_i + p_j)",
                                    "G + (q_i + q_j) (riffle's)"};
  const char* class_names[3] = {"free surface", "within r_e", "deeper"};
  double worst[kForms][3] = {};
  std::size_t counts[3] = {};
  for (std::size_t i = 0; i < fluid_count; ++i) {
    const double p = fluid.pressure[i];
    Vec3 sums[kForms];
    for (Vec3& sum : sums) sum = Vec3::Zero();
    for_each_partner(i, [&](std::uint32_t j, bool fluid_partner, const Vec3& offset, double partner, double,
                            double w_r2) {
      const std::uint32_t owner = fluid_owner_of(lists, j);
      const Eigen::Matrix3d partner_correction = fluid_partner ? correction[owner] : Eigen::Matrix3d::Identity();
      sums[1] += gradient_term(partner - p, w_r2, offset);
      sums[2] += gradient_term(partner + p, w_r2, offset);
      sums[3] += 0.5 * (correction[i] + partner_correction) * gradient_term(partner + p, w_r2, offset);
      const Vec3 at = fluid.predicted_position[i] + offset;
      sums[4] += gradient_term(p - exact.dot(fluid.predicted_position[i]) + partner - exact.dot(at) - 2.0 * reduced_minimum,
                               w_r2, offset);
    });
    for (Vec3& sum : sums) sum *= 3.0 / n0;
    sums[0] = fluid.pressure_gradient[i];
    sums[4] += exact;
    const double depth = top - fluid.predicted_position[i].z();
    const int kind = fluid.free_surface[i] ? 0 : (depth < constants.effective_radius ? 1 : 2);
    ++counts[kind];
    for (int f = 0; f < kForms; ++f)
      worst[f][kind] = std::max(worst[f][kind], (sums[f] - exact).norm() / exact.norm());
  }
  std::printf("still water after %d steps: largest |<grad p> - rho g| / (rho g) by form and class (particles: %zu, "
              "%zu, %zu)\n", steps, counts[0], counts[1], counts[2]);
  for (int f = 0; f < kForms; ++f)
    std::printf("  %-28s %-14s %.3f   %-14s %.3f   %-10s %.3f\n", form_names[f], class_names[0], worst[f][0],
                class_names[1], worst[f][1], class_names[2], worst[f][2]);
}

}  // namespace

// What an antisymmetric (momentum-conserving) gradient would cost in accuracy (not a check; docs/COUPLING.md).
// build/tests/riffle_verification_tests -tc="momentum budget forms*" --no-skip
TEST_CASE("momentum budget forms: the pressure gradient forms' error in still water" * doctest::skip()) {
  print_still_water_form_errors(50);
  print_still_water_form_errors(500);
}

// The kept check. Each share is held to what the analysis above predicts, to rounding: the tolerance 1e-10 |P0|
// bounds the rounding of the booking itself (P is summed in long double and rounded to a double of ulp ~1e-16 |P|
// at each of the ~2e5 bookings of a run: at most ~2e-11 |P0| if every rounding went one way), far below any real
// exchange error (a drag reaction off by the mixture reading's 1/eps at eps = 0.99 would book 1e-2 of the
// exchanged impulse, ~1e-2 |P0|). So: the exchange (drag reaction, its delivery in the prediction), the viscous
// term, the searches, the solve and the rest book nothing; the sub-steps book exactly dt_s (F_0 - F_n) / 2 per step;
// fluid_correct books exactly the net GC pressure impulse -dt l0^3 sum_i <grad p>_i (the DS pairs cancel); and the
// run's drift is the sum of the two. How large the net pressure impulse is, is the sweep's business (above, and
// docs/COUPLING.md): it is a discretisation error of the pressure gradient, not bounded to rounding.
TEST_CASE("momentum budget: the drift of a coupled run is the net GC pressure force and the exchange is exact") {
  for (const bool periodic : {true, false}) {
    CAPTURE(periodic);
    const Budget budget = run_budget(grain_through_water(periodic, 1.0e-3, 0.01), 400, true);
    const Ledger& ledger = budget.ledger;
    const double tolerance = 1e-10 * budget.initial.norm();
    REQUIRE(budget.initial.norm() > 0.0);
    // The set-up the analysis assumes: no wall within r_e of the water, no particle escaped, the grain always wet,
    // and the harness's gradient is the one fluid_correct applied.
    CHECK(ledger.wall_neighbours == 0);
    CHECK(budget.fluid_count_end == budget.fluid_count_start);
    CHECK(budget.grain_fluid_weight_min > 0.0);
    CHECK(ledger.worst_recomputed < 1e-12);
    const Vec3 exchanged = ledger.by_system.at("solid_drag");
    CHECK(exchanged.norm() > 0.5 * budget.initial.norm());  // the grain handed most of its momentum over
    Vec3 substeps = Vec3::Zero();
    for (const auto& entry : ledger.by_system) {
      const std::string& name = entry.first;
      const Vec3& change = entry.second;
      CAPTURE(name);
      const double booked = change.norm();
      CAPTURE(booked);
      const bool grains = name == "solid_drag" || name == "solid_kick" || name == "solid_kick_drift";
      if (grains) substeps += change;
      else if (name != "fluid_correct") CHECK(change.norm() < tolerance);
    }
    CAPTURE(ledger.worst_substep_residual);
    CHECK(ledger.worst_substep_residual < tolerance);
    CHECK(substeps.norm() <= budget.largest_drag_impulse);  // telescoped: dt_s (F_initial - F_last) / 2
    const Vec3 correct = ledger.by_system.at("fluid_correct");
    CAPTURE(correct.norm());
    CAPTURE(ledger.pressure.norm());
    CHECK((correct - ledger.pressure).norm() < tolerance);
    CAPTURE(budget.drift.norm());
    CHECK((budget.drift - ledger.pressure - substeps).norm() < tolerance);
  }
}

// DS between fluid particles is a pair term with shares 1/2 and 1/2 (numerics 2.7), equal and opposite: when the
// slab's halves are thrown at each other at 0.5 m/s, thousands of pairs come within the DS distance, and the sum of
// their DS momentum (fluid_correct's own term, from its lists and r*) stays at rounding (the tolerance of the test
// above); the wall pairs (share 1: the wall, infinitely heavy, takes the reaction) are the tank's force, booked apart.
TEST_CASE("momentum budget: the dynamic stabilisation between fluid particles books nothing when active") {
  const Budget budget = run_budget(grain_through_water(true, 1.0e-3, 0.01, "", "", false, true), 60, true);
  const Ledger& ledger = budget.ledger;
  CAPTURE(ledger.stabilised_pairs);
  CHECK(ledger.stabilised_pairs > 1000);
  const double tolerance = 1e-10 * budget.initial.norm();
  CHECK(ledger.stabilisation_fluid.norm() < tolerance);
  // The recomputed DS terms are the ones fluid_correct applied: its booking is the GC pressure impulse plus them.
  const Vec3 unexplained = ledger.by_system.at("fluid_correct") - ledger.pressure - ledger.stabilisation_fluid -
                           ledger.stabilisation_wall;
  CAPTURE(ledger.stabilisation_wall.norm());
  CHECK(unexplained.norm() < tolerance);
}

}  // namespace riffle

namespace riffle {

// The conservative gradient ([fluid.schemes] conservative_gradient: G + (3/n0) sum_j (q_i + q_j) (w / r^2) r_ij,
// q = p - G . r - min): the pair's bracket is the same seen from either end and r_ij changes sign, so the pressure
// forces of a fluid pair cancel, across the seam too. It is for water without a free surface, so the case is a box
// periodic along x and y full of water between floor and lid (8 x 8 x 8 l0, no gravity, so G = 0), the grain shot
// through it as above. What fluid_correct books must be the walls' share alone (their pressure pairs, recomputed from
// the same lists, r* and p^{k+1}, and their DS pairs), to the rounding bound of the booking (1e-10 |P0|, above),
// where GC books 7e-5 (slab) and 3.7e-3 (cube) of |P0| of net pressure force (docs/COUPLING.md); the grain still
// hands the water most of its momentum, so the exchange is real.
TEST_CASE("momentum budget: with the conservative gradient the water's pressure forces cancel pair by pair") {
  // The grains sample GC's gradient here (grain_gradient = "corrected"), which the ledger recomputes.
  const Budget budget = run_budget(grain_through_water(true, 1.0e-3, 0.01, "",
                                                       "\n[fluid.schemes]\nconservative_gradient = true\n"
                                                       "grain_gradient = \"corrected\"\n",
                                                       false, false, true),
                                   400, true);
  const Ledger& ledger = budget.ledger;
  const double tolerance = 1e-10 * budget.initial.norm();
  REQUIRE(budget.initial.norm() > 0.0);
  CHECK(budget.fluid_count_end == budget.fluid_count_start);
  CHECK(ledger.wall_neighbours > 0);  // the floor's and the lid's layers
  const Vec3 exchanged = ledger.by_system.at("solid_drag");
  CHECK(exchanged.norm() > 0.5 * budget.initial.norm());
  Vec3 substeps = Vec3::Zero();
  for (const auto& entry : ledger.by_system) {
    const std::string& name = entry.first;
    CAPTURE(name);
    const double booked = entry.second.norm();
    CAPTURE(booked);
    if (name == "solid_drag" || name == "solid_kick" || name == "solid_kick_drift") substeps += entry.second;
    else if (name != "fluid_correct" && name != "fluid_predict") CHECK(booked < tolerance);
  }
  CHECK(substeps.norm() <= budget.largest_drag_impulse);
  // fluid_predict books the floor's and the lid's viscous traction here (its fluid pairs cancel: the GC case above,
  // which has no wall within r_e, holds them to the tolerance). fluid_correct books the walls' share (pressure and
  // DS), nothing of the fluid pairs.
  const Vec3 correct = ledger.by_system.at("fluid_correct");
  const Vec3 walls = ledger.conservative_walls + ledger.stabilisation_wall;
  MESSAGE("sealed box, conservative gradient: fluid_correct books (" << correct.transpose() << "), the walls' share ("
          << walls.transpose() << "), |P0| " << budget.initial.norm() << "; the stored gradients' net impulse ("
          << ledger.pressure.transpose() << ")");
  CHECK(ledger.stabilisation_fluid.norm() < tolerance);
  CHECK((correct - walls).norm() < tolerance);
  // The stored applied gradient is what moved the water (with DS), and the grains' sampled one is GC's gradient of
  // the same p^{k+1}, recomputed here from the lists, not the conservative form's.
  CHECK((correct - ledger.pressure - ledger.stabilisation_wall).norm() < tolerance);
  CHECK(ledger.worst_recomputed < 1e-12);
  CHECK(ledger.worst_sampled_gap > 0.0);
  CHECK((budget.drift - correct - substeps - ledger.by_system.at("fluid_predict")).norm() < tolerance);

  // With gravity G = rho g is not zero: the split q = p - G . r* and G's own share must leave the fluid pairs'
  // cancellation as exact (gravity, the grain's fall onto the floor and the walls move P too, so only fluid_correct's
  // identity is checked; 100 steps).
  // (The grains sample the applied gradient here, the default: stored as is.)
  std::string text = grain_through_water(true, 1.0e-3, 0.01, "", "\n[fluid.schemes]\nconservative_gradient = true\n",
                                         false, false, true);
  const std::string still = "gravity = [0.0, 0.0, 0.0]";
  text.replace(text.find(still), still.size(), "gravity = [0.0, 0.0, -9.81]");
  // Without added mass: it reads the grains' sampled gradient in the water's acceleration and hands its impulse back,
  // so with it the water would no longer move the same whichever gradient the grains sample (checked below).
  const std::string no_pressure_force = "pressure_gradient = false";
  REQUIRE(text.find(no_pressure_force) != std::string::npos);
  text.replace(text.find(no_pressure_force), no_pressure_force.size(), no_pressure_force + "\nadded_mass = false");
  const Budget heavy = run_budget(text, 100, true);
  const Vec3 heavy_correct = heavy.ledger.by_system.at("fluid_correct");
  const Vec3 heavy_walls = heavy.ledger.conservative_walls + heavy.ledger.stabilisation_wall;
  MESSAGE("with gravity: fluid_correct books (" << heavy_correct.transpose() << "), G and the walls' share ("
          << heavy_walls.transpose() << ")");
  // G's share holds the water up: rho g V t = 1000 x 512 l0^3 x 9.81 x 0.1 s (the walls' z share is small: 1 %).
  CHECK(std::abs(heavy_correct.z() - 1000.0 * 512 * 1e-6 * 9.81 * 0.1) < 0.01 * 0.5023);
  CHECK(heavy.ledger.stabilisation_fluid.norm() < 1e-10 * heavy_correct.norm());
  CHECK((heavy_correct - heavy_walls).norm() < 1e-10 * heavy_correct.norm());
  CHECK(heavy.ledger.worst_sampled_gap == 0.0);
  // "corrected" under gravity: the grains' field is GC's gradient with the walls extrapolated hydrostatically (the
  // split G is not GC's business), recomputed by the ledger; the water moves exactly as with the default.
  const std::string schemes = "conservative_gradient = true\n";
  text.replace(text.find(schemes), schemes.size(), schemes + "grain_gradient = \"corrected\"\n");
  const Budget corrected = run_budget(text, 100, true);
  CHECK(corrected.ledger.worst_recomputed < 1e-12);
  CHECK(corrected.ledger.worst_sampled_gap > 0.0);
  CHECK(corrected.ledger.by_system.at("fluid_correct").x() == heavy_correct.x());
}

}  // namespace riffle
