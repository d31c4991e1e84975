// How a scene would split over N MPI ranks: the weighted recursive bisection of its particles
// (systems/physics/geometry/recursive_bisection.hpp) and, per rank, the work it owns and the ghosts it would need.
// Not a test: run it by hand; docs/SCALING.md records its tables.
//
//   riffle_partition_study SCENE [--copies-x K] [--fluid-weight W] [--grain-weight W] [--parts 2,4,...]
//
// The scene's initial state (fluid laid out, grains from their checkpoint) is repeated K times along x (K = 10: the
// seed tank as a 2.4 m flume). Work weights per particle and step (defaults: the seed tank at l0 = 5 mm, one thread,
// AMD EPYC, timings.csv of `riffle run scenes/oscillating_tank.toml --until 0.3 --threads 1`: the fluid step graph
// 59.7 ms over 18,432 fluid particles, 3.24 us each; the grains' branch 69.1 ms over 8,162 grains, 8.47 us each).
// Per rank: its weight over the mean (imbalance), its fluid ghosts (fluid particles of other ranks within r_e + skin
// of its box, which every fluid pass reads), its grain ghosts (grains of other ranks within the largest contact
// range, 2 r_max + skin, exchanged every DEM sub-step), and the ranks it exchanges with.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "engine/run/simulation.hpp"
#include "systems/physics/geometry/recursive_bisection.hpp"
#include "systems/physics/mps/mps_common.hpp"

int main(int argc, char** argv) {
  using namespace riffle;
  if (argc < 2) {
    std::fprintf(stderr, "usage: riffle_partition_study SCENE [--copies-x K] [--fluid-weight W] [--grain-weight W] "
                         "[--parts 2,4,...]\n");
    return 2;
  }
  int copies = 1;
  double fluid_weight = 3.24e-6, grain_weight = 8.47e-6;
  std::vector<int> part_counts = {2, 4, 8, 16, 32, 64, 128, 256, 512, 1024};
  for (int k = 2; k + 1 < argc; k += 2) {
    if (!std::strcmp(argv[k], "--copies-x")) copies = std::atoi(argv[k + 1]);
    else if (!std::strcmp(argv[k], "--fluid-weight")) fluid_weight = std::atof(argv[k + 1]);
    else if (!std::strcmp(argv[k], "--grain-weight")) grain_weight = std::atof(argv[k + 1]);
    else if (!std::strcmp(argv[k], "--parts")) {
      part_counts.clear();
      std::stringstream list(argv[k + 1]);
      for (std::string item; std::getline(list, item, ',');) part_counts.push_back(std::atoi(item.c_str()));
    }
  }
  spdlog::set_level(spdlog::level::warn);
  auto simulation = Simulation::from_scene_file(argv[1]);
  const World& world = simulation->world();
  const Model& model = simulation->model();
  const double length = model.tank.size.x();

  std::vector<Vec3> points;
  std::vector<double> weights;
  std::vector<char> is_grain;
  double largest_radius = 0.0;
  std::size_t fluid_count = 0;
  if (world.fluid) fluid_count = fluid_slot_count(*world.fluid);
  const std::size_t grain_count = world.solids ? world.solids->size() : 0;
  for (int copy = 0; copy < copies; ++copy) {
    const Vec3 shift(copy * length, 0.0, 0.0);
    for (std::size_t i = 0; i < fluid_count; ++i) {
      points.push_back(world.fluid->position[i] + shift);
      weights.push_back(fluid_weight);
      is_grain.push_back(0);
    }
    for (std::size_t i = 0; i < grain_count; ++i) {
      points.push_back(world.solids->position[i] + shift);
      weights.push_back(grain_weight);
      is_grain.push_back(1);
      largest_radius = std::max(largest_radius, world.solids->radius[i]);
    }
  }
  PartBox domain{model.tank.origin, model.tank.origin + model.tank.size};
  domain.high.x() = model.tank.origin.x() + copies * length;
  const double fluid_range = model.fluid.enabled
                                 ? model.fluid.effective_radius() + model.fluid.neighbour_skin_ratio * model.fluid.spacing
                                 : 0.0;
  const double grain_range = 2.0 * largest_radius + model.contact.skin;
  std::printf("%s x %d along x: %zu fluid particles, %zu grains; weights %.3g / %.3g s; ghost ranges %.4g m (fluid), "
              "%.4g m (grains)\n\n",
              argv[1], copies, fluid_count * copies, grain_count * copies, fluid_weight, grain_weight, fluid_range,
              grain_range);
  std::printf("| ranks | owned particles a rank (mean) | imbalance (max / mean work) | fluid ghosts / owned fluid, mean "
              "(max) | grain ghosts / owned grains, mean (max) | neighbour ranks, mean (max) |\n|---|---|---|---|---|---|\n");
  for (const int parts : part_counts) {
    const std::vector<PartBox> boxes = recursive_bisection(points, weights, domain, parts);
    const auto part_count = static_cast<std::size_t>(parts);
    std::vector<double> work(part_count, 0.0);
    std::vector<std::size_t> owned_fluid(part_count, 0), owned_grains(part_count, 0), owner(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
      owner[i] = part_of(boxes, points[i]);
      work[owner[i]] += weights[i];
      (is_grain[i] ? owned_grains : owned_fluid)[owner[i]] += 1;
    }
    std::vector<std::size_t> fluid_ghosts(part_count, 0), grain_ghosts(part_count, 0);
    std::vector<std::vector<char>> exchanges(part_count, std::vector<char>(part_count, 0));
    for (std::size_t i = 0; i < points.size(); ++i) {
      const double range = is_grain[i] ? grain_range : fluid_range;
      for (std::size_t p = 0; p < part_count; ++p) {
        if (p == owner[i]) continue;
        if (distance_to_box(boxes[p], points[i]) > range) continue;
        (is_grain[i] ? grain_ghosts : fluid_ghosts)[p] += 1;
        exchanges[p][owner[i]] = 1;
      }
    }
    const double mean_work = [&] {
      double sum = 0.0;
      for (const double w : work) sum += w;
      return sum / parts;
    }();
    double fluid_ratio_sum = 0.0, fluid_ratio_max = 0.0, grain_ratio_sum = 0.0, grain_ratio_max = 0.0;
    double neighbours_sum = 0.0, neighbours_max = 0.0;
    for (std::size_t p = 0; p < part_count; ++p) {
      const double fluid_ratio = owned_fluid[p] ? static_cast<double>(fluid_ghosts[p]) / owned_fluid[p] : 0.0;
      const double grain_ratio = owned_grains[p] ? static_cast<double>(grain_ghosts[p]) / owned_grains[p] : 0.0;
      fluid_ratio_sum += fluid_ratio;
      grain_ratio_sum += grain_ratio;
      fluid_ratio_max = std::max(fluid_ratio_max, fluid_ratio);
      grain_ratio_max = std::max(grain_ratio_max, grain_ratio);
      double neighbours = 0.0;
      for (const char e : exchanges[p]) neighbours += e;
      neighbours_sum += neighbours;
      neighbours_max = std::max(neighbours_max, neighbours);
    }
    std::printf("| %d | %.0f | %.3f | %.2f (%.2f) | %.2f (%.2f) | %.1f (%.0f) |\n", parts,
                static_cast<double>(points.size()) / parts, *std::max_element(work.begin(), work.end()) / mean_work,
                fluid_ratio_sum / parts, fluid_ratio_max, grain_ratio_sum / parts, grain_ratio_max,
                neighbours_sum / parts, neighbours_max);
    std::fflush(stdout);
  }
  return 0;
}
