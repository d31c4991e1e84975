#pragma once
// The stepper advances the World by one engine step by firing one graph, built once from the pipeline's lists in
// this order: step_start (copies one side reads while the other writes), step (the fluid), the grains' sub-step loop
// (one composite node: solid_step's systems, then the substep systems once per sub-step), end_of_step (checks,
// reductions, coupling, reordering). Every edge, the loop's included, comes from declared access (scheduler.hpp):
// when the fluid's systems and the loop touch no common component (the coupled scenes exchange their fields through
// the step-start copy and the end-of-step systems), the scheduler finds that they may run side by side, and each
// end-of-step system starts as soon as what it reads is done. The step length comes from decide_step_lengths.
#include <atomic>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/core/scheduler.hpp"
#include "engine/core/substep_loop.hpp"
#include "engine/run/registry.hpp"

namespace riffle {

class Stepper {
 public:
  Stepper(Pipeline pipeline, World& world, const Model& model);

  /// Advances world.time by the step decide_step_lengths chose (stored in world.last_step) and world.step by one.
  /// Problems are left in world.step_status.
  void step();

  /// Lets a stop request (Ctrl-C, SIGTERM) end a long step: `stop_signal` is read, one relaxed load, before every
  /// solid sub-step. Once it is non-zero the step goes on for at most `grace_seconds` more (most steps finish and
  /// the run stops after them as usual); past that the remaining sub-steps and the systems not started yet are
  /// skipped, the running ones are waited for, and the step is abandoned (last_step_abandoned()). nullptr (the
  /// default): steps always finish.
  void set_stop_flag(const std::atomic<int>* stop_signal, double grace_seconds);
  /// True if the last step() was abandoned: the world is mid-step (time and step not advanced, the grains part way
  /// through their sub-steps). It must not be checkpointed, reported or stepped again.
  bool last_step_abandoned() const { return abandoned_; }

  /// Computes the forces of the current state without advancing it (dt = 0: springs do not grow). Called once for
  /// a new run; a resumed run has its forces in the checkpoint.
  void compute_initial_forces();

  /// Timers of every system, by phase: step_start, step, solid_step, substep, end_of_step.
  std::vector<SystemTimer> timers() const;
  /// Wall time of each branch of the step (phase "branch"): the fluid's systems (after the step-start copies), the
  /// grains' sub-step loop, the end-of-step systems once both branches are done (Scheduler::phase_spans). The first
  /// two run side by side and add up to more than the stepping time. A branch the scene does not have has no calls.
  std::vector<SystemTimer> branch_timers() const;
  /// True if the graph has no path between the fluid's systems and the grains' sub-step loop: they may run beside
  /// each other.
  bool concurrent_branches() const { return concurrent_; }

  /// The step's graph, with the sub-step loop as one node.
  const Scheduler& step_graph() const { return *step_; }
  /// The grains' sub-step loop, or nullptr if the scene has no grains' systems.
  const SubstepLoop* substep_loop() const { return loop_; }
  const Scheduler& initial_forces_graph() const { return initial_forces_; }
  /// DOT text of the step graph, the loop's inner graphs as clusters (`riffle graph`).
  std::string dot() const { return step_->dot(); }

  /// Names of the loop node and of the phases, as they appear in timers, tests and the graph dump.
  static constexpr const char* kLoopName = "solid_substeps";
  static constexpr const char* kLoopPhase = "solid_branch";

 private:
  std::unique_ptr<Scheduler> build_step_graph(Pipeline& pipeline);
  /// The timer of the phase's span in the step graph, renamed as a branch; no calls if the phase is empty.
  SystemTimer phase_branch(const std::string& phase, const std::string& name) const;

  World& world_;
  const Model& model_;
  SubstepLoop* loop_ = nullptr;  ///< owned by step_
  std::unique_ptr<Scheduler> step_;
  Scheduler initial_forces_;
  bool concurrent_ = false;
  const std::atomic<int>* stop_signal_ = nullptr;
  double stop_grace_seconds_ = 0.0;
  std::optional<Clock::time_point> stop_seen_at_;  ///< when a sub-step first saw the stop request
  bool abandoned_ = false;

  /// True once a stop was requested more than the grace period ago (checked before each sub-step).
  bool abandon_now();
};

}  // namespace riffle
