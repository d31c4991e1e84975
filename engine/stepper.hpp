#pragma once
// The stepper advances the World by one engine step: the step-phase graph (the fluid, later), then
// solid_substeps runs of the sub-step graph (DEM), then the end-of-step graph (checks, reductions, reordering).
// Each graph is built once.
#include <memory>
#include <vector>

#include "engine/scheduler.hpp"
#include "systems/registry.hpp"

namespace riffle {

class Stepper {
 public:
  Stepper(Pipeline pipeline, World& world, const Model& model);

  /// Advances world.time by model.dt and world.step by one. Problems are left in world.step_status.
  void step();

  /// Computes the forces of the current state without advancing it (dt = 0: springs do not grow). Called once for
  /// a new run; a resumed run has its forces in the checkpoint.
  void compute_initial_forces();

  /// Timers of every system, step phase first.
  std::vector<SystemTimer> timers() const;
  const Scheduler& step_graph() const { return step_; }
  const Scheduler& substep_graph() const { return substep_; }
  const Scheduler& end_of_step_graph() const { return end_of_step_; }

 private:
  World& world_;
  const Model& model_;
  Scheduler step_;
  Scheduler substep_;
  Scheduler end_of_step_;
  Scheduler initial_forces_;
};

}  // namespace riffle
