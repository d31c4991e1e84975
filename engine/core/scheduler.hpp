#pragma once
// Builds a oneTBB flow graph once from an ordered list of systems and fires it once per (sub)step.
//
// Edges come from the declared access, in list order, per component: the last writer precedes every later reader;
// the readers since the last write precede the next writer (or, with no readers between, the writer precedes the
// next writer). Systems with no path between them may run concurrently. Explicit run_after() names add edges; a
// cycle is an error.
#include <tbb/flow_graph.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "engine/core/system.hpp"
#include "engine/core/timers.hpp"

namespace riffle {

class SchedulerError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

class Scheduler {
 public:
  /// `phase` labels the timers ("step", "substep", ...). Throws SchedulerError for duplicate names, unknown
  /// run_after names, components missing from the world, or cycles.
  Scheduler(std::string phase, std::vector<std::unique_ptr<System>> systems, World& world, const Model& model);
  Scheduler(const Scheduler&) = delete;
  Scheduler& operator=(const Scheduler&) = delete;

  /// Runs every system once for the (sub)step [time, time + dt]. Exceptions from systems are rethrown here.
  void run(double time, double dt);

  /// Dependency edges as (from, to) indices into the system list, sorted.
  const std::vector<std::pair<std::size_t, std::size_t>>& edges() const { return edges_; }
  /// The same edges by name, "a -> b", for tests and logs.
  std::vector<std::string> edge_names() const;
  /// Graphviz DOT text of the graph.
  std::string dot() const;

  /// Every component some system of this graph reads or writes, each once.
  std::vector<ComponentId> components() const;

  std::size_t size() const { return systems_.size(); }
  bool empty() const { return systems_.empty(); }
  const System& system(std::size_t index) const { return *systems_[index]; }
  const std::vector<SystemTimer>& timers() const { return timers_; }
  const std::string& phase() const { return phase_; }

 private:
  void derive_edges();
  void check_acyclic() const;
  void build_graph();

  std::string phase_;
  std::vector<std::unique_ptr<System>> systems_;
  std::vector<Access> access_;
  World& world_;
  const Model& model_;
  std::vector<std::pair<std::size_t, std::size_t>> edges_;
  std::vector<SystemTimer> timers_;

  double time_ = 0.0;
  double dt_ = 0.0;
  tbb::flow::graph graph_;
  std::unique_ptr<tbb::flow::broadcast_node<tbb::flow::continue_msg>> start_;
  std::vector<std::unique_ptr<tbb::flow::continue_node<tbb::flow::continue_msg>>> nodes_;
};

}  // namespace riffle
