#pragma once
// Builds the World at t = 0 from a validated Model: tank walls, grains, tank kinematics.
#include "engine/model.hpp"
#include "engine/world.hpp"

namespace riffle {

World initial_world(const Model& model);

/// The grains of the checkpoint named by model.solids.initial_state, with their material indices mapped by name to
/// this model's materials. Throws std::runtime_error (CheckpointError included) naming what is wrong.
Solids initial_grains(const Model& model);

/// The tank's walls (one plane per closed face), placed at rest.
Walls tank_walls(const TankModel& tank);

}  // namespace riffle
