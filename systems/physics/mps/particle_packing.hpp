#pragma once
// A packed start for the MPS water (docs/FLUID.md, "A packed start"): the water's particles moved off the cubic
// lattice into a disordered arrangement of uniform number density before the run starts. Water laid on the lattice
// resists being sheared through its first spacing (measured; its mechanism is not isolated): a grain settling from
// rest in lattice water stalls its own disturbance at 0.7-0.8 of the continuum's until the water next to it has
// moved about one spacing, where water started off the lattice follows the continuum within a few hundredths.
// Packing (Colagrossi, Bouscasse, Antuono & Marrone 2012, Comput. Phys. Commun. 183, 1641-1653: particle
// arrangements for meshless schemes are made uniform and isotropic, not lattices) here: each particle whose kernel
// lies wholly in water and walls is displaced by a seeded uniform random offset, then relaxed by Fickian shifts,
// delta r = -D grad C with C = n / n0 (Lind, Xu, Stansby & Rogers 2012; the pieces of particle_shifting.hpp), the
// walls and the water within r_e of a free surface held on the lattice. Off the lattice, under a free surface, the
// projection keeps water at rest only in a viscous liquid (packed_start_viscosity_floor below).
#include <cmath>
#include <cstdint>
#include <vector>

#include "components/vec.hpp"
#include "systems/physics/geometry/periodic_box.hpp"

namespace riffle {

struct PackingSettings {
  double spacing = 0.0;           ///< [m] l0
  double effective_radius = 0.0;  ///< [m] r_e
  double jitter = 0.2;            ///< [l0] the random offset's half-width per axis
  int iterations = 40;            ///< Fickian shifts after the offset
  double diffusivity = 0.36;      ///< [l0^2] D of each shift (A h^2, A = 0.25, h = r_e / 2 at r_e = 2.4 l0; stable below 0.67)
  double max_shift = 0.1;         ///< [l0] the longest shift per iteration
  std::uint64_t seed = 0x5EEDF1D0ull;
};

struct PackingReport {
  std::size_t moved = 0;              ///< particles displaced (the rest stay on the lattice)
  double spread_after_offset = 0.0;   ///< RMS of n / n0 - 1 over the moved particles after the random offset
  double spread_after_packing = 0.0;  ///< the same after the shifts
  double mean_offset = 0.0;           ///< [l0] mean distance of a moved particle from its lattice site at the end
};

/// The least kinematic viscosity [m^2/s] at which packed water at rest comes to rest, 0.01 l0 sqrt(g l0): measured
/// with scenes/hydrostatic.toml (l0 = 5 mm, 3 s) packed, its largest speed falls to 2e-5 m/s at nu = 1e-4
/// (0.09 l0 sqrt(g l0)), stays near 1 mm/s at 1e-5 (0.009) and grows to 0.1 m/s at water's 1e-6 (0.0009): the
/// motion starts in the top layers and grows with the density term's rate (docs/FLUID.md, "A packed start"). A sealed
/// box full of water (no free-surface particle, so no clamp) comes to rest at water's viscosity too.
inline double packed_start_viscosity_floor(double spacing, double gravity) {
  return 0.01 * spacing * std::sqrt(gravity * spacing);
}

/// Whether packed water at rest may not come to rest: a liquid below the floor above, unless the particle-scale
/// viscosity ([fluid] scatter_viscosity > 0) damps the scatter it grows from (measured: packed water under a free
/// surface at water's viscosity then comes to rest; docs/FLUID.md).
inline bool packed_water_may_not_rest(double kinematic_viscosity, double scatter_viscosity, double spacing,
                                      double gravity) {
  return scatter_viscosity <= 0.0 && kinematic_viscosity < packed_start_viscosity_floor(spacing, gravity);
}

/// Packs `positions` (every MPS particle: water, walls and dummies) in place. Only particles with `movable[i]` set
/// may move (the caller's water); of those, only the ones whose number density on the lattice is n0 (a complete
/// kernel of water, wall or dummy particles: not within r_e of a free surface) are displaced. Along `box`'s periodic
/// axes neighbours are found across the seams and moved particles are wrapped into the period. Deterministic: the
/// offsets are a function of the seed and the particle's index.
PackingReport pack_particles(std::vector<Vec3>& positions, const std::vector<char>& movable, const PeriodicBox& box,
                             const PackingSettings& settings);

}  // namespace riffle
