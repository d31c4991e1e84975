// Engine benchmark: throughput of the free-flight pipeline (integrator, checks, reductions, cell sort) and the
// per-fire overhead of the flow graph, at a chosen thread count. Not a test: run it by hand or from
// tools/bench.sh, which records the results in docs/BENCHMARKS.md.
//
//   riffle_bench_engine [--grains N] [--steps S] [--threads T]
#include <spdlog/spdlog.h>
#include <tbb/global_control.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "engine/scene/scene.hpp"
#include "engine/run/simulation.hpp"

int main(int argc, char** argv) {
  long grains_per_side = 40;
  long steps = 200;
  int threads = 1;
  for (int k = 1; k + 1 < argc; k += 2) {
    if (!std::strcmp(argv[k], "--side")) grains_per_side = std::atol(argv[k + 1]);
    else if (!std::strcmp(argv[k], "--steps")) steps = std::atol(argv[k + 1]);
    else if (!std::strcmp(argv[k], "--threads")) threads = std::atoi(argv[k + 1]);
  }
  spdlog::set_level(spdlog::level::warn);
  const double spacing = 0.006;
  const double extent = spacing * static_cast<double>(grains_per_side - 1);
  char scene[2048];
  std::snprintf(scene, sizeof scene,
                "[run]\nend_time = 10.0\ndt = 1e-3\nsolid_substeps = 10\ngravity = [0.0, 0.0, 0.0]\n"
                "[materials.grain]\ndensity = 1318.0\n"
                "[tank]\nsize = [%.6f, %.6f, %.6f]\nwall_material = \"grain\"\n"
                "[tank.motion]\nkind = \"sinusoidal\"\namplitude = 0.01\nfrequency = 1.7\n"
                "[solids]\nsort_every = 20\n"
                "[[solids.blocks]]\nmin = [0.005, 0.005, 0.005]\nmax = [%.6f, %.6f, %.6f]\nspacing = %.6f\n"
                "radius = 0.0025\nmaterial = \"grain\"\nvelocity = [0.001, 0.0, 0.0]\n",
                extent + 0.01, extent + 0.01, extent + 0.01, extent + 0.005, extent + 0.005, extent + 0.005,
                spacing);
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  auto simulation = riffle::Simulation::from_model(riffle::parse_scene(scene, "bench_engine"));
  const std::size_t grains = simulation->world().solids->size();
  const auto start = riffle::Clock::now();
  for (long s = 0; s < steps; ++s) simulation->step();
  const double seconds = riffle::seconds_since(start);
  std::printf("grains %zu  steps %ld  substeps/step %lld  threads %d  wall %.3f s\n", grains, steps,
              static_cast<long long>(simulation->model().solid_substeps), threads, seconds);
  std::printf("%s", riffle::format_timing_table(simulation->stepper().timers(), seconds).c_str());
  return 0;
}
