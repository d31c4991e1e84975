#pragma once
// ParaView output: VTK XML PolyData frames (.vtp) per particle phase and for the walls, tied together by one .pvd
// time series per phase. Point and cell arrays come from the components' field tables. The arrays' bytes are raw
// after the XML (VTK's "appended" data, the form ParaView's own writers use) or base64 inside each array's element
// ("inline"); real values in single or double precision ([output] vtk_encoding, vtk_precision).
#include <string>
#include <vector>

#include "components/fluid.hpp"
#include "components/model.hpp"
#include "components/solids.hpp"
#include "components/walls.hpp"
#include "systems/physics/geometry/periodic_box.hpp"

namespace riffle {

/// How a frame stores its arrays. The defaults are the scenes': raw bytes appended after the XML, real values in
/// single precision (a frame is for viewing and plotting: 7 digits; a position of the seed's tank to 1e-8 m), the
/// water without its dummy particles: the seed's 5 mm frame 3.4 times smaller than base64 doubles of every particle.
/// Integers (ids, kinds, flags) keep their types in either precision.
struct VtkFormat {
  bool appended = true;         ///< false: base64 inside each DataArray (XML that any parser reads whole)
  bool single_precision = true;  ///< false: Float64, the state's own values bit for bit
  /// The water's frames with the dummy layers behind the walls (which only fill the walls' kernel: no pressure of
  /// their own, 40 % of the seed tank's particles); without them, the water and the wall particles.
  bool dummy_particles = false;
};
/// The format [output] asks for.
VtkFormat vtk_format(const OutputModel& output);

/// Grains as vertices with every output field of the Solids table as point data; the positions wrapped into the
/// period along `box`'s periodic axes (a grain that crossed a seam is wrapped in the state only at the next
/// neighbour-list rebuild).
std::string solids_vtp(const Solids& solids, const PeriodicBox& box = {}, const VtkFormat& format = {});
/// MPS particles (fluid and wall; dummy too with format.dummy_particles) as vertices with every output field of the
/// FluidParticles table as point data: id, kind, velocity, pressure, number_density, free_surface, ...
std::string fluid_vtp(const FluidParticles& fluid, const VtkFormat& format = {});
/// Walls as quads (face centre +- half extents) with every output field of the Walls table as cell data.
std::string walls_vtp(const Walls& walls, const VtkFormat& format = {});
/// ParaView's parallel file (.pvtp) of one frame written in pieces, one per MPI rank: the point arrays every piece
/// holds (declared from the table's output fields, as solids_vtp and fluid_vtp write them) and the pieces' file
/// names, relative to the .pvtp's folder, in rank order; `format` the pieces' (its precision names the real arrays'
/// type).
std::string solids_pvtp(const std::vector<std::string>& pieces, const VtkFormat& format = {});
std::string fluid_pvtp(const std::vector<std::string>& pieces, const VtkFormat& format = {});
/// A .pvd collection listing `files[k]` at `times[k]`.
std::string pvd_collection(const std::vector<double>& times, const std::vector<std::string>& files);

std::string base64_encode(const void* data, std::size_t size);

/// [bytes] the size of one frame of `grains` grains and of `shown_mps_particles` MPS particles (those the frame
/// shows: without the dummies unless format.dummy_particles) in `format`, from the field tables: what `riffle check`
/// quotes before a run. Within a few hundred bytes of the written files (the XML's text is estimated).
struct FrameBytes {
  double grains = 0.0;  ///< solids_NNNNNN.vtp
  double water = 0.0;   ///< fluid_NNNNNN.vtp
};
FrameBytes estimate_frame_bytes(const VtkFormat& format, double grains, double shown_mps_particles);

}  // namespace riffle
