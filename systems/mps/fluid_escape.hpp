#pragma once
// Removes escaped fluid particles at the end of each step ([fluid] escape = "remove"): a fluid particle whose centre
// left the domain box, or a lone one (no other MPS particle within r_e) farther than fluid.escape_distance outside
// the tank's inner box. Such a particle is spray that has left the experiment: a droplet thrown over a side wall or
// high out of an open top (wedge-entry jets leave at up to twice the impact speed; Zhao & Faltinsen 1993, J. Fluid
// Mech. 246); kept, it would only stop the run when it reaches the domain's edge.
//
// What stays exact: every fluid particle has the mass rho l0^3, particles are never added, so the water's mass is
// F rho l0^3 and the removed mass (F0 - F) rho l0^3, F0 the particles laid out (FluidSummary::initial_fluid_count).
// A non-finite particle is never removed (fluid_escape_kind): fluid_checks stops the run naming it. fluid_checks
// also stops the run once more than fluid.escape_fraction_limit of the water has gone.
//
// Removal compacts the MPS table: the remaining fluid particles keep their order in slots [0, F'), walls and dummies
// follow; ids never change and are never reused. Every role travels together (keep_fields on the whole group), the
// neighbour lists are marked stale (the next search rebuilds them), and the removed particles are listed in
// FluidSummary::escaped for the run's log. Which particles go is a pure function of each particle's state, found
// in slot order, so the result is the same for any thread count and in resumed runs.
#include "systems/system.hpp"
#include "systems/physics/mps/mps_common.hpp"

namespace riffle {

class FluidEscape final : public System {
 public:
  std::string_view name() const override { return "fluid_escape"; }
  Access access() const override { return {{}, component_ids<FluidParticles, FluidNeighbours, FluidSummary>()}; }
  void run(SystemContext& context) override;
};

}  // namespace riffle
