#include "engine/core/scheduler.hpp"

#include <algorithm>
#include <map>
#include <set>

namespace riffle {

Scheduler::Scheduler(std::string phase, std::vector<std::unique_ptr<System>> systems, World& world,
                     const Model& model)
    : phase_(std::move(phase)), systems_(std::move(systems)), world_(world), model_(model) {
  std::set<std::string, std::less<>> names;
  for (const auto& system : systems_) {
    if (!names.insert(std::string(system->name())).second)
      throw SchedulerError("two systems are named '" + std::string(system->name()) + "'");
    access_.push_back(system->access());
    for (const auto* list : {&access_.back().reads, &access_.back().writes})
      for (ComponentId id : *list)
        if (!world_.has(id))
          throw SchedulerError("system '" + std::string(system->name()) + "' declares component '" +
                               std::string(component_name(id)) + "', which this scene does not have");
    timers_.push_back(SystemTimer{std::string(system->name()), phase_});
  }
  derive_edges();
  check_acyclic();
  build_graph();
}

void Scheduler::derive_edges() {
  std::set<std::pair<std::size_t, std::size_t>> edges;
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
      if (use.last_writer) edges.emplace(*use.last_writer, index);
      use.readers_since_write.push_back(index);
    }
    for (ComponentId id : access.writes) {
      Usage& use = usage[id];
      if (!use.readers_since_write.empty()) {
        for (std::size_t reader : use.readers_since_write) edges.emplace(reader, index);
      } else if (use.last_writer) {
        edges.emplace(*use.last_writer, index);
      }
      use.last_writer = index;
      use.readers_since_write.clear();
    }
  }
  for (std::size_t index = 0; index < systems_.size(); ++index) {
    for (const std::string& before : systems_[index]->run_after()) {
      auto found = std::find_if(systems_.begin(), systems_.end(),
                                [&](const auto& system) { return system->name() == before; });
      if (found == systems_.end())
        throw SchedulerError("system '" + std::string(systems_[index]->name()) + "' runs after '" + before +
                             "', which is not scheduled in phase '" + phase_ + "'");
      edges.emplace(static_cast<std::size_t>(found - systems_.begin()), index);
    }
  }
  edges_.assign(edges.begin(), edges.end());
}

void Scheduler::check_acyclic() const {
  // Depth-first search with colours; a grey node reached again closes a cycle.
  const std::size_t count = systems_.size();
  std::vector<std::vector<std::size_t>> successors(count);
  for (auto [from, to] : edges_) successors[from].push_back(to);
  std::vector<int> colour(count, 0);
  std::vector<std::size_t> path;
  std::function<void(std::size_t)> visit = [&](std::size_t node) {
    colour[node] = 1;
    path.push_back(node);
    for (std::size_t next : successors[node]) {
      if (colour[next] == 1) {
        std::string cycle;
        auto start = std::find(path.begin(), path.end(), next);
        for (auto it = start; it != path.end(); ++it) cycle += std::string(systems_[*it]->name()) + " -> ";
        cycle += std::string(systems_[next]->name());
        throw SchedulerError("the systems of phase '" + phase_ + "' form a cycle: " + cycle);
      }
      if (colour[next] == 0) visit(next);
    }
    path.pop_back();
    colour[node] = 2;
  };
  for (std::size_t node = 0; node < count; ++node)
    if (colour[node] == 0) visit(node);
}

void Scheduler::build_graph() {
  using tbb::flow::continue_msg;
  start_ = std::make_unique<tbb::flow::broadcast_node<continue_msg>>(graph_);
  for (std::size_t index = 0; index < systems_.size(); ++index) {
    nodes_.push_back(std::make_unique<tbb::flow::continue_node<continue_msg>>(
        graph_, [this, index](const continue_msg&) {
          SystemContext context(world_, model_, *systems_[index], access_[index], time_, dt_);
          const auto start = Clock::now();
          systems_[index]->run(context);
          timers_[index].add(seconds_since(start), context.items());
        }));
  }
  std::vector<bool> has_predecessor(systems_.size(), false);
  for (auto [from, to] : edges_) {
    tbb::flow::make_edge(*nodes_[from], *nodes_[to]);
    has_predecessor[to] = true;
  }
  for (std::size_t index = 0; index < systems_.size(); ++index)
    if (!has_predecessor[index]) tbb::flow::make_edge(*start_, *nodes_[index]);
}

void Scheduler::run(double time, double dt) {
  if (systems_.empty()) return;
  time_ = time;
  dt_ = dt;
  start_->try_put(tbb::flow::continue_msg());
  try {
    graph_.wait_for_all();
  } catch (...) {
    graph_.reset();  // leave the graph usable; the caller decides whether to go on
    throw;
  }
}

std::vector<std::string> Scheduler::edge_names() const {
  std::vector<std::string> names;
  for (auto [from, to] : edges_)
    names.push_back(std::string(systems_[from]->name()) + " -> " + std::string(systems_[to]->name()));
  return names;
}

std::string Scheduler::dot() const {
  std::string out = "digraph " + phase_ + " {\n";
  for (const auto& system : systems_) out += "  \"" + std::string(system->name()) + "\";\n";
  for (auto [from, to] : edges_)
    out += "  \"" + std::string(systems_[from]->name()) + "\" -> \"" + std::string(systems_[to]->name()) + "\";\n";
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

}  // namespace riffle
