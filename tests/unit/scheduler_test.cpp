// The scheduler: edges from declared access, ordering, concurrency, and refusal of bad graphs.
#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <functional>
#include <mutex>
#include <thread>

#include "engine/setup/initial_state.hpp"
#include "engine/scene/scene.hpp"
#include "engine/core/scheduler.hpp"
#include "engine/run/stepper.hpp"
#include "engine/run/registry.hpp"
#include "tests/test_support.hpp"

using namespace riffle;

namespace {

/// A system whose access and body are given by the test.
class ProbeSystem final : public System {
 public:
  ProbeSystem(std::string name, Access access, std::function<void(SystemContext&)> body,
              std::vector<std::string> after = {})
      : name_(std::move(name)), access_(std::move(access)), body_(std::move(body)), after_(std::move(after)) {}
  std::string_view name() const override { return name_; }
  Access access() const override { return access_; }
  std::vector<std::string> run_after() const override { return after_; }
  void run(SystemContext& context) override { body_(context); }

 private:
  std::string name_;
  Access access_;
  std::function<void(SystemContext&)> body_;
  std::vector<std::string> after_;
};

constexpr ComponentId kSolidsId = component_id<GrainState>;
constexpr ComponentId kWallsId = component_id<Walls>;
constexpr ComponentId kStatusId = component_id<StepStatus>;

std::vector<std::unique_ptr<System>> systems_of(std::vector<ProbeSystem> probes) {
  std::vector<std::unique_ptr<System>> systems;
  for (auto& probe : probes) systems.push_back(std::make_unique<ProbeSystem>(std::move(probe)));
  return systems;
}

void nothing(SystemContext&) {}

}  // namespace

TEST_CASE("scheduler derives writer-reader, reader-writer and writer-writer edges in declared order") {
  const Model model = test::small_model();
  World world = initial_world(model);
  Scheduler scheduler("test",
                      systems_of({
                          ProbeSystem("write_solids", {{}, {kSolidsId}}, nothing),
                          ProbeSystem("read_solids_a", {{kSolidsId}, {}}, nothing),
                          ProbeSystem("read_solids_b", {{kSolidsId}, {kStatusId}}, nothing),
                          ProbeSystem("write_walls", {{}, {kWallsId}}, nothing),
                          ProbeSystem("rewrite_solids", {{kWallsId}, {kSolidsId}}, nothing),
                          ProbeSystem("write_solids_again", {{}, {kSolidsId}}, nothing),
                      }),
                      world, model);
  const std::vector<std::string> expected = {
      "write_solids -> read_solids_a",       // writer -> reader
      "write_solids -> read_solids_b",       // writer -> reader
      "read_solids_a -> rewrite_solids",     // reader -> next writer
      "read_solids_b -> rewrite_solids",     // reader -> next writer
      "write_walls -> rewrite_solids",       // writer -> reader of walls
      "rewrite_solids -> write_solids_again" // writer -> next writer with no reader between
  };
  std::vector<std::string> names = scheduler.edge_names();
  std::sort(names.begin(), names.end());
  std::vector<std::string> sorted_expected = expected;
  std::sort(sorted_expected.begin(), sorted_expected.end());
  CHECK(names == sorted_expected);
  CHECK(scheduler.dot().find("\"write_walls\" -> \"rewrite_solids\"") != std::string::npos);
}

TEST_CASE("the default pipeline's graphs have exactly the pinned edges") {
  Model model = test::small_model();
  World world = initial_world(model);
  Stepper stepper(build_pipeline(model), world, model);
  CHECK(stepper.step_graph().empty());
  CHECK(stepper.substep_graph().edge_names() == std::vector<std::string>{"solid_kick_drift -> solid_kick"});
  std::vector<std::string> end_edges = stepper.end_of_step_graph().edge_names();
  std::sort(end_edges.begin(), end_edges.end());
  CHECK(end_edges == std::vector<std::string>{"solid_domain_check -> solid_cell_sort",
                                              "solid_summary -> solid_cell_sort"});
}

TEST_CASE("a scene without solids schedules no solid system") {
  Model model = test::small_model();
  model.solids = SolidsModel{};
  World world = initial_world(model);
  CHECK_FALSE(world.solids.has_value());
  Stepper stepper(build_pipeline(model), world, model);
  CHECK(stepper.substep_graph().empty());
  CHECK(stepper.end_of_step_graph().empty());
  REQUIRE(stepper.step_graph().size() == 1);
  CHECK(stepper.step_graph().system(0).name() == "wall_motion");
}

TEST_CASE("a coupled scene's fluid step graph and grain sub-steps share no component and run side by side") {
  // docs/COUPLING.md: the coupling is staggered by one fluid step, so the exchange happens through the step-start
  // copy and the end-of-step graph.
  const Model model = parse_scene(R"(
[run]
end_time = 0.01
dt = 1.0e-3
solid_substeps = 10
[materials.grain]
density = 1318.0
[materials.glass]
density = 2500.0
[tank]
size = [0.05, 0.05, 0.05]
open_faces = ["z_max"]
wall_material = "glass"
[solids]
[[solids.spheres]]
position = [0.025, 0.025, 0.02]
radius = 0.003
material = "grain"
[fluid]
spacing = 0.005
[[fluid.boxes]]
low = [0.0, 0.0, 0.0]
high = [0.05, 0.05, 0.03]
)", "coupled.toml");
  World world = initial_world(model);
  Stepper stepper(build_pipeline(model), world, model);
  CHECK(stepper.concurrent_branches());
  // The grains' branch (its once-a-step graph, then the sub-steps) touches nothing the fluid's step graph touches.
  std::vector<ComponentId> solid_side = stepper.substep_graph().components();
  for (const ComponentId component : stepper.solid_step_graph().components()) solid_side.push_back(component);
  for (const ComponentId component : stepper.step_graph().components())
    CHECK(std::find(solid_side.begin(), solid_side.end(), component) == solid_side.end());
  // The grains sample a copy of the water taken before the branches start, first thing in their branch.
  REQUIRE(stepper.step_start_graph().size() == 1);
  CHECK(stepper.step_start_graph().system(0).name() == "fluid_sample_copy");
  REQUIRE(stepper.solid_step_graph().size() == 1);
  CHECK(stepper.solid_step_graph().system(0).name() == "solid_fluid_sampling");
  std::vector<std::string> end_edges = stepper.end_of_step_graph().edge_names();
  const auto has = [&](const std::string& edge) {
    return std::find(end_edges.begin(), end_edges.end(), edge) != end_edges.end();
  };
  // The voidage at the grains' new positions comes first, then the drag impulse goes back divided by it.
  CHECK(has("solid_voidage -> fluid_drag_reaction"));
  // The step graph opens with the neighbour search; the cell sort runs right before the search at r*.
  CHECK(stepper.step_graph().system(0).name() == "fluid_neighbours");
  CHECK(stepper.step_graph().system(3).name() == "fluid_cell_sort");
  CHECK(stepper.step_graph().system(4).name() == "fluid_neighbours_predicted");
  for (int step = 0; step < 3; ++step) stepper.step();
  CHECK(world.step_status.ok());
  for (const SystemTimer& branch : stepper.branch_timers()) CHECK(branch.calls == 3);
}

TEST_CASE("dependent systems always run in declared order") {
  const Model model = test::small_model();
  World world = initial_world(model);
  std::mutex mutex;
  std::vector<std::string> order;
  auto record = [&](const char* name) {
    return [&, name](SystemContext&) {
      std::this_thread::sleep_for(std::chrono::microseconds(50));
      std::lock_guard lock(mutex);
      order.push_back(name);
    };
  };
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 2);
  Scheduler scheduler("test",
                      systems_of({ProbeSystem("first", {{}, {kSolidsId}}, record("first")),
                                  ProbeSystem("second", {{kSolidsId}, {kWallsId}}, record("second")),
                                  ProbeSystem("third", {{kWallsId}, {}}, record("third"))}),
                      world, model);
  for (int repeat = 0; repeat < 50; ++repeat) {
    order.clear();
    scheduler.run(0.0, 1e-3);
    REQUIRE(order == std::vector<std::string>{"first", "second", "third"});
  }
  for (const SystemTimer& timer : scheduler.timers()) CHECK(timer.calls == 50);
}

TEST_CASE("independent systems overlap in time when two threads are allowed") {
  const Model model = test::small_model();
  World world = initial_world(model);
  std::atomic<int> arrived{0};
  std::atomic<int> saw_partner{0};
  // Each waits (bounded) for the other to arrive: both arriving proves they ran at the same time.
  auto rendezvous = [&](SystemContext&) {
    arrived.fetch_add(1);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    while (arrived.load() < 2 && std::chrono::steady_clock::now() < deadline) std::this_thread::yield();
    if (arrived.load() >= 2) saw_partner.fetch_add(1);
  };
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 2);
  Scheduler scheduler("test",
                      systems_of({ProbeSystem("reads_solids", {{kSolidsId}, {}}, rendezvous),
                                  ProbeSystem("writes_walls", {{}, {kWallsId}}, rendezvous)}),
                      world, model);
  CHECK(scheduler.edges().empty());
  scheduler.run(0.0, 1e-3);
  CHECK(saw_partner.load() == 2);
}

TEST_CASE("an undeclared write or read is an error raised from run") {
  const Model model = test::small_model();
  World world = initial_world(model);
  SUBCASE("write of a component declared read-only") {
    Scheduler scheduler("test",
                        systems_of({ProbeSystem("sneaky_writer", {{kSolidsId}, {}},
                                                [](SystemContext& context) { context.write<GrainState>(); })}),
                        world, model);
    CHECK_THROWS_WITH_AS(scheduler.run(0.0, 1e-3),
                         "system 'sneaky_writer' writes component 'grain_state' without declaring it", UndeclaredAccess);
  }
  SUBCASE("write of another role of the same entities") {
    // Writing the grains' state does not let a system write their drag: roles are separate components.
    Scheduler scheduler("test",
                        systems_of({ProbeSystem("role_crosser", {{}, {kSolidsId}},
                                                [](SystemContext& context) { context.write<GrainDrag>(); })}),
                        world, model);
    CHECK_THROWS_WITH_AS(scheduler.run(0.0, 1e-3),
                         "system 'role_crosser' writes component 'grain_drag' without declaring it", UndeclaredAccess);
  }
  SUBCASE("read of a component not declared at all") {
    Scheduler scheduler("test",
                        systems_of({ProbeSystem("sneaky_reader", {{}, {kWallsId}},
                                                [](SystemContext& context) { context.read<GrainState>(); })}),
                        world, model);
    CHECK_THROWS_AS(scheduler.run(0.0, 1e-3), UndeclaredAccess);
    // The graph stays usable after a failed run.
    CHECK_THROWS_AS(scheduler.run(0.0, 1e-3), UndeclaredAccess);
  }
}

TEST_CASE("cycles, duplicate names, unknown run_after and missing components are refused") {
  Model model = test::small_model();
  World world = initial_world(model);
  SUBCASE("cycle through an explicit run_after") {
    // Data order says a -> b; b is also asked to run before a.
    CHECK_THROWS_WITH_AS(Scheduler("test",
                                   systems_of({ProbeSystem("a", {{}, {kSolidsId}}, nothing, {"b"}),
                                               ProbeSystem("b", {{kSolidsId}, {}}, nothing)}),
                                   world, model),
                         doctest::Contains("form a cycle: a -> b -> a"), SchedulerError);
  }
  SUBCASE("duplicate names") {
    CHECK_THROWS_AS(Scheduler("test",
                              systems_of({ProbeSystem("same", {{kSolidsId}, {}}, nothing),
                                          ProbeSystem("same", {{kWallsId}, {}}, nothing)}),
                              world, model),
                    SchedulerError);
  }
  SUBCASE("run_after names a system that is not scheduled") {
    CHECK_THROWS_WITH_AS(
        Scheduler("test", systems_of({ProbeSystem("a", {{kSolidsId}, {}}, nothing, {"ghost"})}), world, model),
        doctest::Contains("'ghost'"), SchedulerError);
  }
  SUBCASE("a component the scene does not have") {
    world.solids.reset();
    CHECK_THROWS_WITH_AS(Scheduler("test", systems_of({ProbeSystem("a", {{kSolidsId}, {}}, nothing)}), world, model),
                         doctest::Contains("which this scene does not have"), SchedulerError);
  }
}
