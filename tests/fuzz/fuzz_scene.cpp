// libFuzzer harness over the scene reader: arbitrary text through parse_scene, whose budget check
// (engine/setup/budget.hpp) runs with a 64 MiB limit and at most 2000 grains; a scene it accepts and that is small is then
// built into its initial world (beds generated, laid out, neighbour lists, initial forces). Acceptable outcomes are a
// Model or a SceneError (from the reader, or from set-up for a bed that jams); any other exception, a crash, a hang or
// an allocation above libFuzzer's -malloc_limit_mb is a finding.
//
// Build and run (docs/RELIABILITY.md):
//   CC=clang CXX=clang++ cmake -B build-fuzz -G Ninja -DRIFFLE_FUZZ=ON -DRIFFLE_SANITIZE=ON
//       -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRIFFLE_BUILD_TESTS=OFF -DCMAKE_CXX_COMPILER_LAUNCHER=ccache
//   cmake --build build-fuzz --target riffle_fuzz_scene
//   mkdir -p /tmp/scene-corpus && build-fuzz/riffle_fuzz_scene /tmp/scene-corpus tests/fuzz/corpus/scene
//       -dict=tests/fuzz/scene.dict -rss_limit_mb=2048 -malloc_limit_mb=1024 -timeout=10 -max_total_time=300
// [solids] initial_state names a checkpoint on disk: in the fuzzer a missing file is just one more SceneError.
#include <cstddef>
#include <cstdint>
#include <exception>
#include <memory>
#include <string>

#include "engine/setup/budget.hpp"
#include "engine/scene/scene.hpp"
#include "engine/run/simulation.hpp"

namespace {

/// What a mutated scene may ask for: well under -malloc_limit_mb, so that an accepted scene that then allocates
/// more than the limit is the estimate's fault, a finding; and few enough grains that generating a bed (random
/// sequential addition, 2.6 ms a grain near the jam under ASan, 30 times the release build) stays within the
/// timeout.
constexpr double kFuzzMemoryLimit = 64.0 * 1024.0 * 1024.0;
constexpr double kFuzzMaxGrains = 2000.0;
/// Scenes this small are also built (layouts, grids, lists, the first forces); bigger ones only parsed, to keep
/// thousands of executions per second.
constexpr double kFuzzBuildGrains = 2000.0;
constexpr double kFuzzBuildParticles = 20000.0;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  riffle::SceneLimits limits;
  limits.memory_limit = kFuzzMemoryLimit;
  limits.max_grains = kFuzzMaxGrains;
  riffle::Model model;
  try {
    model = riffle::parse_scene(text, "fuzz.toml", limits);
  } catch (const riffle::SceneError&) {
    return 0;  // refused with file:line:column messages: the expected outcome for most mutants
  }
  const riffle::SceneBudget budget = riffle::estimate_budget(model);
  if (budget.grains > kFuzzBuildGrains ||
      budget.fluid_particles + budget.wall_particles + budget.dummy_particles > kFuzzBuildParticles)
    return 0;
  // A scene accepted by the reader must build: the CLI would report any exception here but a SceneError as "cannot
  // set up the run", which names no key. A SceneError is a bed or fill whose random grains jam, which only
  // generating shows, reported at its key. (A checkpoint named by initial_state may vanish between the two: not a
  // finding.)
  try {
    auto simulation = riffle::Simulation::from_model(std::move(model));
  } catch (const riffle::SceneError&) {
  }
  return 0;
}
