#include "engine/setup/budget.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "engine/setup/initial_state.hpp"
#include "engine/setup/fluid_layout.hpp"
#include "systems/physics/geometry/cell_grid.hpp"
#include "systems/physics/coupling/voidage_grid.hpp"
#include "systems/physics/geometry/domain.hpp"
#include "systems/physics/dem/neighbour_range.hpp"

namespace riffle {

namespace {

constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;

// Bytes per item: the components' fields (Solids ~320 B a grain, FluidParticles ~200 B a particle) times what the
// run holds beside them (contacts' per-grain arrays, the sorts' scratch copies, the set-up copies (SphereSpec,
// lattice layouts), the PPE's vectors, and the serialised checkpoint written at the end), calibrated against the
// peak RSS of runs (/usr/bin/time -v, docs/RELIABILITY.md "Memory budget"): 6.4e4 and 3.43e5 grains in a dense
// block, 5.1e4 and 5.7e5 MPS particles of still water. Estimate / measured: 1.03 to 1.2 (1.4 for dam_break and
// ergun_plug, whose dummy particles cost less than the average).
constexpr double kBytesPerGrain = 2600.0;
/// pair_second, spring, force, two torques, overlap, reverse index, saved springs
constexpr double kBytesPerGrainPair = 200.0;
constexpr double kBytesPerGrainWallPair = 90.0;   ///< wall slot, spring, force, torque, overlap
constexpr double kBytesPerMpsParticle = 1100.0;
constexpr double kBytesPerFluidNeighbour = 20.0;  ///< list slots (wide and narrow), PPE matrix entry, pair batches
constexpr double kBytesPerGridCell = 8.0;         ///< cell start (uint32) and its fill cursor
constexpr double kBytesPerVoidageNode = 16.0;     ///< solid and fluid deposit (two doubles)
constexpr double kBaseBytes = 16.0 * 1024.0 * 1024.0;  ///< the process itself (9 MB measured), TBB's pools, logs

/// Closest-packed spheres fill at most pi / sqrt(18) of space.
constexpr double kDensestPacking = 0.7405;

/// Lattice cells whose centres lie in [low, high] along one axis (fluid_layout.cpp's lattice_range, in doubles so
/// that an absurd box gives a huge number rather than an overflowed integer).
double lattice_cells(double origin, double low, double high, double spacing) {
  const double first = std::ceil((low - origin) / spacing - 0.5 - 1e-9);
  const double last = std::floor((high - origin) / spacing - 0.5 + 1e-9);
  return std::max(0.0, last - first + 1.0);
}

double box_particles(const ParticleBoxModel& box, const Vec3& origin, double spacing) {
  double count = 1.0;
  for (int axis = 0; axis < 3; ++axis)
    count *= box.fit_extent ? std::max(1.0, std::round((box.high[axis] - box.low[axis]) / spacing))  // box_grid
                            : lattice_cells(origin[axis], box.low[axis], box.high[axis], spacing);
  return count;
}

/// Particles of the tank's shell `layers` deep beyond its closed, non-periodic faces (fluid_layout.hpp: prod_a (n_a + L_a^- + L_a^+) - prod_a n_a).
double tank_shell(const TankModel& tank, double spacing, double layers) {
  double outer = 1.0, inner = 1.0;
  for (int axis = 0; axis < 3; ++axis) {
    const double cells = std::max(1.0, std::round(tank.size[axis] / spacing));
    // A periodic axis has no wall on either side, as an open face has none (tank_wall_layout).
    const bool periodic = tank.periodic[static_cast<std::size_t>(axis)];
    const double below = periodic || tank.face_open(axis, 0) ? 0.0 : layers;
    const double above = periodic || tank.face_open(axis, 1) ? 0.0 : layers;
    outer *= cells + below + above;
    inner *= cells;
  }
  return outer - inner;
}

/// Nodes of a voidage grid (systems/physics/coupling/voidage_grid.cpp) over `extent` with `cell` wide cells: extent / cell + 3 per
/// axis, at most 4096.
double voidage_nodes(const Vec3& extent, const Vec3& cell) {
  double nodes = 1.0;
  for (int axis = 0; axis < 3; ++axis) nodes *= std::min(std::floor(extent[axis] / cell[axis]) + 3.0, 4096.0);
  return nodes;
}
double voidage_nodes(const Vec3& extent, double cell) { return voidage_nodes(extent, Vec3::Constant(cell)); }

/// The grains' count and sizes as the budget uses them: from the scene's descriptions (scene_grain_sizes), the
/// count in doubles.
struct BudgetGrains {
  double count = 0.0;
  double smallest = 0.0, largest = 0.0;  ///< [m] radii
  double mean_cube = 0.0;                ///< [m^3] mean of r^3
};

BudgetGrains budget_grains(const Model& model) {
  const GrainSizes sizes = scene_grain_sizes(model.solids);
  BudgetGrains grains;
  grains.count = static_cast<double>(sizes.count);
  if (sizes.count > 0) {
    grains.smallest = sizes.smallest_radius;
    grains.largest = sizes.largest_radius;
    grains.mean_cube = sizes.radius_cubed_sum / grains.count;
  }
  return grains;
}

/// Grain-grain list entries: each grain lists the grains within r_i + r_j + skin once per pair. With a typical
/// grain of radius r (the cube root of the mean r^3), a grain sees at most the densest packing's share of the
/// sphere of radius 2r + skin, and never more than all other grains.
double grain_pairs(const BudgetGrains& sizes, double skin) {
  if (sizes.count < 2.0) return 0.0;
  const double r = std::cbrt(sizes.mean_cube);
  const double reach = 2.0 * r + skin;
  const double around = kDensestPacking * (reach * reach * reach) / (r * r * r);
  return 0.5 * sizes.count * std::min(sizes.count - 1.0, around);
}

}  // namespace

double grain_bytes_lower_bound(double grains) {
  // Monodisperse grains with the default skin of r/2: (2.5)^3 x 0.74 / 2 = 5.8 list entries per grain.
  const double pairs_per_grain = 0.5 * kDensestPacking * 2.5 * 2.5 * 2.5;
  return kBaseBytes + grains * (kBytesPerGrain + pairs_per_grain * kBytesPerGrainPair + kBytesPerGrainWallPair);
}

SceneBudget estimate_budget(const Model& model) {
  SceneBudget budget;
  const TankModel& tank = model.tank;
  // The coupling grids span the particles, which may be anywhere in the domain (the tank extent by its motion, plus
  // the margin); each is bounded by its own node limit, so a wide domain costs at most that.
  const DomainBox domain = domain_box(model);
  const Vec3 extent = domain.high - domain.low;

  BudgetGrains grains;
  if (model.solids.enabled) {
    grains = budget_grains(model);
    budget.grains = grains.count;
    const double skin = model.contact.skin > 0.0 ? model.contact.skin : 0.5 * grains.smallest;
    if (model.contact.enabled) {
      budget.grain_pairs = grain_pairs(grains, skin);
      budget.grain_wall_pairs = grains.count;  // a grain touches at most about one wall at a time
    }
    budget.grain_grid_cells = grains.count > 0.0 ? solid_grid_cell_limit(static_cast<std::size_t>(grains.count)) : 0.0;
  }

  const FluidModel& fluid = model.fluid;
  double fluid_reach = 0.0;
  if (fluid.enabled && fluid.spacing > 0.0) {
    for (const ParticleBoxModel& box : fluid.boxes)
      budget.fluid_particles += box_particles(box, tank.origin, fluid.spacing);
    for (const ParticleBoxModel& box : fluid.wall_boxes)
      budget.wall_particles += box_particles(box, tank.origin, fluid.spacing);
    if (fluid.tank_walls) {
      const double dummy_layers =
          std::max(0.0, std::ceil(fluid.effective_radius_ratio - 1e-9) - 1.0);  // dummy_layer_count in doubles
      const double walls = tank_shell(tank, fluid.spacing, 1.0);
      budget.wall_particles += walls;
      budget.dummy_particles = tank_shell(tank, fluid.spacing, 1.0 + dummy_layers) - walls;
    }
    // Lattice points within r_e plus the list's skin: 4/3 pi (r_e/l0 + skin/l0)^3 per listed particle.
    const double reach = fluid.effective_radius_ratio + fluid.neighbour_skin_ratio;
    const double listed = budget.fluid_particles + budget.wall_particles;
    budget.fluid_neighbours = listed * 4.0 / 3.0 * std::numbers::pi * reach * reach * reach;
    fluid_reach = fluid.effective_radius();
  }

  if (model.coupling.enabled && grains.count > 0.0 && fluid.spacing > 0.0) {
    // systems/coupling/solid_voidage.cpp and systems/coupling/fluid_drag_reaction.cpp: 0.42 R_eps (0.668 R_eps for the
    // cloud-in-cell estimate) and 0.668 (r_max + r_e) cells.
    const double voidage_radius = model.coupling.voidage_radius > 0.0
                                      ? model.coupling.voidage_radius
                                      : std::max(3.0 * fluid.spacing, 4.0 * grains.largest);
    const double node_limit = voidage_node_limit(static_cast<std::size_t>(grains.count + budget.fluid_particles));
    const double voidage_cell = voidage_cell_ratio(model.coupling.voidage_estimate ==
                                                 CouplingModel::VoidageEstimate::kSelfCorrected);
    const double across = model.coupling.voidage_vertical_radius > 0.0 ? model.coupling.voidage_vertical_radius
                                                                         : voidage_radius;
    const Vec3 voidage_cells(voidage_cell * voidage_radius, voidage_cell * voidage_radius, voidage_cell * across);
    budget.voidage_nodes = std::min(voidage_nodes(extent, voidage_cells), node_limit) +
                           std::min(voidage_nodes(extent, 0.668 * (grains.largest + fluid_reach)), node_limit);
    // systems/coupling/solid_fluid_sampling.cpp: cells of 0.5 (r_min + r_e) over the fluid, bounded by cell_grid.hpp.
    const double cell = 0.5 * (grains.smallest + fluid_reach);
    double cells = 1.0;
    for (int axis = 0; axis < 3; ++axis) cells *= std::ceil(extent[axis] / cell + 1.0);
    budget.sampling_cells = std::min(cells, cell_grid_cell_limit(static_cast<std::size_t>(budget.fluid_particles)));
  }

  budget.grain_pair_bytes = budget.grain_pairs * kBytesPerGrainPair;
  budget.grain_bytes = budget.grains * kBytesPerGrain + budget.grain_pair_bytes +
                       budget.grain_wall_pairs * kBytesPerGrainWallPair;
  const double mps = budget.fluid_particles + budget.wall_particles + budget.dummy_particles;
  budget.fluid_bytes = mps * kBytesPerMpsParticle +
                       budget.fluid_neighbours * kBytesPerFluidNeighbour;
  budget.grid_bytes = (budget.grain_grid_cells + 2.0 * budget.sampling_cells) * kBytesPerGridCell +
                      budget.voidage_nodes * kBytesPerVoidageNode;
  budget.bytes = kBaseBytes + budget.grain_bytes + budget.fluid_bytes + budget.grid_bytes;
  return budget;
}

double effective_memory_limit(const Model& model) {
  return model.memory_limit > 0.0 ? model.memory_limit : default_memory_limit();
}

std::string memory_limit_advice(const Model& model) {
  const std::string source =
      model.memory_limit > 0.0 ? model.memory_limit_source : std::string("the default, 3/4 of physical memory");
  return "the memory limit is " + format_bytes(effective_memory_limit(model)) + " (" + source +
         "); raise it with [run] memory_limit = GIB or --memory-limit GIB if the machine has the memory";
}

std::string grain_count_problem(const Model& model, double grains) {
  char count[64];
  std::snprintf(count, sizeof count, "%.6g", grains);
  if (grains > std::min(kMaxSceneGrains, model.max_grains)) {
    char limit[64];
    if (model.max_grains >= kMaxSceneGrains)
      std::snprintf(limit, sizeof limit, "5e7");
    else
      std::snprintf(limit, sizeof limit, "%.0f", model.max_grains);
    return std::string("the scene would have ") + count + " grains in all, more than the " + limit +
           " a scene may have";
  }
  const double bytes = grain_bytes_lower_bound(grains);
  if (bytes > effective_memory_limit(model))
    return std::string("the scene's ") + count + " grains would need at least an estimated " + format_bytes(bytes) +
           "; " + memory_limit_advice(model);
  return {};
}

double default_memory_limit() {
  const long pages = ::sysconf(_SC_PHYS_PAGES);
  const long page_size = ::sysconf(_SC_PAGESIZE);
  const double physical =
      pages > 0 && page_size > 0 ? static_cast<double>(pages) * static_cast<double>(page_size) : 0.0;
  return std::max(kGiB, 0.75 * physical);
}

std::string format_bytes(double bytes) {
  char text[64];
  if (!(bytes < 1e30)) return "more than 1e30 bytes";
  if (bytes >= kGiB)
    std::snprintf(text, sizeof text, "%.3g GiB", bytes / kGiB);
  else if (bytes >= 1024.0 * 1024.0)
    std::snprintf(text, sizeof text, "%.3g MiB", bytes / (1024.0 * 1024.0));
  else
    std::snprintf(text, sizeof text, "%.3g KiB", bytes / 1024.0);
  return text;
}

std::string describe_budget(const SceneBudget& budget, const Model& model) {
  char text[1024];
  std::snprintf(text, sizeof text,
                "  budget (estimated before anything is allocated):\n"
                "    grains %.6g, grain pairs %.3g, grain-wall pairs %.3g, grain grid cells %.3g\n"
                "    MPS particles %.6g fluid + %.6g wall + %.6g dummy, fluid neighbour entries %.3g\n"
                "    coupling grids: voidage nodes %.3g, sampling cells %.3g\n"
                "    memory %s (grains %s, MPS %s, grids %s) of the limit %s (%s)\n",
                budget.grains, budget.grain_pairs, budget.grain_wall_pairs, budget.grain_grid_cells,
                budget.fluid_particles, budget.wall_particles, budget.dummy_particles, budget.fluid_neighbours,
                budget.voidage_nodes, budget.sampling_cells, format_bytes(budget.bytes).c_str(),
                format_bytes(budget.grain_bytes).c_str(), format_bytes(budget.fluid_bytes).c_str(),
                format_bytes(budget.grid_bytes).c_str(), format_bytes(effective_memory_limit(model)).c_str(),
                model.memory_limit > 0.0 ? model.memory_limit_source.c_str() : "the default");
  return text;
}

}  // namespace riffle
