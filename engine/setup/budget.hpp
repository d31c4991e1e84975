#pragma once
// The scene's budget: particle, pair and cell counts and the memory they need, estimated in closed form from the
// scene's boxes, spacings and grain sizes before any particle is laid out or any array allocated. A scene whose
// estimate exceeds the memory limit is refused at once (exit 2) instead of dying later in std::bad_alloc.
// `riffle check` prints the estimate. docs/SCENES.md ([run] memory_limit) and docs/RELIABILITY.md describe it.
#include <cstddef>
#include <string>

#include "components/model.hpp"

namespace riffle {

/// Limits the scene is checked against that come from outside the scene (the command line).
struct SceneLimits {
  /// [bytes] --memory-limit; 0 = not given: the scene's run.memory_limit, else default_memory_limit().
  double memory_limit = 0.0;
  /// Grains a scene may have in all (at most kMaxSceneGrains); lower in the fuzzer, where generating a bed of
  /// thousands of grains under the sanitizers takes longer than its timeout.
  double max_grains = 5e7;
};

/// Estimated counts (doubles: an absurd scene may ask for more than any integer holds) and memory of a scene.
struct SceneBudget {
  double grains = 0.0;            ///< spheres of [solids] (explicit, blocks, beds, fills, initial_state)
  double grain_pairs = 0.0;       ///< grain-grain neighbour-list entries (each pair once), skin included
  double grain_wall_pairs = 0.0;  ///< grain-wall neighbour-list entries
  double fluid_particles = 0.0;   ///< fluid particles of [[fluid.boxes]]
  double wall_particles = 0.0;    ///< wall particles: the tank's wall layer and [[fluid.wall_boxes]]
  double dummy_particles = 0.0;   ///< dummy layers behind the tank walls
  double fluid_neighbours = 0.0;  ///< entries of the fluid neighbour lists (r_e plus the skin, every particle)
  double grain_grid_cells = 0.0;  ///< cells of the grain neighbour grid (bounded by solid_grid_cell_limit)
  double voidage_nodes = 0.0;     ///< nodes of the two voidage grids together (grain voidage, drag reaction)
  double sampling_cells = 0.0;    ///< cells of the grid the grains sample the fluid with
  double bytes = 0.0;             ///< [bytes] estimated peak resident memory of the run
  double grain_bytes = 0.0;       ///< [bytes] of which grains and their pairs
  double grain_pair_bytes = 0.0;  ///< [bytes] of which the grain-grain pairs
  double fluid_bytes = 0.0;       ///< [bytes] of which MPS particles and their neighbour lists and solver
  double grid_bytes = 0.0;        ///< [bytes] of which grids
};

/// The estimate for a validated model, from its descriptions alone: grains from their specs (scene_grain_sizes: the
/// exact count and sizes a run lays out), MPS particles from their boxes.
SceneBudget estimate_budget(const Model& model);

/// [bytes] the limit when neither the scene nor the command line sets one: 3/4 of physical memory (at least
/// 1 GiB). A run needing more would swap or be killed anyway, and a quarter is left to the system and the
/// transient copies (checkpoint writes, VTK frames) the estimate leaves out.
double default_memory_limit();

/// [bytes] model.memory_limit, or default_memory_limit() where the model was not made by parse_scene (0).
double effective_memory_limit(const Model& model);

/// [bytes] an estimated upper bound on the memory of `grains` grains alone (with their pairs at a dense packing):
/// what the scene reader checks as it reads blocks, beds and fills.
double grain_bytes_lower_bound(double grains);

/// Grains never exceed this per scene (the neighbour-list indices are 32 bits; the per-generator cap of 5e7 spheres
/// now holds for the scene's sum too).
inline constexpr double kMaxSceneGrains = 5e7;
/// MPS particles (fluid, wall and dummy together) never exceed this per scene, whatever the memory.
inline constexpr double kMaxSceneFluidParticles = 5e7;

/// Empty if a scene with `grains` grains in all can be generated; else why not (more than kMaxSceneGrains, or more
/// than model.memory_limit for the grains alone). The scene reader asks as it reads each block, bed or fill.
std::string grain_count_problem(const Model& model, double grains);

/// The advice that ends every memory refusal: how to raise the limit.
std::string memory_limit_advice(const Model& model);

/// "1.5 GiB", "320 MiB", "12 KiB": for messages.
std::string format_bytes(double bytes);

/// Multi-line description of the budget for `riffle check`, each line starting with two spaces.
std::string describe_budget(const SceneBudget& budget, const Model& model);

}  // namespace riffle
