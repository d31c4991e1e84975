#pragma once
// Builds the World at t = 0 from a validated Model: tank walls, grains, MPS particles, tank kinematics.
#include "components/model.hpp"
#include "components/world.hpp"

namespace riffle {

World initial_world(const Model& model);

/// The World's shape without its contents: every component the scene's systems use, empty (no grain, particle or
/// contact), the tank at t = 0. `riffle check` and `riffle graph` build the step graph on it, so they answer from
/// the model alone; initial_world fills it.
World unlaid_world(const Model& model);

/// Reads the grains of the checkpoint named by model.solids.initial_state, with their material indices mapped by
/// name to this model's materials. Throws std::runtime_error (CheckpointError included) naming what is wrong. The
/// scene reader calls it once and keeps the grains in model.solids.initial_grains.
Solids read_initial_grains(const Model& model);

/// The tank's walls (one plane per closed face), placed at rest.
Walls tank_walls(const TankModel& tank);

/// The MPS particles at t = 0 on one lattice anchored at tank.origin (engine/setup/fluid_layout.hpp): the fluid of every
/// box in scene order first, so that fluid particles hold slots [0, F) (the pressure solver's unknowns are those
/// slots); then the tank's wall and dummy particles; then the wall boxes as wall particles, each lattice point once.
/// Walls and dummies are placed with the tank at `tank` and move with it; fluid starts with its box's velocity.
FluidParticles initial_fluid(const Model& model, const TankMotion& tank);

}  // namespace riffle
