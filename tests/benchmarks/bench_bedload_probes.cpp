// Cost of the bed-load probes (docs/SCENES.md, "Bed-load measures"): loads a scene, runs a few engine steps (so the
// contact list and the fluid forces exist), then times each bed-load probe's row (ProbeWriter::write) over
// repeated calls on that state. Not a test: run it by hand; docs/SCENES.md records its result on the seed bed.
//
//   riffle_bench_bedload_probes SCENE [--steps S] [--repeats R] [--out DIR]
#include <spdlog/spdlog.h>
#include <tbb/global_control.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>

#include "engine/output/probes.hpp"
#include "engine/run/simulation.hpp"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: riffle_bench_bedload_probes SCENE [--steps S] [--repeats R] [--out DIR]\n");
    return 2;
  }
  long steps = 5, repeats = 20;
  std::string out = "/tmp/riffle_bench_bedload_probes";
  for (int k = 2; k + 1 < argc; k += 2) {
    if (!std::strcmp(argv[k], "--steps")) steps = std::atol(argv[k + 1]);
    else if (!std::strcmp(argv[k], "--repeats")) repeats = std::atol(argv[k + 1]);
    else if (!std::strcmp(argv[k], "--out")) out = argv[k + 1];
  }
  spdlog::set_level(spdlog::level::warn);
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
  auto simulation = riffle::Simulation::from_scene_file(argv[1]);
  for (long s = 0; s < steps; ++s) simulation->step();
  riffle::World& world = simulation->world();
  std::filesystem::create_directories(out);
  const riffle::Model& model = simulation->model();
  std::printf("grains %zu  MPS particles %zu  steps %ld  repeats %ld  (1 thread)\n",
              world.solids ? world.solids->size() : 0, world.fluid ? world.fluid->size() : 0, steps, repeats);
  const char* kinds[] = {"moving_fraction", "packing_density", "bedload_flux", "velocity_profile",
                         "bed_shear_stress"};
  const riffle::ProbeModel::Kind values[] = {
      riffle::ProbeModel::Kind::kMovingFraction, riffle::ProbeModel::Kind::kPackingDensity,
      riffle::ProbeModel::Kind::kBedloadFlux, riffle::ProbeModel::Kind::kVelocityProfile,
      riffle::ProbeModel::Kind::kBedShearStress};
  for (int k = 0; k < 5; ++k) {
    riffle::ProbeModel probe;
    probe.kind = values[k];
    probe.name = kinds[k];
    probe.file = std::string("probe_") + kinds[k] + ".csv";
    probe.layer_thickness = model.fluid.enabled ? model.fluid.spacing : 0.005;
    if (probe.kind == riffle::ProbeModel::Kind::kBedShearStress && !model.fluid.enabled) continue;
    riffle::ProbeWriter writer(model, probe, out, world, true);
    const auto start = riffle::Clock::now();
    for (long r = 0; r < repeats; ++r) writer.write(world);
    std::printf("%-18s %9.3f ms per row\n", kinds[k], 1e3 * riffle::seconds_since(start) / static_cast<double>(repeats));
  }
  return 0;
}
