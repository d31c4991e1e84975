#pragma once
// The mean-flow fluid's column at the start of a run (docs/cases/bedload.md): the grains' solid fraction and bed
// surface, and the water's first velocity profile ([mean_flow] initial).
#include "components/mean_flow.hpp"
#include "components/model.hpp"
#include "components/solids.hpp"

namespace riffle {

/// The column over `grains` (null: none). With initial = "log_law" and a drive along x, the water starts at the
/// rough-wall log law of the drive's friction velocity above the bed surface, u = (u*/kappa) ln(1 + (z - z_bed) /
/// z0), u*^2 = f (top - z_bed), z0 = initial_roughness_length, else k_s / 30 of the grains (k_s = 2.5 d, d =
/// shields_diameter) or of a rough floor, else nu / (9 u*) (the smooth wall); under a lid, the laminar Couette line
/// from the bed surface to the lid. At rest otherwise.
MeanFlowColumn initial_column(const Model& model, const Solids* grains);

}  // namespace riffle
