#include "engine/core/substep_loop.hpp"

#include <tbb/task.h>

namespace riffle {

namespace {

/// True once the graph this loop runs in was cancelled (another of its systems threw): the step will be unwound,
/// so the remaining sub-steps would be wasted work on a world nobody reads.
bool enclosing_graph_cancelled() {
  tbb::task_group_context* context = tbb::task::current_context();
  return context != nullptr && context->is_group_execution_cancelled();
}

}  // namespace

SubstepLoop::SubstepLoop(std::string name, std::unique_ptr<Scheduler> once, std::unique_ptr<Scheduler> repeated,
                         std::function<Plan()> plan, std::function<bool()> stop_now)
    : name_(std::move(name)),
      once_(std::move(once)),
      repeated_(std::move(repeated)),
      plan_(std::move(plan)),
      stop_now_(std::move(stop_now)),
      timer_{"solid branch", "branch"} {
  const Access first = once_->access(), second = repeated_->access();
  for (const Access* part : {&first, &second})
    for (const ComponentId component : part->writes)
      if (!access_.writes_component(component)) access_.writes.push_back(component);
  for (const Access* part : {&first, &second})
    for (const ComponentId component : part->reads)
      if (!access_.writes_component(component) && !access_.reads_component(component))
        access_.reads.push_back(component);
}

void SubstepLoop::run(SystemContext& context) {
  const auto begin = Clock::now();
  const Plan plan = plan_();
  once_->run(context.time, context.dt);
  std::int64_t sub = 0;
  for (; sub < plan.count; ++sub) {
    if (stop_now_()) {  // leave the step unfinished
      timer_.add(seconds_since(begin), static_cast<std::uint64_t>(sub));
      throw StepAbandoned();
    }
    if (enclosing_graph_cancelled()) break;
    repeated_->run(context.time + static_cast<double>(sub) * plan.length, plan.length);
  }
  timer_.add(seconds_since(begin), static_cast<std::uint64_t>(sub));
  context.count_items(static_cast<std::size_t>(sub));
}

}  // namespace riffle
