#include "engine/output/vtk_output.hpp"

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <type_traits>

namespace riffle {

namespace {

template <class T>
const char* vtk_type() {
  if constexpr (std::is_same_v<T, double> || std::is_same_v<T, Vec3>) return "Float64";
  else if constexpr (std::is_same_v<T, std::int32_t>) return "Int32";
  else if constexpr (std::is_same_v<T, std::uint64_t>) return "UInt64";
  else return nullptr;
}

/// One <DataArray> in VTK's inline binary form: base64 of a UInt32 byte count followed by the raw values.
std::string data_array(const char* name, const char* type, int components, const void* values, std::size_t bytes) {
  std::string block(sizeof(std::uint32_t) + bytes, '\0');
  const auto count = static_cast<std::uint32_t>(bytes);
  std::memcpy(block.data(), &count, sizeof count);
  if (bytes) std::memcpy(block.data() + sizeof count, values, bytes);
  char head[256];
  std::snprintf(head, sizeof head,
                "        <DataArray type=\"%s\" Name=\"%s\" NumberOfComponents=\"%d\" format=\"binary\">\n", type,
                name, components);
  return std::string(head) + "          " + base64_encode(block.data(), block.size()) + "\n        </DataArray>\n";
}

template <class T>
std::string field_array(const char* name, const std::vector<T>& field) {
  if constexpr (std::is_same_v<T, Vec3>) {
    std::vector<double> flat(3 * field.size());
    for (std::size_t i = 0; i < field.size(); ++i)
      for (int c = 0; c < 3; ++c) flat[3 * i + static_cast<std::size_t>(c)] = field[i][c];
    return data_array(name, "Float64", 3, flat.data(), flat.size() * sizeof(double));
  } else {
    return data_array(name, vtk_type<T>(), 1, field.data(), field.size() * sizeof(T));
  }
}

/// Every output field of a component's table, as the arrays of one PointData or CellData block.
template <class Component>
std::string field_arrays(const Component& component) {
  std::string out;
  for_each_field_in_order(component, [&](const FieldInfo& info, const auto& field) {
    using T = typename std::decay_t<decltype(field)>::value_type;
    if constexpr (!std::is_same_v<T, std::string>)
      if (info.output) out += field_array(info.name, field);
  });
  return out;
}

std::string points_block(const std::vector<double>& xyz) {
  return "      <Points>\n" + data_array("Points", "Float64", 3, xyz.data(), xyz.size() * sizeof(double)) +
         "      </Points>\n";
}

std::string connectivity_block(const char* tag, const std::vector<std::int64_t>& connectivity,
                               const std::vector<std::int64_t>& offsets) {
  return std::string("      <") + tag + ">\n" +
         data_array("connectivity", "Int64", 1, connectivity.data(), connectivity.size() * sizeof(std::int64_t)) +
         data_array("offsets", "Int64", 1, offsets.data(), offsets.size() * sizeof(std::int64_t)) + "      </" + tag +
         ">\n";
}

const char* kHeader =
    "<?xml version=\"1.0\"?>\n"
    "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt32\">\n"
    "  <PolyData>\n";
const char* kFooter = "    </Piece>\n  </PolyData>\n</VTKFile>\n";

}  // namespace

std::string base64_encode(const void* data, std::size_t size) {
  static const char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* bytes = static_cast<const unsigned char*>(data);
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < size; i += 3) {
    const std::uint32_t triple = (bytes[i] << 16) | (bytes[i + 1] << 8) | bytes[i + 2];
    out += kAlphabet[(triple >> 18) & 63];
    out += kAlphabet[(triple >> 12) & 63];
    out += kAlphabet[(triple >> 6) & 63];
    out += kAlphabet[triple & 63];
  }
  if (i < size) {
    const std::uint32_t triple = (bytes[i] << 16) | (i + 1 < size ? bytes[i + 1] << 8 : 0);
    out += kAlphabet[(triple >> 18) & 63];
    out += kAlphabet[(triple >> 12) & 63];
    out += i + 1 < size ? kAlphabet[(triple >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

namespace {
/// Particles of any SoA component as vertices at `position`, its output fields as point data.
/// Positions wrapped into `box`'s period (unchanged without periodic axes).
template <class Component>
std::string particles_vtp(const Component& particles, const char* scalars, const PeriodicBox& box = {}) {
  const std::size_t count = particles.size();
  std::vector<double> xyz(3 * count);
  std::vector<std::int64_t> connectivity(count), offsets(count);
  for (std::size_t i = 0; i < count; ++i) {
    const Vec3 position = box.wrap(particles.position[i]);  // unchanged along non-periodic axes
    for (int c = 0; c < 3; ++c) xyz[3 * i + static_cast<std::size_t>(c)] = position[c];
    connectivity[i] = static_cast<std::int64_t>(i);
    offsets[i] = static_cast<std::int64_t>(i + 1);
  }
  char piece[160];
  std::snprintf(piece, sizeof piece,
                "    <Piece NumberOfPoints=\"%zu\" NumberOfVerts=\"%zu\" NumberOfLines=\"0\" NumberOfStrips=\"0\" "
                "NumberOfPolys=\"0\">\n",
                count, count);
  return std::string(kHeader) + piece + "      <PointData Scalars=\"" + scalars + "\">\n" +
         field_arrays(particles) + "      </PointData>\n" + points_block(xyz) +
         connectivity_block("Verts", connectivity, offsets) + kFooter;
}

/// The .pvtp of a frame of `Component` in pieces: each output field as a PDataArray of its type and components.
template <class Component>
std::string particles_pvtp(const char* scalars, const std::vector<std::string>& pieces) {
  std::string out = std::string(
                        "<?xml version=\"1.0\"?>\n"
                        "<VTKFile type=\"PPolyData\" version=\"1.0\" byte_order=\"LittleEndian\" "
                        "header_type=\"UInt32\">\n"
                        "  <PPolyData GhostLevel=\"0\">\n"
                        "    <PPointData Scalars=\"") +
                    scalars + "\">\n";
  char line[256];
  const Component schema;  // an empty table: its fields' names and types
  for_each_field_in_order(schema, [&](const FieldInfo& info, const auto& field) {
    using T = typename std::decay_t<decltype(field)>::value_type;
    if constexpr (!std::is_same_v<T, std::string>) {
      if (!info.output) return;
      std::snprintf(line, sizeof line, "      <PDataArray type=\"%s\" Name=\"%s\" NumberOfComponents=\"%d\"/>\n",
                    vtk_type<T>(), info.name, std::is_same_v<T, Vec3> ? 3 : 1);
      out += line;
    }
  });
  out +=
      "    </PPointData>\n"
      "    <PPoints>\n"
      "      <PDataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"/>\n"
      "    </PPoints>\n";
  for (const std::string& piece : pieces) out += "    <Piece Source=\"" + piece + "\"/>\n";
  return out + "  </PPolyData>\n</VTKFile>\n";
}
}  // namespace

std::string solids_vtp(const Solids& solids, const PeriodicBox& box) { return particles_vtp(solids, "radius", box); }

std::string solids_pvtp(const std::vector<std::string>& pieces) { return particles_pvtp<Solids>("radius", pieces); }

std::string fluid_pvtp(const std::vector<std::string>& pieces) {
  return particles_pvtp<FluidParticles>("pressure", pieces);
}

std::string fluid_vtp(const FluidParticles& fluid) { return particles_vtp(fluid, "pressure"); }

std::string walls_vtp(const Walls& walls) {
  const std::size_t count = walls.size();
  std::vector<double> xyz;
  std::vector<std::int64_t> connectivity, offsets;
  const double corner_signs[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  for (std::size_t wall = 0; wall < count; ++wall) {
    for (const auto& sign : corner_signs) {
      const Vec3 corner = walls.point[wall] + sign[0] * walls.half_extent_u[wall] + sign[1] * walls.half_extent_v[wall];
      xyz.insert(xyz.end(), {corner[0], corner[1], corner[2]});
      connectivity.push_back(static_cast<std::int64_t>(connectivity.size()));
    }
    offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
  }
  char piece[160];
  std::snprintf(piece, sizeof piece,
                "    <Piece NumberOfPoints=\"%zu\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" "
                "NumberOfPolys=\"%zu\">\n",
                4 * count, count);
  return std::string(kHeader) + piece + "      <CellData>\n" + field_arrays(walls) + "      </CellData>\n" +
         points_block(xyz) + connectivity_block("Polys", connectivity, offsets) + kFooter;
}

std::string pvd_collection(const std::vector<double>& times, const std::vector<std::string>& files) {
  std::string out =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "  <Collection>\n";
  char line[512];
  for (std::size_t k = 0; k < times.size() && k < files.size(); ++k) {
    std::snprintf(line, sizeof line, "    <DataSet timestep=\"%.9g\" group=\"\" part=\"0\" file=\"%s\"/>\n", times[k],
                  files[k].c_str());
    out += line;
  }
  return out + "  </Collection>\n</VTKFile>\n";
}

}  // namespace riffle
