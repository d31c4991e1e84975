// The scheduler: edges from declared access, ordering, concurrency, and refusal of bad graphs.
#include <doctest/doctest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <functional>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "engine/setup/initial_state.hpp"
#include "engine/scene/scene.hpp"
#include "engine/core/scheduler.hpp"
#include "engine/core/substep_loop.hpp"
#include "engine/run/stepper.hpp"
#include "engine/run/registry.hpp"
#include "tests/support/test_support.hpp"
#include "tests/support/scene_builder.hpp"

using namespace riffle;
using riffle::test::SceneBuilder;

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

TEST_CASE("the default pipeline's step graph has exactly the pinned edges") {
  Model model = test::small_model();
  World world = initial_world(model);
  Stepper stepper(build_pipeline(model), world, model);
  REQUIRE(stepper.substep_loop() != nullptr);
  CHECK(stepper.substep_loop()->once().empty());
  CHECK(stepper.substep_loop()->repeated().edge_names() ==
        std::vector<std::string>{"solid_kick_drift -> solid_kick"});
  std::vector<std::string> edges = stepper.step_graph().edge_names();
  std::sort(edges.begin(), edges.end());
  // solid_substeps -> solid_cell_sort: the sort rewrites roles (the force roles) that the loop wrote and no check
  // reads, so the writer-writer rule orders them directly as well as through the checks.
  CHECK(edges == std::vector<std::string>{"solid_domain_check -> solid_cell_sort", "solid_substeps -> solid_cell_sort",
                                          "solid_substeps -> solid_domain_check", "solid_substeps -> solid_summary",
                                          "solid_summary -> solid_cell_sort"});
  CHECK_FALSE(stepper.concurrent_branches());  // no fluid
}

TEST_CASE("a scene without solids schedules no solid system") {
  Model model = test::small_model();
  model.solids = SolidsModel{};
  World world = initial_world(model);
  CHECK_FALSE(world.solids.has_value());
  Stepper stepper(build_pipeline(model), world, model);
  CHECK(stepper.substep_loop() == nullptr);
  REQUIRE(stepper.step_graph().size() == 1);
  CHECK(stepper.step_graph().system(0).name() == "wall_motion");
  CHECK(stepper.step_graph().phase_of(0) == "step");
}

TEST_CASE("a coupled scene's fluid systems and the grains' sub-step loop share no component and run side by side") {
  // docs/COUPLING.md: the coupling is staggered by one fluid step, so the exchange happens through the step-start
  // copy and the end-of-step systems.
  const Model model = parse_scene(SceneBuilder().run({.end_time = 0.01, .dt = 1.0e-3, .solid_substeps = 10})
      .material("grain", {.density = 1318.0}).material("glass", {.density = 2500.0})
      .tank({.size = {0.05, 0.05, 0.05}, .open_faces = {"z_max"}, .wall_material = "glass"})
      .sphere({.position = {0.025, 0.025, 0.02}, .radius = 0.003, .material = "grain"}).fluid({.spacing = 0.005})
      .fluid_box({0.0, 0.0, 0.0}, {0.05, 0.05, 0.03}).toml(), "coupled.toml");
  World world = initial_world(model);
  Stepper stepper(build_pipeline(model), world, model);
  CHECK(stepper.concurrent_branches());
  const Scheduler& graph = stepper.step_graph();
  const std::optional<std::size_t> loop = graph.find(Stepper::kLoopName);
  REQUIRE(loop);
  // The scheduler, not the stepper, finds it: no path joins any fluid system to the loop, and the loop touches
  // nothing the fluid's systems touch.
  const std::vector<ComponentId> grains = stepper.substep_loop()->once().components();
  std::size_t fluid_systems = 0;
  for (std::size_t index = 0; index < graph.size(); ++index) {
    if (graph.phase_of(index) != "step") continue;
    ++fluid_systems;
    CHECK_FALSE(graph.has_path(index, *loop));
    CHECK_FALSE(graph.has_path(*loop, index));
  }
  CHECK(fluid_systems == 8);
  // The grains sample a copy of the water taken first in the step, first thing in their loop.
  REQUIRE(graph.find("fluid_sample_copy"));
  CHECK(graph.phase_of(*graph.find("fluid_sample_copy")) == "step_start");
  CHECK(graph.has_path(*graph.find("fluid_sample_copy"), *loop));
  // Then what the drag keeps over the step and the history force (on by default with added mass and the
  // undisturbed slip), from the water just sampled.
  const auto& once = stepper.substep_loop()->once();
  REQUIRE(once.size() == 3);
  CHECK(once.system(0).name() == "solid_fluid_sampling");
  std::vector<std::string> after_sampling{std::string(once.system(1).name()), std::string(once.system(2).name())};
  std::sort(after_sampling.begin(), after_sampling.end());
  CHECK(after_sampling == std::vector<std::string>{"solid_drag_law", "solid_history_force"});
  CHECK(once.has_path(0, 1));
  CHECK(once.has_path(0, 2));
  const std::vector<std::string> edges = graph.edge_names();
  const auto has = [&](const std::string& edge) { return std::find(edges.begin(), edges.end(), edge) != edges.end(); };
  // The voidage at the grains' new positions comes first, then the drag impulse goes back divided by it.
  CHECK(has("solid_substeps -> solid_voidage"));
  CHECK(has("solid_voidage -> fluid_drag_reaction"));
  // The fluid's checks need only the fluid: they may start while the grains still step.
  CHECK_FALSE(graph.has_path(*loop, *graph.find("fluid_checks")));
  // The fluid's systems keep the registry's order: the neighbour search first, the cell sort right before the
  // search at r*.
  CHECK(graph.has_path(*graph.find("fluid_neighbours"), *graph.find("fluid_cell_sort")));
  CHECK(has("fluid_cell_sort -> fluid_neighbours_predicted"));
  for (int step = 0; step < 3; ++step) stepper.step();
  CHECK(world.step_status.ok());
  for (const SystemTimer& branch : stepper.branch_timers()) CHECK(branch.calls == 3);
  // 10 sub-steps a step at run.dt: the loop's timer counts them.
  CHECK(stepper.branch_timers()[1].items == 30);
  CHECK(world.last_step.substeps == 10);
}

namespace {

constexpr ComponentId kFluidId = component_id<TankMotion>;  // stands in for the fluid's component in a dry world
constexpr ComponentId kSummaryId = component_id<SolidSummary>;

/// A step graph of the stepper's shape from probes: a "fluid" chain over `fluid_component`, then a sub-step loop
/// (a once graph and a repeated one over solids and walls), then an end-of-step reader of both.
struct ProbeStep {
  std::atomic<int> fluid_runs{0}, once_runs{0}, substep_runs{0}, end_runs{0};
  std::vector<double> substep_times;
  std::int64_t substeps = 3;
  bool stop = false;
  int throw_at_substep = -1;  ///< the sub-step whose push_grains throws; -1: none
  std::unique_ptr<Scheduler> graph;

  ProbeStep(World& world, const Model& model, ComponentId fluid_component) {
    std::vector<Scheduler::Phase> phases;
    phases.push_back({"step", systems_of({ProbeSystem("fluid_a", {{}, {fluid_component}}, count(fluid_runs)),
                                          ProbeSystem("fluid_b", {{fluid_component}, {kSummaryId}},
                                                      count(fluid_runs))})});
    auto once = std::make_unique<Scheduler>(
        "solid_step", systems_of({ProbeSystem("sample", {{}, {kSolidsId}}, count(once_runs))}), world, model);
    auto repeated = std::make_unique<Scheduler>(
        "substep",
        systems_of({ProbeSystem("move_walls", {{}, {kWallsId}}, count(substep_runs)),
                    ProbeSystem("push_grains", {{kWallsId}, {kSolidsId}},
                                [this](SystemContext& context) {
                                  if (static_cast<int>(substep_times.size()) == throw_at_substep)
                                    throw std::runtime_error("a grain blew up");
                                  substep_times.push_back(context.time);
                                })}),
        world, model);
    std::vector<std::unique_ptr<System>> loop;
    loop.push_back(std::make_unique<SubstepLoop>(
        "loop", std::move(once), std::move(repeated), [this] { return SubstepLoop::Plan{substeps, 0.25}; },
        [this] { return stop; }));
    phases.push_back({"grains", std::move(loop)});
    phases.push_back(
        {"end_of_step", systems_of({ProbeSystem("check", {{kSolidsId, kSummaryId}, {kStatusId}}, count(end_runs))})});
    graph = std::make_unique<Scheduler>("step", std::move(phases), world, model);
    graph->run_on_caller("loop");  // as the stepper runs its loop
  }

  static std::function<void(SystemContext&)> count(std::atomic<int>& runs) {
    return [&runs](SystemContext&) { runs.fetch_add(1); };
  }
  std::size_t at(const char* name) const { return *graph->find(name); }
};

}  // namespace

TEST_CASE("one step graph: a fluid branch and a sub-step loop with disjoint access get no path between them") {
  const Model model = test::small_model();
  World world = initial_world(model);
  ProbeStep step(world, model, kFluidId);
  const Scheduler& graph = *step.graph;
  // The loop declares the union of its inner graphs' access: solids and walls written, nothing only read.
  const Access loop = graph.system(step.at("loop")).access();
  CHECK(loop.writes == std::vector<ComponentId>{kSolidsId, kWallsId});
  CHECK(loop.reads.empty());
  CHECK_FALSE(graph.has_path(step.at("fluid_a"), step.at("loop")));
  CHECK_FALSE(graph.has_path(step.at("fluid_b"), step.at("loop")));
  CHECK_FALSE(graph.has_path(step.at("loop"), step.at("fluid_a")));
  std::vector<std::string> edges = graph.edge_names();
  std::sort(edges.begin(), edges.end());
  CHECK(edges == std::vector<std::string>{"fluid_a -> fluid_b", "fluid_b -> check", "loop -> check"});
  CHECK(graph.edge_reasons() == std::vector<std::string>{"tank_motion", "solid_summary", "grain_state"});

  step.graph->run(1.0, 0.75);
  CHECK(step.fluid_runs == 2);
  CHECK(step.once_runs == 1);
  CHECK(step.substep_runs == 3);
  CHECK(step.end_runs == 1);
  // Sub-step k starts at the step's start plus k sub-steps.
  CHECK(step.substep_times == std::vector<double>{1.0, 1.25, 1.5});
  // Each phase's span is timed once per run.
  REQUIRE(graph.phase_spans().size() == 3);
  for (const SystemTimer& span : graph.phase_spans()) CHECK(span.calls == 1);
}

TEST_CASE("one step graph: a component the fluid branch and the loop both write serialises them in list order") {
  const Model model = test::small_model();
  World world = initial_world(model);
  ProbeStep step(world, model, kWallsId);  // the "fluid" now writes the walls the sub-steps move
  const Scheduler& graph = *step.graph;
  CHECK(graph.has_path(step.at("fluid_a"), step.at("loop")));
  std::vector<std::string> edges = graph.edge_names();
  const auto has = [&](const std::string& edge) { return std::find(edges.begin(), edges.end(), edge) != edges.end(); };
  // fluid_a writes the walls, fluid_b reads them, then the loop writes them: reader before the next writer.
  CHECK(has("fluid_b -> loop"));
  CHECK_FALSE(has("fluid_a -> loop"));
}

TEST_CASE("a loop told to stop abandons the step: the systems after it do not run, and the graph stays usable") {
  const Model model = test::small_model();
  World world = initial_world(model);
  ProbeStep step(world, model, kFluidId);
  step.stop = true;
  CHECK_THROWS_AS(step.graph->run(0.0, 1.0), StepAbandoned);
  CHECK(step.substep_runs == 0);
  CHECK(step.end_runs == 0);
  const auto* loop = dynamic_cast<const SubstepLoop*>(&step.graph->system(step.at("loop")));
  REQUIRE(loop != nullptr);
  CHECK(loop->timer().calls == 1);  // an abandoned loop is still timed, with no sub-step done
  CHECK(loop->timer().items == 0);
  step.stop = false;
  step.graph->run(0.0, 1.0);
  CHECK(step.substep_runs == 3);
  CHECK(step.end_runs == 1);
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

TEST_CASE("an exception inside a sub-step surfaces from the step graph, and the next run is whole") {
  const Model model = test::small_model();
  World world = initial_world(model);
  ProbeStep step(world, model, kFluidId);
  step.throw_at_substep = 1;
  CHECK_THROWS_WITH_AS(step.graph->run(0.0, 1.0), "a grain blew up", std::runtime_error);
  CHECK(step.substep_times.size() == 1);  // the loop stopped at the failing sub-step
  CHECK(step.end_runs == 0);              // what waits for the loop never started
  // No cancellation is left behind in the inner graphs: every system of every sub-step runs next time.
  step.throw_at_substep = -1;
  step.substep_runs = 0;
  step.substep_times.clear();
  step.graph->run(0.0, 1.0);
  CHECK(step.substep_runs == 3);
  CHECK(step.substep_times.size() == 3);
  CHECK(step.end_runs == 1);
}
