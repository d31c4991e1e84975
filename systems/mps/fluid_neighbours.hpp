#pragma once
// Neighbour lists of all MPS particles (fluid, wall, dummy) within a search radius (>= r_e; numerics 1.1, 1.3):
// a uniform cell grid over the particles' bounding box with cells half a radius wide (or half a wider cell radius),
// counted, scanned and filled in parallel (oneTBB). Each particle's list is its neighbours' slots in ascending
// order, self excluded, so the lists (and every sum over them) do not depend on the thread count, the grid or the
// cell size.
//
// Choice: the lists live in their own component, FluidNeighbours (like Contacts for the grains), not in
// FluidParticles: the build reads the particles and writes only the lists, so the scheduler can order it before
// every operator that reads the lists and writes the particles. FluidNeighbourSearch keeps them as Verlet lists
// (radius r_e + skin, rebuilt when the skin is used up); the operators cut at r_e themselves.
#include <algorithm>
#include <vector>

#include "systems/system.hpp"
#include "systems/physics/mps/mps_common.hpp"
#include "systems/physics/geometry/periodic_box.hpp"

namespace riffle {

/// Edge [m] of the search grid's cells for a search radius: a query scans about 5^3 cells of half a radius, about
/// 40 % fewer candidates than 3^3 cells of a radius.
inline double fluid_search_cell_size(double radius) { return 0.5 * radius; }

/// Builds `neighbours` for the first `query_count` particles of `positions` (all by default): j is a neighbour of i
/// (j != i) iff |r_j - r_i| < radius, j among all particles. Non-finite positions get no neighbours and are nobody's
/// neighbour. The grid's cells have a corner at `grid_anchor` and are fluid_search_cell_size(cell_radius) wide
/// (cell_radius >= radius; 0: radius); the result depends on neither, the speed does: particles kept in the order
/// of the same cells (FluidCellSort) come out of the scan nearly sorted.
void build_fluid_neighbours(const std::vector<Vec3>& positions, double radius, FluidNeighbours& neighbours,
                            std::size_t query_count = static_cast<std::size_t>(-1),
                            const Vec3& grid_anchor = Vec3::Zero(), double cell_radius = 0.0);

/// The candidate test of build_fluid_neighbours: the portable one, or 4 (AVX2) or 8 (AVX-512) candidates at a time
/// where the CPU has them. All keep exactly the same pairs; the cap (default: the widest) lets a test compare them.
enum class FluidSearchSimd { kPortable, kAvx2, kAvx512 };
void set_fluid_search_simd_cap(FluidSearchSimd cap);
/// The test the next build takes: the widest the CPU has, up to the cap.
FluidSearchSimd fluid_search_simd();

/// Verlet lists of the fluid particles (queries) among all MPS particles, built with radius r_e + skin and rebuilt
/// only when the two particles that moved most since the build (walls included: they move with the tank) moved more
/// than the skin together (systems/physics/geometry/verlet_skin.hpp: no pair's distance changed by more).
/// The operators cut at r_e and the lists are ascending, so when a rebuild happens, and with which skin, changes
/// no result. Two instances run per step: at the step start (current positions) and after the prediction (r*).
///
/// The skin adapts: when the last lists lasted a single step (in violent flow the fastest particles use up any
/// skin of a few tenths of l0 every step), a wide skin buys no reuse and only lengthens every pass over the lists
/// (r_e + 0.3 l0 holds 42 % more candidates than r_e), so the next build takes `narrow_skin`; once a list lasts
/// longer, the build goes back to `skin` (docs/BENCHMARKS.md, "Fluid speed work").
///
/// In a periodic tank (`box` with a periodic axis) each rebuild builds the halo (components/halo.hpp) of every MPS
/// slot within the list radius of a periodic face and searches the reals and their ghosts together: list slots
/// [N, N + G) are ghosts. Every run (rebuild or not) exchanges the ghosts' positions (the ones searched at),
/// velocities and kinds. fluid_correct wraps the positions into the period at every step: a particle that crosses
/// a face jumps by one period, which uses up any skin and so forces the next rebuild. The halo reaches r_e + skin, and
/// at r* as far again as the farthest particle lies past a face (periodic_overshoot: r* is wrapped only at the
/// correction): a real farther than that from a face at the build lies more than r_e + skin from every particle on
/// the far side of the face, and no pair's distance shrinks by more than the skin before the next rebuild.
///
/// Over MPI ranks (FluidNeighbours::ranks active) a rebuild is decided over all the ranks (any rank's particle past
/// half the skin: a pair across two ranks joins moves measured apart), and the ghosts are the other ranks' particles
/// (and the images across periodic faces) within the list radius of this rank's box, widened by how far any rank's
/// particle lies outside its box (fluid_box_overflow); between rebuilds their positions and velocities come from their
/// owners. fluid_rank_migration has handed the particles to the ranks whose boxes hold them just before the step-start
/// search rebuilds.
class FluidNeighbourSearch final : public System {
 public:
  enum class Positions { kCurrent, kPredicted };
  FluidNeighbourSearch(double effective_radius, double skin, double narrow_skin, Positions at,
                       const PeriodicBox& box = {})
      : effective_radius_(effective_radius), skin_(skin), narrow_skin_(std::min(narrow_skin, skin)), at_(at),
        box_(box) {}
  std::string_view name() const override {
    return at_ == Positions::kCurrent ? "fluid_neighbours" : "fluid_neighbours_predicted";
  }
  Access access() const override {
    return {component_ids<ParticleState, ParticlePrediction>(), component_ids<FluidNeighbours>()};
  }
  void run(SystemContext& context) override;

  /// Whether the lists in `neighbours` still hold every pair within `effective_radius` of the particles at `positions`
  /// (the two largest moves, in the tank's frame, within the skin they were built with; over ranks the largest within
  /// half of it; the same particles). This rank's answer only; fluid_rank_migration asks it of the step-start search.
  static bool lists_still_valid(const std::vector<Vec3>& positions, std::size_t queries,
                                const FluidNeighbours& neighbours, double effective_radius,
                                const Vec3& tank_displacement);

 private:
  /// Ghost positions (the ones searched at: r^k or r*), velocities and kinds from the reals.
  void exchange_ghosts(const ParticleState& particles, const std::vector<Vec3>& positions,
                       FluidNeighbours& neighbours) const;
  /// The same over MPI ranks: positions and velocities from the ghosts' owners (kinds come with the build).
  void exchange_rank_ghosts(const ParticleState& particles, const std::vector<Vec3>& positions,
                            FluidNeighbours& neighbours) const;
  /// Over MPI ranks: the ghosts within `radius` (widened by the boxes' overflow) of this rank's box, at `positions`.
  void build_rank_ghosts(const ParticleState& particles, const std::vector<Vec3>& positions, double radius,
                         FluidNeighbours& neighbours) const;

  double effective_radius_;
  double skin_;
  double narrow_skin_;
  Positions at_;
  PeriodicBox box_;
};

}  // namespace riffle
