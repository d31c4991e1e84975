#pragma once
// A System does one job over the World's components. It declares what it reads and writes; the scheduler orders
// systems from those declarations, and the SystemContext refuses any access that was not declared.
#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "components/component_id.hpp"
#include "components/model.hpp"
#include "components/world.hpp"

namespace riffle {

struct Access {
  std::vector<ComponentId> reads;   ///< read-only
  std::vector<ComponentId> writes;  ///< read-write
  bool reads_component(ComponentId id) const;
  bool writes_component(ComponentId id) const;
};

/// Raised when a system touches a component it did not declare; surfaces from Scheduler::run.
class UndeclaredAccess : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

class System;
class Scheduler;

/// A graph that a composite node runs inside itself, and how often ("once", "once per sub-step").
struct InnerGraph {
  const Scheduler* graph;
  std::string_view runs;
};

/// What a system sees while it runs: the model, the clock of this (sub)step, and checked component access.
class SystemContext {
 public:
  SystemContext(World& world, const Model& model, const System& system, const Access& access, double time,
                double dt)
      : model(model), time(time), dt(dt), world_(world), system_(system), access_(access) {}

  const Model& model;
  const double time;  ///< [s] time at the start of this (sub)step
  const double dt;    ///< [s] length of this (sub)step

  template <class C>
  const C& read() const {
    if (!access_.reads_component(C::kId) && !access_.writes_component(C::kId)) fail("reads", C::kId);
    return checked(world_.find<C>(), C::kId);
  }

  template <class C>
  C& write() {
    if (!access_.writes_component(C::kId)) fail("writes", C::kId);
    return checked(world_.find<C>(), C::kId);
  }

  /// World clock (step count) for systems that act every N steps.
  std::uint64_t step() const { return world_.step; }

  /// [s] Length of the engine (fluid) step this run belongs to, as decide_step_lengths chose it (run.dt shortened by
  /// the Courant, diffusion or drag limit); `fallback` before the first step (the initial forces).
  double fluid_step(double fallback) const { return world_.last_step.dt > 0.0 ? world_.last_step.dt : fallback; }

  /// Entities processed by this run, for the particles-per-second column of the timing table.
  void count_items(std::size_t items) { items_ += items; }
  std::size_t items() const { return items_; }

 private:
  [[noreturn]] void fail(const char* verb, ComponentId id) const;
  template <class C>
  C& checked(C* component, ComponentId id) const {
    if (!component) missing(id);
    return *component;
  }
  [[noreturn]] void missing(ComponentId id) const;

  World& world_;
  const System& system_;
  const Access& access_;
  std::size_t items_ = 0;
};

class System {
 public:
  virtual ~System() = default;
  /// Unique, snake_case; used in timings, logs and the graph dump.
  virtual std::string_view name() const = 0;
  virtual Access access() const = 0;
  /// Names of systems that must finish first even if no data links them (a sync point). Usually empty.
  virtual std::vector<std::string> run_after() const { return {}; }
  virtual void run(SystemContext& context) = 0;
  /// The graphs a composite node runs inside itself (the grains' sub-step loop), for the graph dump. Usually none.
  virtual std::vector<InnerGraph> inner_graphs() const { return {}; }
};

}  // namespace riffle
