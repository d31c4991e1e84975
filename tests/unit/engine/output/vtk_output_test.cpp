// VTK XML output: base64 encoding and the arrays a reader will decode.
#include <doctest/doctest.h>

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

/// The decoded payload (after the UInt32 byte count) of the DataArray named `name`.
std::string array_bytes(const std::string& vtp, const std::string& name) {
  // Plain string search: std::regex recurses per character and overflows the stack on long base64 runs.
  const std::size_t tag = vtp.find("Name=\"" + name + "\"");
  REQUIRE(tag != std::string::npos);
  const std::size_t open_end = vtp.find('>', tag);
  const std::size_t close = vtp.find("</DataArray>", open_end);
  REQUIRE(close != std::string::npos);
  std::string text = vtp.substr(open_end + 1, close - open_end - 1);
  text.erase(std::remove_if(text.begin(), text.end(), [](unsigned char c) { return std::isspace(c); }), text.end());
  const std::string block = base64_decode(text);
  REQUIRE(block.size() >= 4);
  std::uint32_t count;
  std::memcpy(&count, block.data(), 4);
  REQUIRE(block.size() == 4 + count);
  return block.substr(4);
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
  const std::string vtp = solids_vtp(solids);
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
  const std::vector<double> points = values<double>(array_bytes(solids_vtp(solids, box), "Points"));
  CHECK(points[0] == doctest::Approx(0.0001).epsilon(1e-12));
  CHECK(points[1] == 0.035);
  CHECK(points[3] == doctest::Approx(0.0398).epsilon(1e-12));
  CHECK(values<double>(array_bytes(solids_vtp(solids), "Points"))[0] == 0.0401);  // no periodic axis: as it is
}

TEST_CASE("walls_vtp draws each wall as a quad around its centre") {
  const World world = initial_world(test::small_model());
  const Walls& walls = *world.walls;
  const std::string vtp = walls_vtp(walls);
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
  CHECK(values<std::int64_t>(array_bytes(vtp, "offsets")).back() == static_cast<std::int64_t>(4 * walls.size()));
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
  const std::string pvtp = solids_pvtp({"solids_000003_0.vtp", "solids_000003_1.vtp"});
  CHECK(declared_arrays(pvtp, "<PPointData", "</PPointData>", "<PDataArray") ==
        declared_arrays(solids_vtp(*grains.solids), "<PointData", "</PointData>", "<DataArray"));
  CHECK(declared_arrays(pvtp, "<PPoints", "</PPoints>", "<PDataArray") ==
        declared_arrays(solids_vtp(*grains.solids), "<Points", "</Points>", "<DataArray"));
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
  const std::string vtp = fluid_vtp(fluid);
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
  CHECK(values<std::int32_t>(array_bytes(last, "kind")) == simulation->world().fluid->kind);
  CHECK_FALSE(std::filesystem::exists(out / "solids.pvd"));  // no grains in this scene
}
