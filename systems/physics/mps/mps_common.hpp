#pragma once
// What every MPS fluid system shares: the kernel and the reference constants of the initial lattice (numerics.md
// 1.1), the slot layout (fluid particles first), and deterministic parallel reductions, so that results do not
// depend on the thread count.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

#include "components/fluid.hpp"
#include "components/model.hpp"
#include "systems/physics/math/deterministic_sum.hpp"
#include "systems/physics/mps/mps_kernel.hpp"

namespace riffle {

/// Derives the model's MPS constants from its l0 and r_e / l0 (FluidModel::constants): the scene reader calls it once
/// the scene is read, and code that builds or changes a model by hand calls it after its last change of either.
inline void fill_mps_constants(FluidModel& fluid) {
  MpsConstants constants;
  constants.spacing = fluid.spacing;
  constants.effective_radius_ratio = fluid.effective_radius_ratio;
  constants.effective_radius = fluid.effective_radius();
  const LatticeConstants lattice = lattice_constants(3, fluid.spacing, fluid.effective_radius());
  constants.reference_density = lattice.number_density;
  constants.laplacian_lambda = lattice.laplacian_lambda;
  constants.particle_volume = fluid.spacing * fluid.spacing * fluid.spacing;
  fluid.constants = constants;
}

/// The model's MPS constants; throws std::logic_error when they were not derived from its present l0 and r_e / l0
/// (never filled, or either changed since), so that no system runs with stale constants.
inline const MpsConstants& mps_constants(const FluidModel& fluid) {
  const MpsConstants& constants = fluid.constants;
  if (!(constants.spacing == fluid.spacing && constants.effective_radius_ratio == fluid.effective_radius_ratio))
    throw std::logic_error("FluidModel::constants were not derived from the model's spacing and effective_radius_ratio: "
                           "call fill_mps_constants after the last change of either");
  return constants;
}

inline constexpr std::int32_t kFluidKind = static_cast<std::int32_t>(FluidKind::kFluid);

/// Fluid particles occupy slots [0, F), walls and dummies follow (the initial state lays them out so and nothing
/// reorders them); returns F.
inline std::size_t fluid_slot_count(const ParticleState& particles) {
  return static_cast<std::size_t>(
      std::partition_point(particles.kind.begin(), particles.kind.end(), [](std::int32_t kind) { return kind == kFluidKind; }) -
      particles.kind.begin());
}

/// Neighbour slots of fluid particle i.
struct NeighbourRange {
  const std::uint32_t* first;
  const std::uint32_t* last;
  const std::uint32_t* begin() const { return first; }
  const std::uint32_t* end() const { return last; }
};
inline NeighbourRange neighbours_of(const FluidNeighbours& neighbours, std::size_t i) {
  return {neighbours.slots.data() + neighbours.offsets[i], neighbours.slots.data() + neighbours.offsets[i + 1]};
}

/// Neighbours of fluid particle i within r_e at r* (recorded by fluid_free_surface).
inline NeighbourRange near_neighbours_of(const FluidNeighbours& neighbours, std::size_t i) {
  const std::uint32_t* first = neighbours.near_slots.data() + neighbours.offsets[i];
  return {first, first + neighbours.near_count[i]};
}

/// A field of the MPS particles over the slots a neighbour list holds: [0, N) the reals, [N, N + G) the ghost copies
/// of a periodic tank's halo (FluidNeighbours::halo, ::ghosts) or, over MPI ranks, of the other ranks' particles
/// (FluidNeighbours::ranks). Without either every slot is real.
template <class T>
Ghosted<T> fluid_ghosted(const std::vector<T>& real, const std::vector<T>& ghost, const FluidNeighbours& neighbours) {
  return {real.data(), ghost.data(),
          neighbours.ranks.active ? neighbours.ranks.real_count
          : neighbours.halo.valid ? neighbours.halo.real_count
                                  : std::numeric_limits<std::uint32_t>::max()};
}
/// The real particle behind a neighbour slot (the slot itself without a halo). Over MPI ranks a ghost's owner is on
/// another rank: its fields come as ghost fields (fluid_ranks.hpp), and this is not to be asked.
inline std::uint32_t fluid_owner_of(const FluidNeighbours& neighbours, std::uint32_t j) {
  return neighbours.halo.valid ? neighbours.halo.owner_of(j) : j;
}

/// Runs body(i) for i in [0, count) in parallel (gather loops: each i writes only its own slot).
template <class Body>
void for_each_particle(std::size_t count, Body&& body) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 256), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) body(i);
  });
}

}  // namespace riffle
