#include "engine/probes.hpp"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <optional>
#include <unordered_map>

#include "engine/initial_state.hpp"

namespace riffle {

namespace fs = std::filesystem;

const std::vector<std::string>& reserved_output_files() {
  static const std::vector<std::string> names = {"diagnostics.csv", "timings.csv",  "bed_profile.csv",
                                                 "class_centroids.csv", "riffle.log", "solids.pvd",
                                                 "walls.pvd",       "vtk",          "checkpoints"};
  return names;
}

namespace {

bool plain_name(const std::string& name) {
  if (name.empty() || name.front() == '.' || name.size() > 200) return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
           c == '.';
  });
}

/// One past the largest grain id the run starts with: the grains of [solids] initial_state (ids below its next_id)
/// and then the scene's own spheres, numbered on from there. nullopt if the initial state cannot be read (that is
/// reported where [solids] is read).
std::optional<std::uint64_t> grain_id_limit(const Model& model) {
  std::uint64_t limit = model.solids.spheres.size();
  if (!model.solids.initial_state.empty()) {
    try {
      limit += initial_grains(model).next_id;
    } catch (const std::exception&) {
      return std::nullopt;
    }
  }
  return limit;
}

/// Walls the tank has (the faces not listed as open), in the order tank_walls() creates them.
std::size_t wall_count(const Model& model) {
  return 6 - model.tank.open_faces.size();
}

}  // namespace

void read_probes(TableReader& output, Model& model) {
  std::vector<TableReader> tables = output.tables("probes");
  for (std::size_t index = 0; index < tables.size(); ++index) {
    TableReader& table = tables[index];
    ProbeModel probe;
    const std::size_t problems_before = table.problem_count();
    const std::string kind = table.choice("kind", std::nullopt, {"grains", "wall_forces"});
    const bool kind_known = table.problem_count() == problems_before;
    probe.kind = kind == "wall_forces" ? ProbeModel::Kind::kWallForces : ProbeModel::Kind::kGrains;
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
    probe.interval = table.number("interval", 0.0, "s", Bounds::non_negative());

    if (kind_known && probe.kind == ProbeModel::Kind::kGrains) {
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
                             "unknown grain id " + std::to_string(id) + ": the scene has " + std::to_string(*limit) +
                                 " grains" + (*limit ? " (ids 0 to " + std::to_string(*limit - 1) + ")" : ""));
        } else if (std::find(probe.ids.begin(), probe.ids.end(), id) != probe.ids.end()) {
          table.item_problem("ids", k, "grain id " + std::to_string(id) + " is listed twice");
        } else {
          probe.ids.push_back(id);
        }
      }
    } else if (!kind_known) {
      // The kind decides which keys belong; with a bad kind, "ids" is not also an unknown key.
      table.integers("ids", false, 0, std::numeric_limits<std::int64_t>::max());
    } else if (probe.kind == ProbeModel::Kind::kWallForces) {
      if (!model.contact.enabled)
        table.problem("kind", "wall forces need [contact]: without contacts no grain pushes on a wall");
      else if (wall_count(model) == 0)
        table.problem("kind", "the tank has no walls (every face is open)");
    }
    table.finish();
    model.output.probes.push_back(probe);
  }
}

GrainSlotMap::GrainSlotMap(std::vector<EntityId> ids) : ids_(std::move(ids)), slots_(ids_.size(), kNone) {}

bool GrainSlotMap::refresh(const Solids& solids) {
  bool current = true;
  for (std::size_t k = 0; k < ids_.size() && current; ++k)
    current = slots_[k] < solids.size() && solids.id[slots_[k]] == ids_[k];
  if (current) return false;
  std::unordered_map<EntityId, std::size_t> wanted;
  for (std::size_t k = 0; k < ids_.size(); ++k) wanted.emplace(ids_[k], k);
  std::fill(slots_.begin(), slots_.end(), kNone);
  for (std::size_t slot = 0; slot < solids.size(); ++slot)
    if (const auto found = wanted.find(solids.id[slot]); found != wanted.end()) slots_[found->second] = slot;
  return true;
}

std::vector<Vec3> wall_reaction_forces(const Contacts& contacts, std::size_t wall_count) {
  if (!contacts.valid || contacts.wall_pair_force.size() != contacts.wall_pair_wall.size()) return {};
  std::vector<Vec3> forces(wall_count, Vec3::Zero());
  for (std::size_t k = 0; k < contacts.wall_pair_wall.size(); ++k)
    if (contacts.wall_pair_wall[k] < wall_count) forces[contacts.wall_pair_wall[k]] -= contacts.wall_pair_force[k];
  return forces;
}

std::string probe_header(const ProbeModel& probe, const World& world) {
  std::string header = "time_s,step";
  if (probe.kind == ProbeModel::Kind::kGrains) {
    static const char* const kColumns[] = {"x_m",      "y_m",      "z_m",      "vx_m_s", "vy_m_s", "vz_m_s",
                                           "wx_rad_s", "wy_rad_s", "wz_rad_s", "fx_N",   "fy_N",   "fz_N"};
    for (EntityId id : probe.ids)
      for (const char* column : kColumns) header += ",grain" + std::to_string(id) + "_" + column;
  } else if (world.walls) {
    for (const std::string& name : world.walls->name)
      for (const char* column : {"fx_N", "fy_N", "fz_N"}) header += "," + name + "_" + column;
  }
  return header;
}

ProbeWriter::ProbeWriter(const ProbeModel& probe, const fs::path& out_dir, const World& world, double dt,
                         bool fresh_run)
    : probe_(probe),
      slots_(probe.ids),
      schedule_(probe.interval, dt, world.time),
      file_(out_dir / probe.file, probe_header(probe, world),
            fresh_run ? std::nullopt : std::optional<double>(world.time)) {}

void ProbeWriter::write(const World& world) {
  std::string row = format_exact(world.time);
  append_field(row, std::to_string(world.step));
  auto append = [&row](const Vec3& value) {
    for (int axis = 0; axis < 3; ++axis) append_field(row, format_value(value[axis]));
  };
  auto append_empty = [&row](int fields) {
    for (int k = 0; k < fields; ++k) row += ",";
  };
  if (probe_.kind == ProbeModel::Kind::kGrains) {
    const Solids* solids = world.solids ? &*world.solids : nullptr;
    if (solids) slots_.refresh(*solids);
    for (std::size_t k = 0; k < probe_.ids.size(); ++k) {
      const std::size_t slot = solids ? slots_.slot(k) : GrainSlotMap::kNone;
      if (slot == GrainSlotMap::kNone) {
        append_empty(12);  // the grain is gone (or never was): empty fields, not made-up numbers
        continue;
      }
      append(solids->position[slot]);
      append(solids->velocity[slot]);
      append(solids->angular_velocity[slot]);
      append(solids->contact_force[slot]);
    }
  } else {
    const std::size_t walls = world.walls ? world.walls->size() : 0;
    const std::vector<Vec3> forces =
        world.contacts ? wall_reaction_forces(*world.contacts, walls) : std::vector<Vec3>{};
    // Before the first step the contact list does not exist yet: the forces are unknown, not zero.
    for (std::size_t wall = 0; wall < walls; ++wall)
      if (forces.empty())
        append_empty(3);
      else
        append(forces[wall]);
  }
  file_.write_row(row);
}

}  // namespace riffle
