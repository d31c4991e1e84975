#pragma once
// The [output] table's probes and bed-profile keys (docs/SCENES.md): read and checked against the grains, the tank
// and the fluid already read. The writers are in engine/output/.
#include <string>
#include <vector>

#include "components/model.hpp"
#include "engine/toml/scene_reader.hpp"

namespace riffle {

/// Output files the run writes itself: a probe's `file` may not be one of them.
const std::vector<std::string>& reserved_output_files();

/// Reads every [[output.probes]] table of the [output] reader into model.output.probes. The grains, the contact
/// model, [tank] and [fluid] must be read already (ids are checked against the grains the run starts with: those of
/// [solids] initial_state, then the scene's spheres, blocks, beds and fills, counted by scene_sphere_count); wall
/// forces need [contact], fluid probes [fluid] and take their default radius from its spacing; points must lie in
/// the tank).
/// Problems go through the reader (file:line:column: key: message).
void read_probes(TableReader& output, Model& model);

/// Reads the [output] keys bed_profile_interval and bed_layer_thickness (the grains must be read already: the
/// profile needs some).
void read_bed_profile_keys(TableReader& output, Model& model);

}  // namespace riffle
