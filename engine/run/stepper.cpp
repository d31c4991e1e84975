#include "engine/run/stepper.hpp"

#include <algorithm>
#include <limits>

#include "systems/physics/ranks/rank_comm.hpp"
#include "systems/physics/time/time_step.hpp"

namespace riffle {

namespace {
/// Over MPI ranks with grains in MPS water both branches talk to the other ranks: one system at a time, in list
/// order (Scheduler::run_in_list_order says why).
bool one_system_at_a_time(const World& world) { return ranks::distributed() && world.fluid && world.solids; }
}  // namespace

Stepper::Stepper(Pipeline pipeline, World& world, const Model& model)
    : world_(world),
      model_(model),
      step_(build_step_graph(pipeline)),
      initial_forces_("initial_forces", std::move(pipeline.initial_forces), world, model) {
  // The fluid's branch may run beside the grains' when no edge path joins any of its systems to the loop.
  const std::optional<std::size_t> loop = step_->find(kLoopName);
  bool any_fluid = false;
  bool joined = false;
  for (std::size_t index = 0; index < step_->size(); ++index) {
    if (step_->phase_of(index) != "step") continue;
    any_fluid = true;
    if (loop && (step_->has_path(index, *loop) || step_->has_path(*loop, index))) joined = true;
  }
  concurrent_ = loop && any_fluid && !joined;
  // Its systems talk to the other ranks too once the world is split (a resume computes no initial forces today).
  if (one_system_at_a_time(world_)) initial_forces_.run_in_list_order();
}

std::unique_ptr<Scheduler> Stepper::build_step_graph(Pipeline& pipeline) {
  // The list order gives the data order wherever two systems share a component: the step-start copies, the fluid,
  // the grains' loop, the end-of-step systems, as the separate graphs of one step ran before.
  std::vector<Scheduler::Phase> phases;
  phases.push_back({"step_start", std::move(pipeline.step_start)});
  phases.push_back({"step", std::move(pipeline.step)});
  std::vector<std::unique_ptr<System>> grains;
  if (!pipeline.solid_step.empty() || !pipeline.substep.empty()) {
    auto loop = std::make_unique<SubstepLoop>(
        kLoopName, std::make_unique<Scheduler>("solid_step", std::move(pipeline.solid_step), world_, model_),
        std::make_unique<Scheduler>("substep", std::move(pipeline.substep), world_, model_),
        [this] { return SubstepLoop::Plan{world_.last_step.substeps, world_.last_step.substep}; },
        [this] { return abandon_now(); });
    loop_ = loop.get();
    grains.push_back(std::move(loop));
  }
  phases.push_back({kLoopPhase, std::move(grains)});
  phases.push_back({"end_of_step", std::move(pipeline.end_of_step)});
  auto graph = std::make_unique<Scheduler>("step", std::move(phases), world_, model_);
  if (one_system_at_a_time(world_)) graph->run_in_list_order();
  // The grains' loop is the step's longest chain: the calling thread runs it (Scheduler::run_on_caller says why).
  if (loop_) graph->run_on_caller(kLoopName);
  return graph;
}

void Stepper::set_stop_flag(const std::atomic<int>* stop_signal, double grace_seconds) {
  stop_signal_ = stop_signal;
  stop_grace_seconds_ = grace_seconds;
  stop_seen_at_.reset();
}

bool Stepper::abandon_now() {
  if (stop_signal_ == nullptr || stop_signal_->load(std::memory_order_relaxed) == 0) return false;
  if (!stop_seen_at_) stop_seen_at_ = Clock::now();
  return seconds_since(*stop_seen_at_) >= stop_grace_seconds_;
}

void Stepper::compute_initial_forces() { initial_forces_.run(world_.time, 0.0); }

void Stepper::step() {
  world_.step_status.clear();
  abandoned_ = false;
  const double start = world_.time;
  // The water's relaxation under the grains' drag, from the grains as the last step left them (as the Courant
  // limit reads the water's speeds as they are).
  double drag_rate = (world_.fluid || world_.mean_flow) && world_.solids ? water_drag_rate(model_, *world_.solids, *world_.solids,
                                                                            *world_.solids, *world_.solids)
                                                         : 0.0;
  // Over MPI ranks every rank takes the same step: the fastest relaxation of any rank's grains.
  if (world_.contacts && world_.contacts->ranks.active) drag_rate = ranks::max(drag_rate);
  std::optional<double> fluid_max_speed_squared;
  double depth = 0.0;
  if (world_.fluid) {
    fluid_max_speed_squared = max_squared_speed(*world_.fluid);
    WaterExtent extent = water_extent(*world_.fluid, model_.gravity);
    // Over MPI ranks with the water spread over them: the fastest particle of any rank's, the whole water's extent
    // (a rank without water reports an empty one, low > high).
    if (world_.fluid_neighbours && world_.fluid_neighbours->ranks.active) {
      fluid_max_speed_squared = ranks::max(*fluid_max_speed_squared);
      const bool empty = extent.low > extent.high;
      extent.low = -ranks::max(empty ? -std::numeric_limits<double>::infinity() : -extent.low);
      extent.high = ranks::max(empty ? -std::numeric_limits<double>::infinity() : extent.high);
    }
    depth = water_depth(extent, model_.fluid.spacing);
  }
  world_.last_step = decide_step_lengths(model_, fluid_max_speed_squared, drag_rate, depth);
  const double dt = world_.last_step.dt;
  if (world_.fluid && dt < model_.fluid.min_dt) {
    // Name the fastest fluid particle: that is where the flow blew up.
    const FluidParticles& fluid = *world_.fluid;
    const std::size_t fluid_count = fluid_slot_count(fluid);
    std::size_t fastest = 0;
    for (std::size_t i = 1; i < fluid_count; ++i)
      if (fluid.velocity[i].squaredNorm() > fluid.velocity[fastest].squaredNorm()) fastest = i;
    world_.step_status.problem = StepProblem::kTimeStepCollapse;
    world_.step_status.phase = "fluid";
    world_.step_status.entity = fluid.id[fastest];
    world_.step_status.position = fluid.position[fastest];
    world_.step_status.velocity = fluid.velocity[fastest];
    return;
  }
  try {
    step_->run(start, dt);
  } catch (const StepAbandoned&) {
    abandoned_ = true;  // mid-step: neither the time nor the step advances
    return;
  }
  world_.time = start + dt;
  ++world_.step;
}

std::vector<SystemTimer> Stepper::timers() const {
  std::vector<SystemTimer> all;
  for (std::size_t index = 0; index < step_->size(); ++index) {
    if (loop_ && &step_->system(index) == loop_) {
      for (const Scheduler* inner : {&loop_->once(), &loop_->repeated()})
        all.insert(all.end(), inner->timers().begin(), inner->timers().end());
    } else {
      all.push_back(step_->timers()[index]);
    }
  }
  return all;
}

SystemTimer Stepper::phase_branch(const std::string& phase, const std::string& name) const {
  for (const SystemTimer& span : step_->phase_spans()) {
    if (span.name != phase) continue;
    SystemTimer branch = span;
    branch.name = name;
    branch.phase = "branch";
    return branch;
  }
  return SystemTimer{name, "branch"};
}

std::vector<SystemTimer> Stepper::branch_timers() const {
  return {phase_branch("step", "fluid step graph"), loop_ ? loop_->timer() : SystemTimer{"solid branch", "branch"},
          phase_branch("end_of_step", "end-of-step graph")};
}

}  // namespace riffle
