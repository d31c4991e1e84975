#pragma once
// The scene's [mean_flow] table (docs/SCENES.md, docs/cases/bedload.md): the mean-flow fluid, a flow uniform along a
// bed held as its plane average over a column of cells, beside the MPS water as the scene's one fluid.
#include "components/model.hpp"
#include "engine/toml/scene_reader.hpp"

namespace riffle {

/// Fills model.mean_flow from the [mean_flow] table; needs the materials, the tank and [fluid] (absent) read first.
void read_mean_flow(TableReader& flow, Model& model);

/// What the grains and the mean-flow water exchange, judged once [coupling] is read: the water's velocity is its
/// pore velocity (coupling.fluid_velocity = "pore"), and the MPS-only forces (added mass, history, the self-induced
/// velocity, the viscous stress over the grain) are refused. Problems go to the [coupling] or [mean_flow] table.
void settle_mean_flow_coupling(TableReader& scene, Model& model);

}  // namespace riffle
