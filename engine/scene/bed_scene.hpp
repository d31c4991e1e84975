#pragma once
// [[solids.layered_beds]] and [[solids.fills]]: read, checked, and generated into the model's sphere list
// (engine/setup/bed_generation.hpp generates).
#include "components/model.hpp"
#include "engine/toml/scene_reader.hpp"

namespace riffle {

/// Reads [[solids.layered_beds]] and [[solids.fills]] from the [solids] reader and appends the generated spheres to
/// model.solids.spheres (beds in order, then fills in order). Materials are looked up by name in model.materials
/// and the regions are checked against model.tank, so both must be read already. Every problem goes through the
/// reader (file:line:col: key: message). Call before solids.finish(), which would otherwise call these tables
/// unknown keys.
void read_bed_generators(TableReader& solids, Model& model);

}  // namespace riffle
