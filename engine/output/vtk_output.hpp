#pragma once
// ParaView output: VTK XML PolyData frames (.vtp, base64 binary arrays) per particle phase and for the walls, tied
// together by one .pvd time series per phase. Point and cell arrays come from the components' field tables.
#include <string>
#include <vector>

#include "components/fluid.hpp"
#include "components/solids.hpp"
#include "components/walls.hpp"
#include "systems/physics/geometry/periodic_box.hpp"

namespace riffle {

/// Grains as vertices with every output field of the Solids table as point data; the positions wrapped into the
/// period along `box`'s periodic axes (a grain that crossed a seam is wrapped in the state only at the next
/// neighbour-list rebuild).
std::string solids_vtp(const Solids& solids, const PeriodicBox& box = {});
/// MPS particles (fluid, wall and dummy) as vertices with every output field of the FluidParticles table as point
/// data: id, kind, velocity, pressure, number_density, free_surface.
std::string fluid_vtp(const FluidParticles& fluid);
/// Walls as quads (face centre +- half extents) with every output field of the Walls table as cell data.
std::string walls_vtp(const Walls& walls);
/// ParaView's parallel file (.pvtp) of one frame written in pieces, one per MPI rank: the point arrays every piece
/// holds (declared from the table's output fields, as solids_vtp and fluid_vtp write them) and the pieces' file
/// names, relative to the .pvtp's folder, in rank order.
std::string solids_pvtp(const std::vector<std::string>& pieces);
std::string fluid_pvtp(const std::vector<std::string>& pieces);
/// A .pvd collection listing `files[k]` at `times[k]`.
std::string pvd_collection(const std::vector<double>& times, const std::vector<std::string>& files);

std::string base64_encode(const void* data, std::size_t size);

}  // namespace riffle
