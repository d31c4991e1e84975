#include "engine/core/scheduler.hpp"

#include <algorithm>
#include <functional>
#include <map>
#include <set>

namespace riffle {

namespace {

std::vector<Scheduler::Phase> one_phase(std::string name, std::vector<std::unique_ptr<System>> systems) {
  std::vector<Scheduler::Phase> phases;
  phases.push_back({std::move(name), std::move(systems)});
  return phases;
}

/// `text` in double quotes, appended piece by piece (GCC 12 warns falsely, -Wrestrict, on "\"" + string + "\"").
std::string quoted(std::string_view text) {
  std::string out;
  out.reserve(text.size() + 2);
  out += '"';
  out += text;
  out += '"';
  return out;
}

}  // namespace

Scheduler::Scheduler(std::string phase, std::vector<std::unique_ptr<System>> systems, World& world,
                     const Model& model)
    : Scheduler(phase, one_phase(phase, std::move(systems)), world, model) {}

Scheduler::Scheduler(std::string name, std::vector<Phase> phases, World& world, const Model& model)
    : name_(std::move(name)), world_(world), model_(model) {
  for (Phase& phase : phases) {
    phases_.push_back({phase.name, systems_.size(), systems_.size() + phase.systems.size()});
    for (auto& system : phase.systems) {
      phase_index_.push_back(phases_.size() - 1);
      systems_.push_back(std::move(system));
    }
    if (!phase.systems.empty()) {
      spans_.push_back(SystemTimer{phase.name, "span"});
      span_phase_.push_back(phases_.size() - 1);
    }
  }
  std::set<std::string, std::less<>> names;
  for (std::size_t index = 0; index < systems_.size(); ++index) {
    const System& system = *systems_[index];
    if (!names.insert(std::string(system.name())).second)
      throw SchedulerError("two systems are named '" + std::string(system.name()) + "'");
    access_.push_back(system.access());
    for (const auto* list : {&access_.back().reads, &access_.back().writes})
      for (ComponentId id : *list)
        if (!world_.has(id))
          throw SchedulerError("system '" + std::string(system.name()) + "' declares component '" +
                               std::string(component_name(id)) + "', which this scene does not have");
    timers_.push_back(SystemTimer{std::string(system.name()), phase_of(index)});
  }
  started_.resize(systems_.size());
  finished_.resize(systems_.size());
  derive_edges();
  check_acyclic();
  build_graph();
}

void Scheduler::derive_edges() {
  std::map<std::pair<std::size_t, std::size_t>, std::set<std::string>> reasons;
  struct Usage {
    std::optional<std::size_t> last_writer;
    std::vector<std::size_t> readers_since_write;
  };
  std::map<ComponentId, Usage> usage;
  for (std::size_t index = 0; index < systems_.size(); ++index) {
    const Access& access = access_[index];
    for (ComponentId id : access.reads) {
      if (access.writes_component(id)) continue;  // a writer is handled below
      Usage& use = usage[id];
      if (use.last_writer) reasons[{*use.last_writer, index}].insert(std::string(component_name(id)));
      use.readers_since_write.push_back(index);
    }
    for (ComponentId id : access.writes) {
      Usage& use = usage[id];
      if (!use.readers_since_write.empty()) {
        for (std::size_t reader : use.readers_since_write)
          reasons[{reader, index}].insert(std::string(component_name(id)));
      } else if (use.last_writer) {
        reasons[{*use.last_writer, index}].insert(std::string(component_name(id)));
      }
      use.last_writer = index;
      use.readers_since_write.clear();
    }
  }
  for (std::size_t index = 0; index < systems_.size(); ++index) {
    for (const std::string& before : systems_[index]->run_after()) {
      const std::optional<std::size_t> found = find(before);
      if (!found)
        throw SchedulerError("system '" + std::string(systems_[index]->name()) + "' runs after '" + before +
                             "', which is not scheduled in graph '" + name_ + "'");
      reasons[{*found, index}].insert("run_after");
    }
  }
  for (const auto& [edge, why] : reasons) {
    edges_.push_back(edge);
    std::string text;
    for (const std::string& reason : why) text += (text.empty() ? "" : ",") + reason;
    edge_reasons_.push_back(text);
  }
}

void Scheduler::check_acyclic() {
  // Depth-first search with colours; a grey node reached again closes a cycle.
  const std::size_t count = systems_.size();
  successors_.assign(count, {});
  for (auto [from, to] : edges_) successors_[from].push_back(to);
  std::vector<int> colour(count, 0);
  std::vector<std::size_t> path;
  std::function<void(std::size_t)> visit = [&](std::size_t node) {
    colour[node] = 1;
    path.push_back(node);
    for (std::size_t next : successors_[node]) {
      if (colour[next] == 1) {
        std::string cycle;
        auto start = std::find(path.begin(), path.end(), next);
        for (auto it = start; it != path.end(); ++it) cycle += std::string(systems_[*it]->name()) + " -> ";
        cycle += std::string(systems_[next]->name());
        throw SchedulerError("the systems of graph '" + name_ + "' form a cycle: " + cycle);
      }
      if (colour[next] == 0) visit(next);
    }
    path.pop_back();
    colour[node] = 2;
  };
  for (std::size_t node = 0; node < count; ++node)
    if (colour[node] == 0) visit(node);
}

void Scheduler::run_system(std::size_t index) {
  SystemContext context(world_, model_, *systems_[index], access_[index], time_, dt_);
  started_[index] = Clock::now();
  systems_[index]->run(context);
  finished_[index] = Clock::now();
  timers_[index].add(std::chrono::duration<double>(finished_[index] - started_[index]).count(), context.items());
}

void Scheduler::build_graph() {
  using tbb::flow::continue_msg;
  nodes_.clear();
  caller_done_.reset();
  start_ = std::make_unique<tbb::flow::broadcast_node<continue_msg>>(graph_);
  // The caller's system and its ancestors are run by the calling thread, not by nodes of the flow graph.
  std::vector<bool> by_caller(systems_.size(), false);
  if (caller_) {
    by_caller[*caller_] = true;
    for (std::size_t index : caller_first_) by_caller[index] = true;
    caller_done_ = std::make_unique<tbb::flow::broadcast_node<continue_msg>>(graph_);
  }
  for (std::size_t index = 0; index < systems_.size(); ++index) {
    if (by_caller[index]) {
      nodes_.push_back(nullptr);
      continue;
    }
    nodes_.push_back(std::make_unique<tbb::flow::continue_node<continue_msg>>(
        graph_, [this, index](const continue_msg&) { run_system(index); }));
  }
  std::vector<bool> has_predecessor(systems_.size(), false);
  for (const auto& edge : edges_) {
    const std::size_t from = edge.first, to = edge.second;
    if (by_caller[to]) continue;  // into the caller's chain: the calling thread runs it in order
    if (caller_ && from == *caller_) {
      tbb::flow::make_edge(*caller_done_, *nodes_[to]);
    } else if (by_caller[from]) {
      continue;  // from an ancestor of the caller's system: done before the graph starts
    } else {
      tbb::flow::make_edge(*nodes_[from], *nodes_[to]);
    }
    has_predecessor[to] = true;
  }
  for (std::size_t index = 0; index < systems_.size(); ++index)
    if (!by_caller[index] && !has_predecessor[index]) tbb::flow::make_edge(*start_, *nodes_[index]);
}

void Scheduler::run_in_list_order() {
  std::vector<std::pair<std::pair<std::size_t, std::size_t>, std::string>> edges;
  for (std::size_t e = 0; e < edges_.size(); ++e) edges.emplace_back(edges_[e], edge_reasons_[e]);
  for (std::size_t index = 1; index < systems_.size(); ++index) {
    const std::pair<std::size_t, std::size_t> edge{index - 1, index};
    if (std::find(edges_.begin(), edges_.end(), edge) == edges_.end()) edges.emplace_back(edge, "list order");
  }
  std::sort(edges.begin(), edges.end());
  edges_.clear();
  edge_reasons_.clear();
  for (auto& [edge, why] : edges) {
    edges_.push_back(edge);
    edge_reasons_.push_back(std::move(why));
  }
  check_acyclic();  // the list order never closes a cycle; this refreshes the successors
  build_graph();
}

void Scheduler::run_on_caller(std::string_view name) {
  const std::optional<std::size_t> found = find(name);
  if (!found) throw SchedulerError("graph '" + name_ + "' has no system '" + std::string(name) + "' to run");
  caller_ = *found;
  // Ancestors in an order that respects the edges: depth-first, predecessors first.
  std::vector<std::vector<std::size_t>> predecessors(systems_.size());
  for (const auto& edge : edges_) predecessors[edge.second].push_back(edge.first);
  std::vector<char> state(systems_.size(), 0);
  caller_first_.clear();
  std::function<void(std::size_t)> visit = [&](std::size_t node) {
    state[node] = 1;
    for (std::size_t before : predecessors[node])
      if (state[before] == 0) visit(before);
    if (node != *caller_) caller_first_.push_back(node);
  };
  visit(*caller_);
  build_graph();
}

void Scheduler::run(double time, double dt) {
  if (systems_.empty()) return;
  time_ = time;
  dt_ = dt;
  if (caller_) {
    for (std::size_t index : caller_first_) run_system(index);  // nothing else has started: a throw just leaves
    start_->try_put(tbb::flow::continue_msg());
    try {
      run_system(*caller_);
    } catch (...) {
      // Never leave the graph running on a world that is being unwound: the systems not started are skipped.
      graph_.cancel();
      try {
        graph_.wait_for_all();
      } catch (...) {
      }
      graph_.reset();
      throw;
    }
    caller_done_->try_put(tbb::flow::continue_msg());
  } else {
    start_->try_put(tbb::flow::continue_msg());
  }
  try {
    graph_.wait_for_all();  // returns, or rethrows, only once no node is running
  } catch (...) {
    graph_.reset();  // leave the graph usable; the caller decides whether to go on
    throw;
  }
  for (std::size_t k = 0; k < spans_.size(); ++k) {
    const PhaseRange& phase = phases_[span_phase_[k]];
    Clock::time_point first = started_[phase.begin], last = finished_[phase.begin];
    for (std::size_t index = phase.begin; index < phase.end; ++index) {
      first = std::min(first, started_[index]);
      last = std::max(last, finished_[index]);
    }
    // Counted once the earlier phases are done: a system that starts beside them (a check that needs only the
    // fluid, beside the grains' loop) is not charged to its phase until then.
    for (std::size_t index = 0; index < phase.begin; ++index) first = std::max(first, finished_[index]);
    spans_[k].add(std::max(0.0, std::chrono::duration<double>(last - first).count()), 1);
  }
}

std::optional<std::size_t> Scheduler::find(std::string_view name) const {
  for (std::size_t index = 0; index < systems_.size(); ++index)
    if (systems_[index]->name() == name) return index;
  return std::nullopt;
}

bool Scheduler::has_path(std::size_t from, std::size_t to) const {
  std::vector<bool> seen(systems_.size(), false);
  std::vector<std::size_t> pending{from};
  while (!pending.empty()) {
    const std::size_t node = pending.back();
    pending.pop_back();
    for (std::size_t next : successors_[node]) {
      if (next == to) return true;
      if (!seen[next]) {
        seen[next] = true;
        pending.push_back(next);
      }
    }
  }
  return false;
}

std::vector<std::string> Scheduler::edge_names() const {
  std::vector<std::string> names;
  for (auto [from, to] : edges_)
    names.push_back(std::string(systems_[from]->name()) + " -> " + std::string(systems_[to]->name()));
  return names;
}

void Scheduler::append_dot_body(std::string& out, const std::string& indent) const {
  // Sorted by name: the golden file changes when the graph does, not when the registry lists systems differently.
  std::vector<std::size_t> order(systems_.size());
  for (std::size_t index = 0; index < order.size(); ++index) order[index] = index;
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return systems_[a]->name() < systems_[b]->name(); });
  const bool phased = phases_.size() > 1;
  for (std::size_t index : order) {
    const System& system = *systems_[index];
    const std::vector<InnerGraph> inner = system.inner_graphs();
    std::string attributes;
    if (phased) attributes += "label=\"" + std::string(system.name()) + "\\n" + phase_of(index) + "\"";
    if (!inner.empty()) attributes += std::string(attributes.empty() ? "" : ", ") + "shape=box";
    out += indent + quoted(system.name()) + (attributes.empty() ? "" : " [" + attributes + "]") + ";\n";
    if (inner.empty()) continue;
    out += indent + "subgraph " + quoted("cluster_" + std::string(system.name())) + " {\n";
    out += indent + "  label=" + quoted(std::string(system.name()) + ": inner graphs, in turn") + ";\n";
    for (const InnerGraph& graph : inner) {
      out += indent + "  subgraph " + quoted("cluster_" + graph.graph->name()) + " {\n";
      out += indent + "    label=" + quoted(graph.graph->name() + " (" + std::string(graph.runs) + ")") + ";\n";
      graph.graph->append_dot_body(out, indent + "    ");
      out += indent + "  }\n";
    }
    out += indent + "}\n";
  }
  std::vector<std::size_t> edge_order(edges_.size());
  for (std::size_t k = 0; k < edge_order.size(); ++k) edge_order[k] = k;
  const auto edge_key = [&](std::size_t k) {
    return std::make_pair(systems_[edges_[k].first]->name(), systems_[edges_[k].second]->name());
  };
  std::sort(edge_order.begin(), edge_order.end(), [&](std::size_t a, std::size_t b) { return edge_key(a) < edge_key(b); });
  for (std::size_t k : edge_order)
    out += indent + quoted(systems_[edges_[k].first]->name()) + " -> " + quoted(systems_[edges_[k].second]->name()) +
           " [label=" + quoted(edge_reasons_[k]) + "];\n";
}

std::string Scheduler::dot() const {
  std::string out = "digraph " + quoted(name_) + " {\n";
  append_dot_body(out, "  ");
  return out + "}\n";
}

std::vector<ComponentId> Scheduler::components() const {
  std::vector<ComponentId> used;
  for (const Access& access : access_)
    for (const auto* list : {&access.reads, &access.writes})
      for (const ComponentId component : *list)
        if (std::find(used.begin(), used.end(), component) == used.end()) used.push_back(component);
  return used;
}

Access Scheduler::access() const {
  Access all;
  for (const Access& access : access_)
    for (const ComponentId component : access.writes)
      if (!all.writes_component(component)) all.writes.push_back(component);
  for (const Access& access : access_)
    for (const ComponentId component : access.reads)
      if (!all.writes_component(component) && !all.reads_component(component)) all.reads.push_back(component);
  return all;
}

}  // namespace riffle
