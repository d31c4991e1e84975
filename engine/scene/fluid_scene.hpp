#pragma once
// The scene's [fluid] table (docs/SCENES.md): the MPS constants, the switchable schemes [fluid.schemes], the fluid
// boxes [[fluid.boxes]] and the solid wall boxes [[fluid.wall_boxes]], validated against the tank so that the
// initial lattice (engine/setup/fluid_layout.hpp) can always be laid out.
#include "components/model.hpp"
#include "engine/toml/scene_reader.hpp"

namespace riffle {

/// Fills model.fluid from the [fluid] table; needs model.tank read first. Problems go through the reader.
void read_fluid(TableReader& fluid, Model& model);

/// A body force along x on the water ([fluid.body_force], [mean_flow.body_force]; docs/SCENES.md).
void read_body_force(TableReader& reader, BodyForceModel& out, const TankMotionModel& tank_motion);

}  // namespace riffle
