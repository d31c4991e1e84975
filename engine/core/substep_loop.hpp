#pragma once
// A composite node of the step graph: the grains' branch. It runs its `once` graph (the grains' once-a-step
// systems), then its `repeated` graph once per sub-step, and declares the union of what the two touch, so the
// scheduler of the step places the whole loop by its access like any other system: beside the fluid's systems when
// the two share no component, after or before them when they do.
#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <string>

#include "engine/core/scheduler.hpp"

namespace riffle {

/// Thrown out of the step graph by a loop told to stop between sub-steps. The graph skips the systems not started
/// yet and waits for those running, then the stepper catches it: the step is abandoned, the world left mid-step.
class StepAbandoned : public std::exception {
 public:
  const char* what() const noexcept override { return "the step was abandoned between two sub-steps"; }
};

class SubstepLoop final : public System {
 public:
  struct Plan {
    std::int64_t count = 0;  ///< sub-steps this step
    double length = 0.0;     ///< [s] each
  };

  /// `plan` gives this step's sub-steps; `stop_now` is asked before each sub-step (true: throw StepAbandoned).
  SubstepLoop(std::string name, std::unique_ptr<Scheduler> once, std::unique_ptr<Scheduler> repeated,
              std::function<Plan()> plan, std::function<bool()> stop_now);

  std::string_view name() const override { return name_; }
  /// What the two inner graphs read only, and what they write.
  Access access() const override { return access_; }
  /// Runs `once` at the step's start time, then sub-step k over [time + k * length, time + (k + 1) * length]. The
  /// sub-step times come from the step start and the index, never from a running sum, so a resumed run sees exactly
  /// the times of an uninterrupted one.
  void run(SystemContext& context) override;
  std::vector<InnerGraph> inner_graphs() const override {
    return {{once_.get(), "once"}, {repeated_.get(), "once per sub-step"}};
  }

  const Scheduler& once() const { return *once_; }
  const Scheduler& repeated() const { return *repeated_; }
  /// Wall time of each run of the loop (phase "branch"), items = the sub-steps done; also counted when abandoned.
  const SystemTimer& timer() const { return timer_; }

 private:
  std::string name_;
  std::unique_ptr<Scheduler> once_, repeated_;
  std::function<Plan()> plan_;
  std::function<bool()> stop_now_;
  Access access_;
  SystemTimer timer_;
};

}  // namespace riffle
