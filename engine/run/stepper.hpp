#pragma once
// The stepper advances the World by one engine step: the step-start graph (copies one branch reads while the other
// writes), then two branches: the step-phase graph (the fluid), and the solid-step graph followed by solid_substeps
// runs of the sub-step graph (DEM); then the end-of-step graph (checks, reductions, coupling, reordering). Each
// graph is built once. When the fluid's branch and the grains' branch touch no common component (the coupled
// scenes exchange their fields through the step-start copy and the end-of-step graph), the two branches run side
// by side: on two cores the grains' many short sub-step loops fill the gaps the fluid's serial parts leave, and
// the reverse.
#include <atomic>
#include <memory>
#include <optional>
#include <vector>

#include "engine/core/scheduler.hpp"
#include "engine/run/registry.hpp"

namespace riffle {

class Stepper {
 public:
  Stepper(Pipeline pipeline, World& world, const Model& model);

  /// Advances world.time by model.dt and world.step by one. Problems are left in world.step_status.
  void step();

  /// Lets a stop request (Ctrl-C, SIGTERM) end a long step: `stop_signal` is read, one relaxed load, before every
  /// solid sub-step. Once it is non-zero the step goes on for at most `grace_seconds` more (most steps finish and
  /// the run stops after them as usual); past that the remaining sub-steps are skipped, the fluid's branch is waited
  /// for, and the step is abandoned (last_step_abandoned()). nullptr (the default): steps always finish.
  void set_stop_flag(const std::atomic<int>* stop_signal, double grace_seconds);
  /// True if the last step() was abandoned: the world is mid-step (time and step not advanced, the grains part way
  /// through their sub-steps). It must not be checkpointed, reported or stepped again.
  bool last_step_abandoned() const { return abandoned_; }

  /// Computes the forces of the current state without advancing it (dt = 0: springs do not grow). Called once for
  /// a new run; a resumed run has its forces in the checkpoint.
  void compute_initial_forces();

  /// Timers of every system, step phase first.
  std::vector<SystemTimer> timers() const;
  /// Wall time of each branch of the step (phase "branch"): the step graph, the grains' branch (solid step and
  /// sub-steps), the end-of-step graph. With concurrent branches the first two overlap, so they add up to more
  /// than the stepping time.
  std::vector<SystemTimer> branch_timers() const { return {step_branch_, substep_branch_, end_of_step_branch_}; }
  /// True if the step graph runs beside the sub-steps.
  bool concurrent_branches() const { return concurrent_; }
  const Scheduler& step_graph() const { return step_; }
  const Scheduler& step_start_graph() const { return step_start_; }
  const Scheduler& solid_step_graph() const { return solid_step_; }
  const Scheduler& substep_graph() const { return substep_; }
  const Scheduler& end_of_step_graph() const { return end_of_step_; }

 private:
  World& world_;
  const Model& model_;
  Scheduler step_start_;
  Scheduler step_;
  Scheduler solid_step_;
  Scheduler substep_;
  Scheduler end_of_step_;
  Scheduler initial_forces_;
  bool concurrent_ = false;
  const std::atomic<int>* stop_signal_ = nullptr;
  double stop_grace_seconds_ = 0.0;
  std::optional<Clock::time_point> stop_seen_at_;  ///< when a sub-step first saw the stop request
  bool abandoned_ = false;
  SystemTimer step_branch_{"fluid step graph", "branch"};
  SystemTimer substep_branch_{"solid branch", "branch"};
  SystemTimer end_of_step_branch_{"end-of-step graph", "branch"};

  /// True once a stop was requested more than the grace period ago (checked before each sub-step).
  bool abandon_now();
};

}  // namespace riffle
