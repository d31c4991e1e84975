#pragma once
// [[solids.layered_beds]] and [[solids.fills]]: read and checked into the model's bed and fill specs
// (components/grain_specs.hpp); engine/setup/bed_generation.hpp generates them when a run starts.
#include "components/model.hpp"
#include "engine/toml/scene_reader.hpp"

namespace riffle {

/// Reads [[solids.layered_beds]] and [[solids.fills]] from the [solids] reader into model.solids.layered_beds and
/// model.solids.fills, each checked as far as it can be without generating it (check_layered_bed, check_fill) and
/// against the scene's grain cap and memory limit. Materials are looked up by name in model.materials and the regions
/// are checked against model.tank, so both must be read already. Every problem goes through the reader
/// (file:line:col: key: message). Call before solids.finish(), which would otherwise call these tables unknown keys.
void read_bed_generators(TableReader& solids, Model& model);

}  // namespace riffle
