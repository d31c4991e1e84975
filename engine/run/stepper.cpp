#include "engine/run/stepper.hpp"

#include <tbb/task_group.h>

#include <algorithm>
#include <cmath>

#include "systems/physics/time_step.hpp"

namespace riffle {

Stepper::Stepper(Pipeline pipeline, World& world, const Model& model)
    : world_(world),
      model_(model),
      step_start_("step_start", std::move(pipeline.step_start), world, model),
      step_("step", std::move(pipeline.step), world, model),
      solid_step_("solid_step", std::move(pipeline.solid_step), world, model),
      substep_("substep", std::move(pipeline.substep), world, model),
      end_of_step_("end_of_step", std::move(pipeline.end_of_step), world, model),
      initial_forces_("initial_forces", std::move(pipeline.initial_forces), world, model) {
  const std::vector<ComponentId> fluid_side = step_.components();
  std::vector<ComponentId> solid_side = substep_.components();
  for (const ComponentId component : solid_step_.components()) solid_side.push_back(component);
  concurrent_ = !step_.empty() && !substep_.empty() &&
                std::none_of(fluid_side.begin(), fluid_side.end(), [&](ComponentId component) {
                  return std::find(solid_side.begin(), solid_side.end(), component) != solid_side.end();
                });
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
  // A fluid limits the step by its Courant and diffusion numbers (numerics 1.5); run.dt is the largest step.
  double dt = model_.dt;
  if (world_.fluid) {
    dt = fluid_time_step(model_.fluid, *world_.fluid, model_.dt);
    if (dt < model_.fluid.min_dt) {
      // Name the fastest fluid particle: that is where the flow blew up.
      const FluidParticles& fluid = *world_.fluid;
      std::size_t fastest = 0;
      for (std::size_t i = 1; i < fluid_slot_count(fluid); ++i)
        if (fluid.velocity[i].squaredNorm() > fluid.velocity[fastest].squaredNorm()) fastest = i;
      world_.step_status.problem = StepProblem::kTimeStepCollapse;
      world_.step_status.phase = "fluid";
      world_.step_status.entity = fluid.id[fastest];
      world_.step_status.position = fluid.position[fastest];
      world_.step_status.velocity = fluid.velocity[fastest];
      world_.last_dt = dt;
      return;
    }
  }
  world_.last_dt = dt;
  step_start_.run(start, dt);
  // Sub-steps no longer than the scene's solid_dt(); exactly solid_substeps of them at the full step.
  // (dt < run.dt here, so the count stays within [1, solid_substeps]; clamped in floating point before the cast.)
  const std::int64_t substeps =
      dt == model_.dt
          ? model_.solid_substeps
          : static_cast<std::int64_t>(std::clamp(std::ceil(dt / model_.solid_dt() - 1e-9), 1.0,
                                                  static_cast<double>(model_.solid_substeps)));
  const double solid_dt = dt / static_cast<double>(substeps);
  const auto run_step_graph = [&] {
    const auto begin = Clock::now();
    step_.run(start, dt);
    step_branch_.add(seconds_since(begin), 1);
  };
  // Sub-step times come from the step start and the sub-step index, never from a running sum, so a resumed run
  // sees exactly the same times as an uninterrupted one.
  const auto run_substeps = [&] {
    const auto begin = Clock::now();
    solid_step_.run(start, dt);
    std::int64_t sub = 0;
    for (; sub < substeps; ++sub) {
      if (abandon_now()) {  // a stop request older than the grace period: leave the step unfinished
        abandoned_ = true;
        break;
      }
      substep_.run(start + static_cast<double>(sub) * solid_dt, solid_dt);
    }
    substep_branch_.add(seconds_since(begin), static_cast<std::uint64_t>(sub));
  };
  if (concurrent_) {
    tbb::task_group fluid_branch;
    fluid_branch.run(run_step_graph);
    try {
      run_substeps();
    } catch (...) {
      fluid_branch.wait();  // never leave the fluid branch running on a world that is being unwound
      throw;
    }
    fluid_branch.wait();  // rethrows what a fluid system threw
  } else {
    run_step_graph();
    run_substeps();
  }
  if (abandoned_) return;  // mid-step: neither the time nor the step advances, and no end-of-step checks run
  world_.time = start + dt;
  const auto end_begin = Clock::now();
  end_of_step_.run(start, dt);
  end_of_step_branch_.add(seconds_since(end_begin), 1);
  ++world_.step;
}

std::vector<SystemTimer> Stepper::timers() const {
  std::vector<SystemTimer> all;
  for (const Scheduler* graph : {&step_start_, &step_, &solid_step_, &substep_, &end_of_step_})
    all.insert(all.end(), graph->timers().begin(), graph->timers().end());
  return all;
}

}  // namespace riffle
