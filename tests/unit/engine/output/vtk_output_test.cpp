// VTK XML output: base64 encoding and the arrays a reader will decode.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <algorithm>
#include <cctype>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "engine/setup/initial_state.hpp"
#include "engine/run/simulation.hpp"
#include "engine/output/vtk_output.hpp"
#include "tests/support/test_support.hpp"

using namespace riffle;

namespace {
std::string base64_decode(const std::string& text) {
  const std::string alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  unsigned buffer = 0;
  int bits = 0;
  for (char c : text) {
    if (c == '=') break;
    buffer = (buffer << 6) | static_cast<unsigned>(alphabet.find(c));
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out += static_cast<char>((buffer >> bits) & 0xFF);
    }
  }
  return out;
}

/// The payload (after the UInt32 byte count) of the DataArray named `name`: base64 inside its element
/// (format="binary"), or raw in the AppendedData block at its offset (format="appended").
std::string array_bytes(const std::string& vtp, const std::string& name) {
  // Plain string search: std::regex recurses per character and overflows the stack on long base64 runs.
  const std::size_t tag = vtp.find("Name=\"" + name + "\"");
  REQUIRE(tag != std::string::npos);
  const std::size_t open_end = vtp.find('>', tag);
  const std::string element = vtp.substr(tag, open_end - tag);
  std::string block;
  if (element.find("format=\"appended\"") != std::string::npos) {
    const std::size_t offset_at = element.find("offset=\"");
    REQUIRE(offset_at != std::string::npos);
    const std::size_t offset = std::stoul(element.substr(offset_at + 8));
    const std::size_t data = vtp.find("<AppendedData encoding=\"raw\">");
    REQUIRE(data != std::string::npos);
    REQUIRE(data > open_end);  // the block follows every element
    const std::size_t base = vtp.find('_', data) + 1;
    REQUIRE(base + offset + 4 <= vtp.size());
    std::uint32_t count;
    std::memcpy(&count, vtp.data() + base + offset, 4);
    REQUIRE(base + offset + 4 + count <= vtp.size());
    return vtp.substr(base + offset + 4, count);
  }
  CHECK(element.find("format=\"binary\"") != std::string::npos);
  const std::size_t close = vtp.find("</DataArray>", open_end);
  REQUIRE(close != std::string::npos);
  std::string text = vtp.substr(open_end + 1, close - open_end - 1);
  text.erase(std::remove_if(text.begin(), text.end(), [](unsigned char c) { return std::isspace(c); }), text.end());
  block = base64_decode(text);
  REQUIRE(block.size() >= 4);
  std::uint32_t count;
  std::memcpy(&count, block.data(), 4);
  REQUIRE(block.size() == 4 + count);
  return block.substr(4);
}

/// The type a DataArray named `name` declares.
std::string array_type(const std::string& vtp, const std::string& name) {
  const std::size_t tag = vtp.find("Name=\"" + name + "\"");
  REQUIRE(tag != std::string::npos);
  const std::size_t type = vtp.rfind("type=\"", tag) + 6;
  return vtp.substr(type, vtp.find('"', type) - type);
}

/// Frames that hold the state's own values: double precision, in either encoding.
constexpr VtkFormat kExactAppended{true, false};
constexpr VtkFormat kExactInline{false, false};
/// The same with the water's dummy particles: every row of the table.
constexpr VtkFormat kExactEveryParticle{true, false, true};

/// The rows of the water's table a frame shows by default: all but the dummies.
template <class T>
std::vector<T> without_dummies(const FluidParticles& fluid, const std::vector<T>& field) {
  std::vector<T> kept;
  for (std::size_t i = 0; i < fluid.size(); ++i)
    if (fluid.kind[i] != static_cast<std::int32_t>(FluidKind::kDummy)) kept.push_back(field[i]);
  return kept;
}

template <class T>
std::vector<T> values(const std::string& bytes) {
  std::vector<T> out(bytes.size() / sizeof(T));
  std::memcpy(out.data(), bytes.data(), out.size() * sizeof(T));
  return out;
}
}  // namespace

TEST_CASE("base64 matches RFC 4648 test vectors") {
  CHECK(base64_encode("", 0) == "");
  CHECK(base64_encode("f", 1) == "Zg==");
  CHECK(base64_encode("fo", 2) == "Zm8=");
  CHECK(base64_encode("foo", 3) == "Zm9v");
  CHECK(base64_encode("foob", 4) == "Zm9vYg==");
  CHECK(base64_encode("fooba", 5) == "Zm9vYmE=");
  CHECK(base64_encode("foobar", 6) == "Zm9vYmFy");
}

TEST_CASE("solids_vtp carries positions and every output field exactly") {
  const World world = initial_world(test::small_model());
  const Solids& solids = *world.solids;
  for (const VtkFormat& format : {kExactAppended, kExactInline}) {
  const std::string vtp = solids_vtp(solids, {}, format);
  CHECK(vtp.find("NumberOfPoints=\"" + std::to_string(solids.size()) + "\"") != std::string::npos);
  const std::vector<double> points = values<double>(array_bytes(vtp, "Points"));
  REQUIRE(points.size() == 3 * solids.size());
  for (std::size_t i = 0; i < solids.size(); ++i)
    for (int c = 0; c < 3; ++c) CHECK(points[3 * i + static_cast<std::size_t>(c)] == solids.position[i][c]);
  CHECK(values<double>(array_bytes(vtp, "radius")) == solids.radius);
  CHECK(values<std::uint64_t>(array_bytes(vtp, "id")) == solids.id);
  CHECK(values<std::int32_t>(array_bytes(vtp, "size_class")) == solids.size_class);
  CHECK(values<double>(array_bytes(vtp, "velocity")).size() == 3 * solids.size());
  // Fields marked not for output stay out.
  CHECK(vtp.find("Name=\"moment_of_inertia\"") == std::string::npos);
  }
}

TEST_CASE("solids_vtp writes a grain past a periodic face at its place in the period") {
  // Between a seam crossing and the next neighbour rebuild a grain's state lies past the face (up to half a skin);
  // the frame shows it where it is, one period back, and leaves the other axes alone.
  const World world = initial_world(test::small_model());
  Solids solids = *world.solids;
  REQUIRE(solids.size() >= 2);
  PeriodicBox box;
  box.low = Vec3(0.0, 0.0, 0.0);
  box.length = Vec3(0.04, 0.03, 0.02);
  box.periodic = {true, false, false};
  solids.position[0] = Vec3(0.0401, 0.035, 0.01);  // past x = L; past y = 0.03 too, but y is not periodic
  solids.position[1] = Vec3(-0.0002, 0.01, 0.01);  // before x = 0
  const std::vector<double> points = values<double>(array_bytes(solids_vtp(solids, box, kExactAppended), "Points"));
  CHECK(points[0] == doctest::Approx(0.0001).epsilon(1e-12));
  CHECK(points[1] == 0.035);
  CHECK(points[3] == doctest::Approx(0.0398).epsilon(1e-12));
  CHECK(values<double>(array_bytes(solids_vtp(solids, {}, kExactAppended), "Points"))[0] == 0.0401);  // as it is
}

TEST_CASE("walls_vtp draws each wall as a quad around its centre") {
  const World world = initial_world(test::small_model());
  const Walls& walls = *world.walls;
  const std::string vtp = walls_vtp(walls, kExactInline);
  CHECK(vtp.find("NumberOfPolys=\"" + std::to_string(walls.size()) + "\"") != std::string::npos);
  const std::vector<double> points = values<double>(array_bytes(vtp, "Points"));
  REQUIRE(points.size() == 12 * walls.size());
  for (std::size_t wall = 0; wall < walls.size(); ++wall) {
    Vec3 mean = Vec3::Zero();
    for (std::size_t corner = 0; corner < 4; ++corner)
      mean += Vec3(points[12 * wall + 3 * corner], points[12 * wall + 3 * corner + 1],
                   points[12 * wall + 3 * corner + 2]);
    CHECK((mean / 4.0 - walls.point[wall]).norm() < 1e-15);
  }
  CHECK(values<std::int32_t>(array_bytes(vtp, "offsets")).back() == static_cast<std::int32_t>(4 * walls.size()));
}

TEST_CASE("pvd_collection lists every frame with its time") {
  const std::string pvd = pvd_collection({0.0, 0.5}, {"vtk/a_000000.vtp", "vtk/a_000001.vtp"});
  CHECK(pvd.find("timestep=\"0\" group=\"\" part=\"0\" file=\"vtk/a_000000.vtp\"") != std::string::npos);
  CHECK(pvd.find("timestep=\"0.5\" group=\"\" part=\"0\" file=\"vtk/a_000001.vtp\"") != std::string::npos);
}

namespace {
/// The (type, name, components) of every array declared by `tag` ("<DataArray" in a piece's PointData, "<PDataArray"
/// in a .pvtp's PPointData) between the first `open` and the next `close`, in order.
std::vector<std::string> declared_arrays(const std::string& xml, const std::string& open, const std::string& close,
                                         const std::string& tag) {
  std::vector<std::string> arrays;
  const std::size_t begin = xml.find(open), end = xml.find(close, begin);
  REQUIRE(begin != std::string::npos);
  REQUIRE(end != std::string::npos);
  for (std::size_t at = xml.find(tag, begin); at < end; at = xml.find(tag, at + 1)) {
    const std::size_t type = xml.find("type=\"", at) + 6;
    const std::size_t name = xml.find("Name=\"", at) + 6;
    const std::size_t components = xml.find("NumberOfComponents=\"", at) + 20;
    arrays.push_back(xml.substr(type, xml.find('"', type) - type) + " " + xml.substr(name, xml.find('"', name) - name) +
                     " " + xml.substr(components, xml.find('"', components) - components));
  }
  return arrays;
}
}  // namespace

TEST_CASE("solids_pvtp and fluid_pvtp declare the arrays their pieces hold and name every piece in order") {
  // ParaView's reader takes each piece's arrays from the .pvtp's declarations: they must be the pieces' own, by type,
  // name and components, in order, and the points' array too.
  const World grains = initial_world(test::small_model());
  for (const VtkFormat& format : {VtkFormat{}, kExactAppended}) {
    const std::string pvtp = solids_pvtp({"solids_000003_0.vtp", "solids_000003_1.vtp"}, format);
    CHECK(declared_arrays(pvtp, "<PPointData", "</PPointData>", "<PDataArray") ==
          declared_arrays(solids_vtp(*grains.solids, {}, format), "<PointData", "</PointData>", "<DataArray"));
    CHECK(declared_arrays(pvtp, "<PPoints", "</PPoints>", "<PDataArray") ==
          declared_arrays(solids_vtp(*grains.solids, {}, format), "<Points", "</Points>", "<DataArray"));
  }
  const std::string pvtp = solids_pvtp({"solids_000003_0.vtp", "solids_000003_1.vtp"});
  CHECK(pvtp.find("<VTKFile type=\"PPolyData\"") != std::string::npos);
  const std::size_t first = pvtp.find("<Piece Source=\"solids_000003_0.vtp\"/>");
  CHECK(first != std::string::npos);
  CHECK(pvtp.find("<Piece Source=\"solids_000003_1.vtp\"/>") > first);
  const World water = initial_world(test::fluid_model());
  CHECK(declared_arrays(fluid_pvtp({"fluid_000000_0.vtp"}), "<PPointData", "</PPointData>", "<PDataArray") ==
        declared_arrays(fluid_vtp(*water.fluid), "<PointData", "</PointData>", "<DataArray"));
}

TEST_CASE("fluid_vtp carries the MPS particles and their output fields exactly") {
  World world = initial_world(test::fluid_model());
  FluidParticles& fluid = *world.fluid;
  for (std::size_t i = 0; i < fluid.size(); ++i) {
    fluid.pressure[i] = 10.0 * static_cast<double>(i) + 0.25;
    fluid.number_density[i] = 1.0 / (1.0 + static_cast<double>(i));
    fluid.free_surface[i] = static_cast<std::int32_t>(i % 3 == 0);
  }
  const std::string vtp = fluid_vtp(fluid, kExactEveryParticle);
  CHECK(vtp.find("NumberOfPoints=\"" + std::to_string(fluid.size()) + "\"") != std::string::npos);
  CHECK(vtp.find("NumberOfVerts=\"" + std::to_string(fluid.size()) + "\"") != std::string::npos);
  const std::vector<double> points = values<double>(array_bytes(vtp, "Points"));
  REQUIRE(points.size() == 3 * fluid.size());
  for (std::size_t i = 0; i < fluid.size(); ++i)
    for (int c = 0; c < 3; ++c) CHECK(points[3 * i + static_cast<std::size_t>(c)] == fluid.position[i][c]);
  CHECK(values<std::uint64_t>(array_bytes(vtp, "id")) == fluid.id);
  CHECK(values<std::int32_t>(array_bytes(vtp, "kind")) == fluid.kind);
  CHECK(values<double>(array_bytes(vtp, "pressure")) == fluid.pressure);
  CHECK(values<double>(array_bytes(vtp, "number_density")) == fluid.number_density);
  CHECK(values<std::int32_t>(array_bytes(vtp, "free_surface")) == fluid.free_surface);
  const std::vector<double> velocity = values<double>(array_bytes(vtp, "velocity"));
  REQUIRE(velocity.size() == 3 * fluid.size());
  CHECK(velocity[0] == fluid.velocity[0].x());
  CHECK(velocity[2] == fluid.velocity[0].z());
  for (const char* hidden : {"rest_position", "predicted_position", "density_rate", "\"position"})
    CHECK_MESSAGE(vtp.find(std::string("Name=\"") + hidden) == std::string::npos, hidden);
}

TEST_CASE("a run with a fluid writes fluid frames and the fluid.pvd series") {
  const auto out = test::scratch_dir("vtk_fluid_run");
  Model model = test::fluid_model();
  model.output.vtk_interval = 0.005;
  auto simulation = Simulation::from_model(std::move(model));
  RunOptions options;
  options.out_dir = out.string();
  options.threads = 1;
  REQUIRE(simulation->run(options).exit_code == kExitOk);
  const std::string pvd = test::file_text(out / "fluid.pvd");
  for (const char* frame : {"vtk/fluid_000000.vtp", "vtk/fluid_000001.vtp", "vtk/fluid_000002.vtp"}) {
    CHECK_MESSAGE(pvd.find(std::string("file=\"") + frame + "\"") != std::string::npos, frame);
    CHECK_MESSAGE(std::filesystem::exists(out / frame), frame);
  }
  const std::string last = test::file_text(out / "vtk/fluid_000002.vtp");
  const FluidParticles& fluid = *simulation->world().fluid;
  CHECK(values<std::int32_t>(array_bytes(last, "kind")) == without_dummies(fluid, fluid.kind));
  CHECK_FALSE(std::filesystem::exists(out / "solids.pvd"));  // no grains in this scene
}

TEST_CASE("a frame in single precision holds each real value rounded to the nearest float, the integers exact") {
  // The scenes' default: points, velocities, pressures as Float32; ids, kinds and flags in their own types.
  World world = initial_world(test::fluid_model());
  FluidParticles& fluid = *world.fluid;
  for (std::size_t i = 0; i < fluid.size(); ++i) fluid.pressure[i] = 1234.5678901234 + 0.1 * static_cast<double>(i);
  const std::string vtp = fluid_vtp(fluid, VtkFormat{true, true, true});  // the defaults, the dummies included
  CHECK(array_type(vtp, "Points") == "Float32");
  CHECK(array_type(vtp, "pressure") == "Float32");
  CHECK(array_type(vtp, "velocity") == "Float32");
  CHECK(array_type(vtp, "id") == "UInt64");
  CHECK(array_type(vtp, "kind") == "Int32");
  CHECK(array_type(vtp, "connectivity") == "Int32");
  const std::vector<float> points = values<float>(array_bytes(vtp, "Points"));
  REQUIRE(points.size() == 3 * fluid.size());
  const std::vector<float> pressure = values<float>(array_bytes(vtp, "pressure"));
  REQUIRE(pressure.size() == fluid.size());
  for (std::size_t i = 0; i < fluid.size(); ++i) {
    CHECK(pressure[i] == static_cast<float>(fluid.pressure[i]));
    for (int c = 0; c < 3; ++c) CHECK(points[3 * i + static_cast<std::size_t>(c)] == static_cast<float>(fluid.position[i][c]));
  }
  CHECK(values<std::uint64_t>(array_bytes(vtp, "id")) == fluid.id);
  CHECK(values<std::int32_t>(array_bytes(vtp, "kind")) == fluid.kind);
  const std::vector<std::int32_t> offsets = values<std::int32_t>(array_bytes(vtp, "offsets"));
  REQUIRE(offsets.size() == fluid.size());
  CHECK(offsets.back() == static_cast<std::int32_t>(fluid.size()));
}

TEST_CASE("appended and inline frames hold the same arrays, and the appended block is where its offsets say") {
  const World world = initial_world(test::small_model());
  const Solids& solids = *world.solids;
  for (const bool single : {true, false}) {
    const std::string appended = solids_vtp(solids, {}, VtkFormat{true, single});
    const std::string inline_text = solids_vtp(solids, {}, VtkFormat{false, single});
    // The same elements but for their format: every array's bytes equal.
    const std::vector<std::string> arrays = declared_arrays(inline_text, "<PointData", "</PointData>", "<DataArray");
    REQUIRE(arrays.size() >= 4);
    CHECK(arrays == declared_arrays(appended, "<PointData", "</PointData>", "<DataArray"));
    for (const char* name : {"Points", "connectivity", "offsets", "radius", "velocity", "id", "size_class"})
      CHECK_MESSAGE(array_bytes(appended, name) == array_bytes(inline_text, name), name);
    // Appended: the XML ends with the block, which holds the arrays back to back (each a UInt32 count and its
    // bytes) from offset 0 to its end; nothing of the arrays inside the elements.
    CHECK(appended.find("</DataArray>") == std::string::npos);
    const std::size_t data = appended.find("<AppendedData encoding=\"raw\">\n   _");
    REQUIRE(data != std::string::npos);
    const std::size_t base = appended.find('_', data) + 1;
    const std::string tail = "\n  </AppendedData>\n</VTKFile>\n";
    REQUIRE(appended.size() > base + tail.size());
    CHECK(appended.compare(appended.size() - tail.size(), tail.size(), tail) == 0);
    std::size_t expected_offset = 0, arrays_seen = 0;
    for (std::size_t at = appended.find("offset=\""); at < data; at = appended.find("offset=\"", at + 1)) {
      CHECK(std::stoul(appended.substr(at + 8)) == expected_offset);
      std::uint32_t count;
      std::memcpy(&count, appended.data() + base + expected_offset, 4);
      expected_offset += 4 + count;
      ++arrays_seen;
    }
    CHECK(arrays_seen == arrays.size() + 3);  // the point data, the points, connectivity and offsets
    CHECK(base + expected_offset == appended.size() - tail.size());
  }
}

TEST_CASE("[output] vtk_encoding and vtk_precision choose the frames' format, and a run writes what they ask") {
  const auto write_run = [](const char* name, OutputModel::VtkEncoding encoding, OutputModel::VtkPrecision precision) {
    const auto out = test::scratch_dir(name);
    Model model = test::small_model();
    model.output.vtk_interval = 1.0;
    model.output.vtk_encoding = encoding;
    model.output.vtk_precision = precision;
    auto simulation = Simulation::from_model(std::move(model));
    RunOptions options;
    options.out_dir = out.string();
    options.threads = 1;
    options.until = 0.0;
    REQUIRE(simulation->run(options).exit_code == kExitOk);
    return test::file_text(out / "vtk/solids_000000.vtp");
  };
  const std::string fast = write_run("vtk_format_default", OutputModel::VtkEncoding::kAppended,
                                     OutputModel::VtkPrecision::kSingle);
  CHECK(fast.find("format=\"appended\"") != std::string::npos);
  CHECK(array_type(fast, "Points") == "Float32");
  const std::string exact = write_run("vtk_format_exact", OutputModel::VtkEncoding::kInline,
                                      OutputModel::VtkPrecision::kDouble);
  CHECK(exact.find("format=\"appended\"") == std::string::npos);
  CHECK(array_type(exact, "Points") == "Float64");
  CHECK(fast.size() * 2 < exact.size());
  const VtkFormat defaults = vtk_format(OutputModel{});
  CHECK(defaults.appended);
  CHECK(defaults.single_precision);
}

TEST_CASE("the water's frames leave the dummy particles out unless asked for them") {
  // The dummy layers behind the walls only fill the walls' kernel; a frame shows the water and the wall particles,
  // each with its own values, in table order.
  World world = initial_world(test::fluid_model());
  FluidParticles& fluid = *world.fluid;
  for (std::size_t i = 0; i < fluid.size(); ++i) fluid.pressure[i] = 3.0 * static_cast<double>(i);
  const std::size_t dummies = static_cast<std::size_t>(
      std::count(fluid.kind.begin(), fluid.kind.end(), static_cast<std::int32_t>(FluidKind::kDummy)));
  REQUIRE(dummies > 0);
  REQUIRE(dummies < fluid.size());
  const std::string vtp = fluid_vtp(fluid, kExactAppended);
  CHECK(vtp.find("NumberOfPoints=\"" + std::to_string(fluid.size() - dummies) + "\"") != std::string::npos);
  CHECK(vtp.find("NumberOfVerts=\"" + std::to_string(fluid.size() - dummies) + "\"") != std::string::npos);
  CHECK(values<std::uint64_t>(array_bytes(vtp, "id")) == without_dummies(fluid, fluid.id));
  CHECK(values<double>(array_bytes(vtp, "pressure")) == without_dummies(fluid, fluid.pressure));
  const std::vector<double> points = values<double>(array_bytes(vtp, "Points"));
  const std::vector<Vec3> kept = without_dummies(fluid, fluid.position);
  REQUIRE(points.size() == 3 * kept.size());
  for (std::size_t k = 0; k < kept.size(); ++k) CHECK(points[3 * k + 2] == kept[k].z());
  const std::vector<std::int32_t> offsets = values<std::int32_t>(array_bytes(vtp, "offsets"));
  CHECK(offsets.back() == static_cast<std::int32_t>(kept.size()));
  Model model = test::fluid_model();
  CHECK_FALSE(vtk_format(model.output).dummy_particles);
  model.output.vtk_dummy_particles = true;
  CHECK(vtk_format(model.output).dummy_particles);
}

TEST_CASE("estimate_frame_bytes gives a frame's size in every format before it is written") {
  // What `riffle check` quotes for a run's frames: within 1 % (and a few hundred bytes of XML) of the files.
  const World grains = initial_world(test::small_model());
  const World water = initial_world(test::fluid_model());
  const FluidParticles& fluid = *water.fluid;
  const double dummies = static_cast<double>(
      std::count(fluid.kind.begin(), fluid.kind.end(), static_cast<std::int32_t>(FluidKind::kDummy)));
  for (const bool appended : {true, false})
    for (const bool single : {true, false})
      for (const bool with_dummies : {false, true}) {
        const VtkFormat format{appended, single, with_dummies};
        CAPTURE(appended);
        CAPTURE(single);
        CAPTURE(with_dummies);
        const double shown = static_cast<double>(fluid.size()) - (with_dummies ? 0.0 : dummies);
        const FrameBytes estimate =
            estimate_frame_bytes(format, static_cast<double>(grains.solids->size()), shown);
        const double solids_file = static_cast<double>(solids_vtp(*grains.solids, {}, format).size());
        const double fluid_file = static_cast<double>(fluid_vtp(fluid, format).size());
        CHECK(std::abs(estimate.grains - solids_file) < 0.01 * solids_file + 600.0);
        CHECK(std::abs(estimate.water - fluid_file) < 0.01 * fluid_file + 600.0);
      }
  const FrameBytes none = estimate_frame_bytes(VtkFormat{}, 0.0, 0.0);
  CHECK(none.grains == 0.0);
  CHECK(none.water == 0.0);
}
