#include "engine/output/vtk_output.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <type_traits>

namespace riffle {

namespace {

/// The VTK type of a frame's real values in `format`.
const char* real_type(const VtkFormat& format) { return format.single_precision ? "Float32" : "Float64"; }

/// How a field of element type T is written in `format`: its VTK type, its components and its bytes per row. Real
/// fields (double, Vec3) follow the frame's precision; integers keep their own type. The frames, their .pvtp
/// declarations and the size estimate all ask here.
template <class T>
const char* field_type(const VtkFormat& format) {
  if constexpr (std::is_same_v<T, double> || std::is_same_v<T, Vec3>) return real_type(format);
  else if constexpr (std::is_same_v<T, std::int32_t>) return "Int32";
  else if constexpr (std::is_same_v<T, std::uint64_t>) return "UInt64";
  else return nullptr;
}
template <class T>
constexpr int field_components() {
  return std::is_same_v<T, Vec3> ? 3 : 1;
}
template <class T>
double field_row_bytes(const VtkFormat& format) {
  if constexpr (std::is_same_v<T, double> || std::is_same_v<T, Vec3>)
    return field_components<T>() * (format.single_precision ? 4.0 : 8.0);
  else return static_cast<double>(sizeof(T));
}

/// The arrays of one frame as they are written: each DataArray element (inline: its base64 text inside; appended:
/// its offset into the block after the XML), and the appended block, each array a UInt32 byte count followed by
/// its raw bytes.
class FrameArrays {
 public:
  explicit FrameArrays(const VtkFormat& format) : format_(format) {}

  const VtkFormat& format() const { return format_; }

  /// One DataArray of `bytes` raw bytes of `type`.
  std::string array(const char* name, const char* type, int components, const void* values, std::size_t bytes) {
    const auto count = static_cast<std::uint32_t>(bytes);
    char head[320];
    if (format_.appended) {
      std::snprintf(head, sizeof head,
                    "        <DataArray type=\"%s\" Name=\"%s\" NumberOfComponents=\"%d\" format=\"appended\" "
                    "offset=\"%zu\"/>\n",
                    type, name, components, appended_.size());
      appended_.append(reinterpret_cast<const char*>(&count), sizeof count);
      if (bytes) appended_.append(static_cast<const char*>(values), bytes);
      return head;
    }
    std::string block(sizeof count + bytes, '\0');
    std::memcpy(block.data(), &count, sizeof count);
    if (bytes) std::memcpy(block.data() + sizeof count, values, bytes);
    std::snprintf(head, sizeof head,
                  "        <DataArray type=\"%s\" Name=\"%s\" NumberOfComponents=\"%d\" format=\"binary\">\n", type,
                  name, components);
    return std::string(head) + "          " + base64_encode(block.data(), block.size()) + "\n        </DataArray>\n";
  }

  /// Real values (`components` per point) in the frame's precision.
  std::string reals(const char* name, int components, const double* values, std::size_t count) {
    if (!format_.single_precision) return array(name, "Float64", components, values, count * sizeof(double));
    narrowed_.resize(count);
    for (std::size_t k = 0; k < count; ++k) narrowed_[k] = static_cast<float>(values[k]);
    return array(name, "Float32", components, narrowed_.data(), count * sizeof(float));
  }

  /// Vertex or cell indices: Int32 while they fit (every frame riffle writes), else Int64.
  std::string indices(const char* name, const std::vector<std::int64_t>& values) {
    const bool fits = values.empty() || values.back() <= std::numeric_limits<std::int32_t>::max();
    if (!fits) return array(name, "Int64", 1, values.data(), values.size() * sizeof(std::int64_t));
    std::vector<std::int32_t> narrow(values.begin(), values.end());
    return array(name, "Int32", 1, narrow.data(), narrow.size() * sizeof(std::int32_t));
  }

  /// What follows the frame's XML elements: the appended block (empty inline).
  std::string appended_data() const {
    if (!format_.appended) return "";
    return "  <AppendedData encoding=\"raw\">\n   _" + appended_ + "\n  </AppendedData>\n";
  }

 private:
  VtkFormat format_;
  std::string appended_;
  std::vector<float> narrowed_;
};

/// The rows a frame writes: every one (`rows` null), or those listed.
template <class T>
const std::vector<T>& rows_of(const std::vector<T>& field, const std::vector<std::uint32_t>* rows,
                              std::vector<T>& scratch) {
  if (rows == nullptr) return field;
  scratch.resize(rows->size());
  for (std::size_t k = 0; k < rows->size(); ++k) scratch[k] = field[(*rows)[k]];
  return scratch;
}

template <class T>
std::string field_array(FrameArrays& arrays, const char* name, const std::vector<T>& all,
                        const std::vector<std::uint32_t>* rows) {
  std::vector<T> scratch;
  const std::vector<T>& field = rows_of(all, rows, scratch);
  if constexpr (std::is_same_v<T, Vec3>) {
    std::vector<double> flat(3 * field.size());
    for (std::size_t i = 0; i < field.size(); ++i)
      for (int c = 0; c < 3; ++c) flat[3 * i + static_cast<std::size_t>(c)] = field[i][c];
    return arrays.reals(name, 3, flat.data(), flat.size());
  } else if constexpr (std::is_same_v<T, double>) {
    return arrays.reals(name, 1, field.data(), field.size());
  } else {
    return arrays.array(name, field_type<T>(arrays.format()), 1, field.data(), field.size() * sizeof(T));
  }
}

/// Every output field of a component's table, as the arrays of one PointData or CellData block: of every row, or
/// of `rows`.
template <class Component>
std::string field_arrays(FrameArrays& arrays, const Component& component,
                         const std::vector<std::uint32_t>* rows = nullptr) {
  std::string out;
  for_each_field_in_order(component, [&](const FieldInfo& info, const auto& field) {
    using T = typename std::decay_t<decltype(field)>::value_type;
    if constexpr (!std::is_same_v<T, std::string>)
      if (info.output) out += field_array(arrays, info.name, field, rows);
  });
  return out;
}

std::string points_block(FrameArrays& arrays, const std::vector<double>& xyz) {
  return "      <Points>\n" + arrays.reals("Points", 3, xyz.data(), xyz.size()) + "      </Points>\n";
}

std::string connectivity_block(FrameArrays& arrays, const char* tag, const std::vector<std::int64_t>& connectivity,
                               const std::vector<std::int64_t>& offsets) {
  // One statement each: the operands of one + are evaluated in no fixed order, and the appended block's order
  // must be the elements' (readers take the offsets, but a frame should not depend on the compiler).
  std::string out = std::string("      <") + tag + ">\n";
  out += arrays.indices("connectivity", connectivity);
  out += arrays.indices("offsets", offsets);
  return out + "      </" + tag + ">\n";
}

const char* kHeader =
    "<?xml version=\"1.0\"?>\n"
    "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt32\">\n"
    "  <PolyData>\n";
/// The end of a frame: its piece and PolyData closed, the appended data (if any), the file closed.
std::string footer(const FrameArrays& arrays) {
  return "    </Piece>\n  </PolyData>\n" + arrays.appended_data() + "</VTKFile>\n";
}

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
/// Positions wrapped into `box`'s period (unchanged without periodic axes). Every particle, or those `rows` lists.
template <class Component>
std::string particles_vtp(const Component& particles, const char* scalars, const PeriodicBox& box,
                          const VtkFormat& format, const std::vector<std::uint32_t>* rows = nullptr) {
  FrameArrays arrays(format);
  const std::size_t count = rows ? rows->size() : particles.size();
  std::vector<double> xyz(3 * count);
  std::vector<std::int64_t> connectivity(count), offsets(count);
  for (std::size_t i = 0; i < count; ++i) {
    const Vec3 position = box.wrap(particles.position[rows ? (*rows)[i] : i]);  // as it is along non-periodic axes
    for (int c = 0; c < 3; ++c) xyz[3 * i + static_cast<std::size_t>(c)] = position[c];
    connectivity[i] = static_cast<std::int64_t>(i);
    offsets[i] = static_cast<std::int64_t>(i + 1);
  }
  char piece[160];
  std::snprintf(piece, sizeof piece,
                "    <Piece NumberOfPoints=\"%zu\" NumberOfVerts=\"%zu\" NumberOfLines=\"0\" NumberOfStrips=\"0\" "
                "NumberOfPolys=\"0\">\n",
                count, count);
  // Built in this order: the arrays' offsets into the appended block follow it.
  std::string out = std::string(kHeader) + piece + "      <PointData Scalars=\"" + scalars + "\">\n";
  out += field_arrays(arrays, particles, rows);
  out += "      </PointData>\n";
  out += points_block(arrays, xyz);
  out += connectivity_block(arrays, "Verts", connectivity, offsets);
  return out + footer(arrays);
}

/// The .pvtp of a frame of `Component` in pieces: each output field as a PDataArray of its type and components.
template <class Component>
std::string particles_pvtp(const char* scalars, const std::vector<std::string>& pieces, const VtkFormat& format) {
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
                    field_type<T>(format), info.name, field_components<T>());
      out += line;
    }
  });
  out +=
      "    </PPointData>\n"
      "    <PPoints>\n"
      "      <PDataArray type=\"" +
      std::string(real_type(format)) +
      "\" Name=\"Points\" NumberOfComponents=\"3\"/>\n"
      "    </PPoints>\n";
  for (const std::string& piece : pieces) out += "    <Piece Source=\"" + piece + "\"/>\n";
  return out + "  </PPolyData>\n</VTKFile>\n";
}
}  // namespace

VtkFormat vtk_format(const OutputModel& output) {
  VtkFormat format;
  format.appended = output.vtk_encoding == OutputModel::VtkEncoding::kAppended;
  format.single_precision = output.vtk_precision == OutputModel::VtkPrecision::kSingle;
  format.dummy_particles = output.vtk_dummy_particles;
  return format;
}

std::string solids_vtp(const Solids& solids, const PeriodicBox& box, const VtkFormat& format) {
  return particles_vtp(solids, "radius", box, format);
}

std::string solids_pvtp(const std::vector<std::string>& pieces, const VtkFormat& format) {
  return particles_pvtp<Solids>("radius", pieces, format);
}

std::string fluid_pvtp(const std::vector<std::string>& pieces, const VtkFormat& format) {
  return particles_pvtp<FluidParticles>("pressure", pieces, format);
}

std::string fluid_vtp(const FluidParticles& fluid, const VtkFormat& format) {
  if (format.dummy_particles) return particles_vtp(fluid, "pressure", PeriodicBox{}, format);
  std::vector<std::uint32_t> shown;
  shown.reserve(fluid.size());
  for (std::size_t i = 0; i < fluid.size(); ++i)
    if (fluid.kind[i] != static_cast<std::int32_t>(FluidKind::kDummy)) shown.push_back(static_cast<std::uint32_t>(i));
  return particles_vtp(fluid, "pressure", PeriodicBox{}, format, &shown);
}

std::string walls_vtp(const Walls& walls, const VtkFormat& format) {
  FrameArrays arrays(format);
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
  std::string out = std::string(kHeader) + piece + "      <CellData>\n";
  out += field_arrays(arrays, walls);
  out += "      </CellData>\n";
  out += points_block(arrays, xyz);
  out += connectivity_block(arrays, "Polys", connectivity, offsets);
  return out + footer(arrays);
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

namespace {
/// [bytes] of a frame of `rows` rows of `Component` in `format`: per array its UInt32 count and its values (base64:
/// four characters per three bytes), plus about 105 (appended) or 125 (inline) characters of XML each and 600 for
/// the file's frame.
template <class Component>
double component_frame_bytes(const VtkFormat& format, double rows) {
  double payload = 0.0, arrays = 0.0;
  const auto add = [&](double bytes) {
    payload += format.appended ? 4.0 + bytes : std::ceil((4.0 + bytes) / 3.0) * 4.0;
    arrays += 1.0;
  };
  const Component schema;  // an empty table: its fields' names and types
  for_each_field_in_order(schema, [&](const FieldInfo& info, const auto& field) {
    using T = typename std::decay_t<decltype(field)>::value_type;
    if constexpr (!std::is_same_v<T, std::string>) {
      if (!info.output) return;
      add(field_row_bytes<T>(format) * rows);
    }
  });
  add(field_row_bytes<Vec3>(format) * rows);  // the points
  const double index = rows <= static_cast<double>(std::numeric_limits<std::int32_t>::max()) ? 4.0 : 8.0;
  add(index * rows);  // connectivity
  add(index * rows);  // offsets
  return payload + (format.appended ? 105.0 : 125.0) * arrays + 600.0;
}
}  // namespace

FrameBytes estimate_frame_bytes(const VtkFormat& format, double grains, double shown_mps_particles) {
  FrameBytes bytes;
  if (grains > 0.0) bytes.grains = component_frame_bytes<Solids>(format, grains);
  if (shown_mps_particles > 0.0) bytes.water = component_frame_bytes<FluidParticles>(format, shown_mps_particles);
  return bytes;
}

}  // namespace riffle
