#pragma once
// Builds a oneTBB flow graph once from an ordered list of systems and fires it once per (sub)step.
//
// Edges come from the declared access, in list order, per component: the last writer precedes every later reader;
// the readers since the last write precede the next writer (or, with no readers between, the writer precedes the
// next writer). Systems with no path between them may run concurrently. Explicit run_after() names add edges; a
// cycle is an error.
//
// The list may be cut into named phases ("step_start", "step", ...). Phases only label the timers and the graph
// dump, and each phase's wall time is measured (phase_spans): the edges run across phases exactly as within one,
// so a system of a later phase starts as soon as what it touches is done.
#include <tbb/flow_graph.h>

#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "systems/system.hpp"
#include "engine/core/timers.hpp"

namespace riffle {

class SchedulerError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

class Scheduler {
 public:
  /// A named run of consecutive systems of the list.
  struct Phase {
    std::string name;
    std::vector<std::unique_ptr<System>> systems;
  };

  /// `name` names the graph in the dump. Throws SchedulerError for duplicate names, unknown run_after names,
  /// components missing from the world, or cycles.
  Scheduler(std::string name, std::vector<Phase> phases, World& world, const Model& model);
  /// A graph of one phase, named like it ("substep", ...).
  Scheduler(std::string phase, std::vector<std::unique_ptr<System>> systems, World& world, const Model& model);
  Scheduler(const Scheduler&) = delete;
  Scheduler& operator=(const Scheduler&) = delete;

  /// Runs every system once for the (sub)step [time, time + dt]. Exceptions from systems are rethrown here, once
  /// every system already running has returned (the systems not started yet are skipped).
  void run(double time, double dt);

  /// From now on run() runs the system `name` on the calling thread, and its ancestors before it, while the rest of
  /// the graph runs around it on the pool. Why: a thread that called run() and has nothing to do sleeps until the
  /// whole graph is done, and is not woken for tasks spawned later; with the grains' loop on a worker, the loop's
  /// parallel loops got no help from it once the fluid beside it was done (measured: the loop took its one-thread
  /// time on two threads). The calling thread running the longest chain itself keeps both threads busy. Edges stay
  /// as derived; the ancestors (the step-start copies) run in list order first, alone. Throws SchedulerError if
  /// there is no such system.
  void run_on_caller(std::string_view name);
  /// From now on every system waits for the one before it in the list (edges "list order" where none was derived),
  /// so that no two run at once, each still spreading its own loops over the threads. Why: over MPI ranks with
  /// grains in MPS water the two branches' systems both talk to the other ranks, and MPI_THREAD_SERIALIZED allows
  /// one call at a time, in the same order on every rank. Call before run_on_caller.
  void run_in_list_order();

  /// Dependency edges as (from, to) indices into the system list, sorted.
  const std::vector<std::pair<std::size_t, std::size_t>>& edges() const { return edges_; }
  /// The same edges by name, "a -> b", for tests and logs.
  std::vector<std::string> edge_names() const;
  /// Why each edge of edges() exists: the components that order the two systems ("fluid", "fluid,solids"), or
  /// "run_after".
  const std::vector<std::string>& edge_reasons() const { return edge_reasons_; }
  /// True if `to` waits for `from` through a chain of edges.
  bool has_path(std::size_t from, std::size_t to) const;
  /// Graphviz DOT text of the graph, with the inner graphs of composite nodes as clusters. Nodes and edges are
  /// sorted by name, so the text depends on the graph only, not on the order of the list.
  std::string dot() const;

  /// Every component some system of this graph reads or writes, each once.
  std::vector<ComponentId> components() const;
  /// The union of the systems' access: what the graph as a whole reads only, and what it writes.
  Access access() const;

  std::size_t size() const { return systems_.size(); }
  bool empty() const { return systems_.empty(); }
  const System& system(std::size_t index) const { return *systems_[index]; }
  /// Index of the system with this name, if it is in the graph.
  std::optional<std::size_t> find(std::string_view name) const;
  /// Phase of the system at `index`.
  const std::string& phase_of(std::size_t index) const { return phases_[phase_index_[index]].name; }
  /// Per-system timers, phase = the system's phase.
  const std::vector<SystemTimer>& timers() const { return timers_; }
  /// Wall time of each phase that has systems, one call per run (name = the phase, phase = "span"): from the start
  /// of its first system, or from the end of the earlier phases' last system if that is later, to the end of its
  /// own last system. Phases that overlap later ones (the fluid beside the grains' loop) add up to more than the
  /// run.
  const std::vector<SystemTimer>& phase_spans() const { return spans_; }
  const std::string& name() const { return name_; }

 private:
  struct PhaseRange {
    std::string name;
    std::size_t begin, end;  ///< systems [begin, end) of the list
  };

  void derive_edges();
  void check_acyclic();
  void build_graph();
  void run_system(std::size_t index);
  void append_dot_body(std::string& out, const std::string& indent) const;

  std::string name_;
  std::vector<PhaseRange> phases_;
  std::vector<std::size_t> phase_index_;  ///< per system: its entry in phases_
  std::vector<std::unique_ptr<System>> systems_;
  std::vector<Access> access_;
  World& world_;
  const Model& model_;
  std::vector<std::pair<std::size_t, std::size_t>> edges_;
  std::vector<std::string> edge_reasons_;
  std::vector<std::vector<std::size_t>> successors_;
  std::vector<SystemTimer> timers_;
  std::vector<SystemTimer> spans_;
  std::vector<std::size_t> span_phase_;  ///< per span timer: its entry in phases_
  std::vector<Clock::time_point> started_, finished_;  ///< per system, this run (each node writes only its own)

  double time_ = 0.0;
  double dt_ = 0.0;
  /// Isolated: a graph run inside another graph's node (the sub-step loop) is not cancelled half way by a failure
  /// beside it, and never inherits a cancellation into its next run; the loop itself stops between sub-steps.
  tbb::task_group_context context_{tbb::task_group_context::isolated};
  tbb::flow::graph graph_{context_};
  std::unique_ptr<tbb::flow::broadcast_node<tbb::flow::continue_msg>> start_;
  std::vector<std::unique_ptr<tbb::flow::continue_node<tbb::flow::continue_msg>>> nodes_;  ///< null: caller runs it
  std::optional<std::size_t> caller_;       ///< the system run_on_caller named
  std::vector<std::size_t> caller_first_;   ///< its ancestors, in an order that respects the edges
  /// Stands for the caller's system in the flow graph: put once it has run, it starts the systems after it.
  std::unique_ptr<tbb::flow::broadcast_node<tbb::flow::continue_msg>> caller_done_;
};

}  // namespace riffle
