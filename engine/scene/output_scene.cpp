#include "engine/scene/output_scene.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>
#include <unordered_map>
#include <utility>

#include "systems/physics/measures/bed_statistics.hpp"
#include "systems/physics/measures/bedload_probes.hpp"
#include "engine/setup/fluid_layout.hpp"
#include "engine/setup/initial_state.hpp"

namespace riffle {

namespace fs = std::filesystem;

const std::vector<std::string>& reserved_output_files() {
  static const std::vector<std::string> names = {"diagnostics.csv", "timings.csv",  "bed_profile.csv",
                                                 "class_centroids.csv", "riffle.log", "solids.pvd",
                                                 "walls.pvd",       "vtk",          "checkpoints"};
  return names;
}

namespace {

/// One past the largest grain id the run starts with: the grains of [solids] initial_state (ids below its next_id)
/// and then the scene's own spheres, numbered on from there. nullopt if the initial state cannot be read (that is
/// reported where [solids] is read).
std::optional<std::uint64_t> grain_id_limit(const Model& model) {
  std::uint64_t limit = static_cast<std::uint64_t>(scene_sphere_count(model.solids));
  if (!model.solids.initial_state.empty()) {
    if (!model.solids.initial_grains) return std::nullopt;
    limit += model.solids.initial_grains->next_id;
  }
  return limit;
}

/// Walls the tank has (the faces not listed as open), in the order tank_walls() creates them.
std::size_t wall_count(const Model& model) {
  std::size_t periodic_faces = 0;  // a periodic axis has no walls (and none of its faces is open)
  for (bool periodic : model.tank.periodic) periodic_faces += periodic ? 2 : 0;
  return 6 - model.tank.open_faces.size() - periodic_faces;
}

const std::vector<std::pair<std::string, ProbeModel::Kind>>& probe_kinds() {
  static const std::vector<std::pair<std::string, ProbeModel::Kind>> kinds = {
      {"grains", ProbeModel::Kind::kGrains},
      {"wall_forces", ProbeModel::Kind::kWallForces},
      {"fluid_pressure", ProbeModel::Kind::kFluidPressure},
      {"wave_gauge", ProbeModel::Kind::kWaveGauge},
      {"surge_front", ProbeModel::Kind::kSurgeFront},
      {"fluid_totals", ProbeModel::Kind::kFluidTotals},
      {"pressure_transducer", ProbeModel::Kind::kPressureTransducer},
      {"driven_flow", ProbeModel::Kind::kDrivenFlow},
      {"moving_fraction", ProbeModel::Kind::kMovingFraction},
      {"packing_density", ProbeModel::Kind::kPackingDensity},
      {"bedload_flux", ProbeModel::Kind::kBedloadFlux},
      {"velocity_profile", ProbeModel::Kind::kVelocityProfile},
      {"bed_shear_stress", ProbeModel::Kind::kBedShearStress},
      {"mean_flow_profile", ProbeModel::Kind::kMeanFlowProfile},
      {"bedload_transport", ProbeModel::Kind::kBedloadTransport}};
  return kinds;
}

bool is_fluid_probe(ProbeModel::Kind kind) {
  return kind == ProbeModel::Kind::kFluidPressure || kind == ProbeModel::Kind::kWaveGauge ||
         kind == ProbeModel::Kind::kSurgeFront || kind == ProbeModel::Kind::kFluidTotals ||
         kind == ProbeModel::Kind::kPressureTransducer || kind == ProbeModel::Kind::kDrivenFlow;
}

/// The `points` of a fluid_pressure (width 3) or wave_gauge (width 2) probe. Each must lie in the tank's inner box
/// at rest, boundary included (a sensor on a wall): points are in the tank frame, and one outside is most likely a
/// unit or frame mistake.
std::vector<Vec3> read_points(TableReader& table, const Model& model, std::size_t width) {
  const std::size_t problems_before = table.problem_count();
  std::vector<Vec3> points = table.points("points", true, width, "m");
  if (points.empty() && table.problem_count() == problems_before)
    table.problem("points", "expected at least one point");
  const Vec3 low = model.tank.origin;
  const Vec3 high = low + model.tank.size;
  if (!(model.tank.size.minCoeff() > 0.0)) return points;  // a bad tank is reported where [tank] is read
  const double slack = 1e-9 * model.tank.size.maxCoeff();
  for (std::size_t k = 0; k < points.size(); ++k) {
    bool inside = true;
    for (std::size_t axis = 0; axis < width; ++axis) {
      const auto a = static_cast<Eigen::Index>(axis);
      inside = inside && points[k][a] >= low[a] - slack && points[k][a] <= high[a] + slack;
    }
    if (!inside) {
      char message[256];
      std::snprintf(message, sizeof message,
                    "the point lies outside the tank (inner box x %g to %g, y %g to %g, z %g to %g m at rest); "
                    "points are in the tank frame",
                    low[0], high[0], low[1], high[1], low[2], high[2]);
      table.item_problem("points", k, message);
    }
  }
  return points;
}

/// The keys of a surge_front probe: a non-zero horizontal direction (normalised) and the height limit.
void read_surge_front(TableReader& table, const Model& model, ProbeModel& probe) {
  const std::size_t problems_before = table.problem_count();
  const Vec3 direction = table.vec3("direction", Vec3::UnitX(), "1", Bounds::any());
  if (table.problem_count() == problems_before) {
    if (direction.z() != 0.0)
      table.problem("direction", "expected a horizontal direction (z component 0): the front runs along the floor");
    else if (direction.norm() == 0.0)
      table.problem("direction", "expected a non-zero direction");
    else if ((model.tank.periodic[0] && direction.x() != 0.0) || (model.tank.periodic[1] && direction.y() != 0.0))
      // The front is the farthest water along the direction: across a seam the water wraps, so there is none.
      table.problem("direction", std::string("a surge front along a periodic axis (") +
                                     (model.tank.periodic[0] && direction.x() != 0.0 ? "x" : "y") +
                                     ") has no meaning: the water wraps across the seam, so it has no farthest "
                                     "point; give a direction along a walled axis or drop the probe");
    else
      probe.direction = direction.normalized();
  }
  probe.below = table.number("below", std::numeric_limits<double>::infinity(), "m", Bounds::positive());
}

/// True for the bed-load probes that measure grains (all but velocity_profile, which may run on water alone).
bool needs_grains(ProbeModel::Kind kind) {
  return kind == ProbeModel::Kind::kMovingFraction || kind == ProbeModel::Kind::kPackingDensity ||
         kind == ProbeModel::Kind::kBedloadFlux || kind == ProbeModel::Kind::kBedShearStress;
}

/// Most layers a velocity profile may have: each row holds one line per layer.
constexpr double kMaxProfileLayers = 100000.0;

/// The keys of the bed-load probes (systems/physics/measures/bedload_probes.hpp).
void read_bedload_probe(TableReader& table, const Model& model, ProbeModel& probe) {
  const bool grains = scene_sphere_count(model.solids) > 0 || !model.solids.initial_state.empty();
  if (needs_grains(probe.kind) && !grains)
    table.problem("kind", "this probe measures grains: the scene has none ([solids] with at least one grain)");
  switch (probe.kind) {
    case ProbeModel::Kind::kMovingFraction:
      probe.threshold = table.number("threshold", probe.threshold, "m/s", Bounds::positive());
      break;
    case ProbeModel::Kind::kPackingDensity: {
      probe.threshold = table.number("threshold", probe.threshold, "m/s", Bounds::positive());
      probe.layer_depth = table.number("layer_depth", probe.layer_depth, "m", Bounds::positive());
      if (table.has("layer_bottom")) {
        if (table.has("layer_depth"))
          table.problem("layer_bottom", "give either layer_depth (below the local bed top) or layer_bottom (a fixed "
                                        "height), not both");
        probe.layer_bottom = table.number("layer_bottom", std::nullopt, "m", Bounds::non_negative());
      }
      break;
    }
    case ProbeModel::Kind::kBedloadFlux:
      break;
    case ProbeModel::Kind::kVelocityProfile: {
      const std::optional<double> fallback =
          model.fluid.enabled && model.fluid.spacing > 0.0 ? std::optional<double>(model.fluid.spacing) : std::nullopt;
      const std::size_t problems_before = table.problem_count();
      probe.layer_thickness = table.number("layer_thickness", fallback, "m", Bounds::positive());
      if (table.problem_count() == problems_before && model.tank.size.z() > 0.0 &&
          model.tank.size.z() / probe.layer_thickness > kMaxProfileLayers)
        table.problem("layer_thickness", "more than 1e5 layers over the tank height; use a thicker layer");
      break;
    }
    case ProbeModel::Kind::kBedShearStress:
      if (!model.fluid.enabled) table.problem("kind", "the bed shear stress is the water's: the scene has no [fluid]");
      probe.lid = model_has_lid(model);
      break;
    default:
      break;
  }
}

/// The longest time window a transducer may average over: its steps' readings are held in memory.
constexpr double kMaxAverageWindow = 1.0;  // [s]

/// The surfaces a transducer may sit on: the tank's inner box (its closed faces; the normal out of the water points
/// out of the box) or one wall box (all six faces; the normal points into the box, and the reading plane is the
/// face of the box's particle cells, the surface the water meets, within l0/2 of the given one).
struct TransducerSurface {
  Vec3 low = Vec3::Zero(), high = Vec3::Zero();  ///< [m] the box as given, tank frame at rest
  std::array<bool, 6> closed{};                  ///< per face (kTankFaceNames order): a transducer may sit on it
  bool inward = false;                           ///< wall box: the normal points into the box
  Vec3 read_low = Vec3::Zero(), read_high = Vec3::Zero();  ///< [m] the planes the discs read on
  std::string what;                              ///< "the tank" or "wall box \"name\"", for messages
  std::string wall(std::size_t face) const {     ///< "the x_min wall" / "the x_min face of wall box \"b\""
    return inward ? "the " + kTankFaceNames[face] + " face of " + what : "the " + kTankFaceNames[face] + " wall";
  }
};

/// The keys of a pressure_transducer probe: `points` (disc centres, each on the inner face of a closed tank wall,
/// or with `wall_box` on a face of that named [[fluid.wall_boxes]] box), `face` (optional: the face every disc is
/// on; without it each point's own), `diameter` and `average_window`. A disc must lie within its face: a disc over
/// an edge would be on two faces at once.
void read_transducers(TableReader& table, const Model& model, ProbeModel& probe) {
  if (!model.fluid.tank_walls && !table.has("wall_box"))
    table.problem("kind", "pressure transducers sit on the tank's walls, and [fluid] tank_walls = false builds none "
                          "(name a wall box with `wall_box` to put them on its faces)");
  probe.diameter = table.number("diameter", std::nullopt, "m", Bounds::positive());
  probe.average_window =
      table.number("average_window", 0.0, "s", Bounds::closed(0.0, kMaxAverageWindow));
  TransducerSurface surface;
  bool surface_ok = model.tank.size.minCoeff() > 0.0;  // a bad tank is reported where [tank] is read
  if (table.has("wall_box")) {
    const std::string name = table.text("wall_box", std::nullopt);
    const auto& boxes = model.fluid.wall_boxes;
    const auto found = std::find_if(boxes.begin(), boxes.end(), [&](const ParticleBoxModel& box) {
      return !box.name.empty() && box.name == name;
    });
    if (found == boxes.end()) {
      std::string names;
      for (const ParticleBoxModel& box : boxes)
        if (!box.name.empty()) names += (names.empty() ? "\"" : ", \"") + box.name + "\"";
      table.problem("wall_box", "no [[fluid.wall_boxes]] entry is named \"" + name + "\" (" +
                                    (names.empty() ? std::string("none has a name: give it one with `name`")
                                                   : "named: " + names) +
                                    ")");
      surface_ok = false;
    } else if (model.fluid.spacing > 0.0) {
      surface.low = found->low;
      surface.high = found->high;
      surface.closed.fill(true);
      surface.inward = true;
      surface.what = "wall box \"" + name + "\"";
      const BoxGrid grid =
          box_grid(model.tank.origin, found->low, found->high, model.fluid.spacing, found->fit_extent);
      // The outermost particles' cells: first - l0/2 and first + (count - 1/2) l0.
      for (Eigen::Index axis = 0; axis < 3; ++axis) {
        const double count = static_cast<double>(grid.count[static_cast<std::size_t>(axis)]);
        surface.read_low[axis] = grid.first[axis] - 0.5 * model.fluid.spacing;
        surface.read_high[axis] = grid.first[axis] + (count - 0.5) * model.fluid.spacing;
      }
    } else {
      surface_ok = false;  // no spacing: reported at [fluid]
    }
  } else {
    surface.low = surface.read_low = model.tank.origin;
    surface.high = surface.read_high = model.tank.origin + model.tank.size;
    const auto& faces = model.tank.open_faces;
    for (std::size_t face = 0; face < 6; ++face)
      surface.closed[face] = std::find(faces.begin(), faces.end(), kTankFaceNames[face]) == faces.end();
    surface.what = "the tank";
  }
  std::optional<std::size_t> chosen;
  bool face_ok = true;  // a bad face is reported once; the points are still read (no "unknown key"), not judged
  if (table.has("face")) {
    const std::size_t problems_before = table.problem_count();
    const std::string name =
        table.choice("face", std::nullopt, std::vector<std::string>(kTankFaceNames.begin(), kTankFaceNames.end()));
    if (table.problem_count() == problems_before) {
      const auto found = std::find(kTankFaceNames.begin(), kTankFaceNames.end(), name);
      chosen = static_cast<std::size_t>(found - kTankFaceNames.begin());
      if (surface_ok && !surface.closed[*chosen]) {
        table.problem("face", "the " + name + " face is open: it has no wall to put a transducer on");
        face_ok = false;
      }
    } else {
      face_ok = false;
    }
  }
  const std::size_t problems_before = table.problem_count();
  const std::vector<Vec3> points = table.points("points", true, 3, "m");
  if (points.empty() && table.problem_count() == problems_before)
    table.problem("points", "expected at least one point");
  if (!face_ok || !surface_ok) return;
  const Vec3& low = surface.low;
  const Vec3& high = surface.high;
  const double slack = 1e-9 * model.tank.size.maxCoeff();
  const double radius = probe.diameter > 0.0 ? 0.5 * probe.diameter : 0.0;
  auto plane = [&](std::size_t face) { return face % 2 == 0 ? low[static_cast<Eigen::Index>(face / 2)]
                                                            : high[static_cast<Eigen::Index>(face / 2)]; };
  // The points a message names are in the tank frame; a wall box's faces are within the tank.
  const char* frame = surface.inward ? "as given, tank frame" : "at rest, tank frame";
  for (std::size_t k = 0; k < points.size(); ++k) {
    const Vec3& point = points[k];
    std::vector<std::size_t> on;  // the closed faces whose plane the point lies in (and, on a wall box, its face)
    for (std::size_t face = 0; face < 6; ++face) {
      const Eigen::Index axis = static_cast<Eigen::Index>(face / 2);
      bool within_face = true;
      if (surface.inward)
        for (Eigen::Index other = 0; other < 3; ++other)
          if (other != axis) within_face = within_face && point[other] >= low[other] - slack &&
                                           point[other] <= high[other] + slack;
      if (surface.closed[face] && within_face && std::abs(point[axis] - plane(face)) <= slack) on.push_back(face);
    }
    std::size_t face = 0;
    char message[400];
    if (chosen) {
      face = *chosen;
      if (std::abs(point[static_cast<Eigen::Index>(face / 2)] - plane(face)) > slack) {
        std::snprintf(message, sizeof message, "the point is not on the %s face%s%s (%c = %g m %s)",
                      kTankFaceNames[face].c_str(), surface.inward ? " of " : "",
                      surface.inward ? surface.what.c_str() : "", "xyz"[face / 2], plane(face), frame);
        table.item_problem("points", k, message);
        continue;
      }
    } else if (on.size() != 1) {
      if (on.empty() && surface.inward) {
        std::snprintf(message, sizeof message,
                      "the point lies on no face of %s: a disc's centre must lie on one of its faces (x = %g or %g, "
                      "y = %g or %g, z = %g or %g m, %s)",
                      surface.what.c_str(), low[0], high[0], low[1], high[1], low[2], high[2], frame);
      } else if (on.empty()) {
        std::snprintf(message, sizeof message,
                      "the point lies on no closed wall of the tank: a disc's centre must lie on a wall's inner face "
                      "(x = %g or %g, y = %g or %g, z = %g or %g m at rest, tank frame; open faces have none)",
                      low[0], high[0], low[1], high[1], low[2], high[2]);
      } else if (surface.inward) {
        std::snprintf(message, sizeof message,
                      "the point lies on the edge of the %s and %s faces of %s: name the face with `face`",
                      kTankFaceNames[on[0]].c_str(), kTankFaceNames[on[1]].c_str(), surface.what.c_str());
      } else {
        std::snprintf(message, sizeof message,
                      "the point lies on the edge of the %s and %s walls: name the wall with `face`",
                      kTankFaceNames[on[0]].c_str(), kTankFaceNames[on[1]].c_str());
      }
      table.item_problem("points", k, message);
      continue;
    } else {
      face = on.front();
    }
    // The disc (or, with a bad diameter, its centre) must lie within the face.
    bool within = true;
    for (Eigen::Index axis = 0; axis < 3; ++axis)
      if (axis != static_cast<Eigen::Index>(face / 2))
        within = within && point[axis] - radius >= low[axis] - slack && point[axis] + radius <= high[axis] + slack;
    if (!within) {
      const Eigen::Index a = face / 2 == 0 ? 1 : 0, b = face / 2 == 2 ? 1 : 2;
      std::snprintf(message, sizeof message,
                    "the disc (diameter %g m) reaches beyond %s (%c %g to %g m, %c %g to %g m %s)", probe.diameter,
                    surface.wall(face).c_str(), "xyz"[a], low[a], high[a], "xyz"[b], low[b], high[b], frame);
      table.item_problem("points", k, message);
      continue;
    }
    const Eigen::Index axis = static_cast<Eigen::Index>(face / 2);
    const double outward = face % 2 == 0 ? -1.0 : 1.0;  // out of the box through this face
    Vec3 normal = Vec3::Zero();
    normal[axis] = surface.inward ? -outward : outward;  // out of the water, into the wall
    Vec3 reading_point = point;
    reading_point[axis] = face % 2 == 0 ? surface.read_low[axis] : surface.read_high[axis];
    probe.points.push_back(reading_point);
    probe.normals.push_back(normal);
  }
}

}  // namespace

void read_probes(TableReader& output, Model& model) {
  std::vector<TableReader> tables = output.tables("probes");
  for (std::size_t index = 0; index < tables.size(); ++index) {
    TableReader& table = tables[index];
    ProbeModel probe;
    const std::size_t problems_before = table.problem_count();
    std::vector<std::string> kind_names;
    for (const auto& entry : probe_kinds()) kind_names.push_back(entry.first);
    const std::string kind = table.choice("kind", std::nullopt, kind_names);
    const bool kind_known = table.problem_count() == problems_before;
    for (const auto& [name, value] : probe_kinds())
      if (name == kind) probe.kind = value;
    probe.name = table.text("name", kind_known ? kind : "probe_" + std::to_string(index));
    const bool name_ok = plain_name(probe.name);
    if (!name_ok)
      table.problem("name", "expected a name of letters, digits, '_', '-' and '.', not starting with '.', got \"" +
                                probe.name + "\"");
    probe.file = table.text("file", "probe_" + probe.name + ".csv");
    if (!name_ok && !table.has("file")) {
      // The default file name comes from the bad name: already reported.
    } else if (!plain_name(probe.file)) {
      table.problem("file", "expected a plain file name (letters, digits, '_', '-', '.'; written in the output "
                            "directory), got \"" + probe.file + "\"");
    } else if (std::find(reserved_output_files().begin(), reserved_output_files().end(), probe.file) !=
               reserved_output_files().end()) {
      table.problem(table.has("file") ? "file" : "name", "\"" + probe.file + "\" is an output riffle writes itself");
    } else {
      for (const ProbeModel& other : model.output.probes)
        if (other.file == probe.file) {
          table.problem(table.has("file") ? "file" : "name",
                        "another probe (\"" + other.name + "\") already writes \"" + probe.file +
                            "\"; give each probe its own name or file");
          break;
        }
    }
    probe.interval = table.number("interval", probe.interval, "s", Bounds::non_negative());

    if (!kind_known) {
      // The kind decides which keys belong: with a bad kind the other keys cannot be judged, so none of them is
      // reported as unknown.
      model.output.probes.push_back(probe);
      continue;
    }
    if (is_fluid_probe(probe.kind) && !model.fluid.enabled)
      table.problem("kind", "\"" + kind + "\" probes need a [fluid] table: the scene has no fluid");
    switch (probe.kind) {
      case ProbeModel::Kind::kGrains: {
        const std::optional<std::uint64_t> limit = grain_id_limit(model);
        const std::size_t problems_before_ids = table.problem_count();
        const std::vector<std::int64_t> ids =
            table.integers("ids", true, 0, std::numeric_limits<std::int64_t>::max());
        if (ids.empty() && table.problem_count() == problems_before_ids)
          table.problem("ids", "expected at least one grain id");
        for (std::size_t k = 0; k < ids.size(); ++k) {
          const auto id = static_cast<EntityId>(ids[k]);
          if (limit && id >= *limit) {
            table.item_problem("ids", k,
                               "unknown grain id " + std::to_string(id) + ": the scene has " +
                                   std::to_string(*limit) + " grains" +
                                   (*limit ? " (ids 0 to " + std::to_string(*limit - 1) + ")" : ""));
          } else if (std::find(probe.ids.begin(), probe.ids.end(), id) != probe.ids.end()) {
            table.item_problem("ids", k, "grain id " + std::to_string(id) + " is listed twice");
          } else {
            probe.ids.push_back(id);
          }
        }
        break;
      }
      case ProbeModel::Kind::kWallForces:
        if (!model.contact.enabled)
          table.problem("kind", "wall forces need [contact]: without contacts no grain pushes on a wall");
        else if (wall_count(model) == 0)
          table.problem("kind", "the tank has no walls (every face is open)");
        break;
      case ProbeModel::Kind::kFluidPressure:
        probe.points = read_points(table, model, 3);
        break;
      case ProbeModel::Kind::kWaveGauge:
        probe.points = read_points(table, model, 2);
        probe.radius = table.number("radius", model.fluid.spacing, "m", Bounds::positive());
        break;
      case ProbeModel::Kind::kSurgeFront:
        read_surge_front(table, model, probe);
        break;
      case ProbeModel::Kind::kFluidTotals:
        break;
      case ProbeModel::Kind::kDrivenFlow:
        for (const ParticleBoxModel& box : model.fluid.wall_boxes)
          if (box.lid) probe.lid_areas.push_back(box.lid_area);
        break;
      case ProbeModel::Kind::kPressureTransducer:
        read_transducers(table, model, probe);
        break;
      case ProbeModel::Kind::kMovingFraction:
      case ProbeModel::Kind::kPackingDensity:
      case ProbeModel::Kind::kBedloadFlux:
      case ProbeModel::Kind::kVelocityProfile:
      case ProbeModel::Kind::kBedShearStress:
        read_bedload_probe(table, model, probe);
        break;
      case ProbeModel::Kind::kMeanFlowProfile:
        if (!model.mean_flow.enabled) table.problem("kind", "\"mean_flow_profile\" needs a [mean_flow] table");
        break;
      case ProbeModel::Kind::kBedloadTransport:
        if (!model.mean_flow.enabled)
          table.problem("kind", "\"bedload_transport\" measures over the mean-flow fluid: the scene has no [mean_flow]");
        if (!model.solids.enabled)
          table.problem("kind", "this probe measures grains: the scene has no [solids]");
        probe.threshold = table.number("threshold", probe.threshold, "m/s", Bounds::positive());
        break;
    }
    table.finish();
    model.output.probes.push_back(probe);
  }
}

void read_bed_profile_keys(TableReader& output, Model& model) {
  OutputModel& out = model.output;
  out.bed_profile_interval =
      output.number("bed_profile_interval", out.bed_profile_interval, "s", Bounds::non_negative());
  // 0 (the default) stands for the smallest grain diameter, resolved by bed_layer_thickness(model).
  out.bed_layer_thickness = output.number("bed_layer_thickness", out.bed_layer_thickness, "m", Bounds::positive());
  if (out.bed_profile_interval > 0.0 && scene_sphere_count(model.solids) == 0 && model.solids.initial_state.empty())
    output.problem("bed_profile_interval", "the bed profile needs grains ([solids] with at least one grain)");
  else if (out.bed_layer_thickness > 0.0 && model.tank.size.z() / out.bed_layer_thickness > kMaxBedLayers)
    output.problem("bed_layer_thickness", "more than 1e6 layers over the tank height; use a thicker layer");
}

}  // namespace riffle
